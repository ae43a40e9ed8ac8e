// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSICountedDoubleVectorProperty.h"

#include "CountedPush.h"
#include "vtkClientServerStream.h"
#include "vtkObjectFactory.h"
#include "vtkPVXMLElement.h"
#include "vtkSMMessage.h"

vtkStandardNewMacro(vtkSICountedDoubleVectorProperty);

//------------------------------------------------------------------------------
vtkSICountedDoubleVectorProperty::vtkSICountedDoubleVectorProperty() = default;

//------------------------------------------------------------------------------
vtkSICountedDoubleVectorProperty::~vtkSICountedDoubleVectorProperty() = default;

//------------------------------------------------------------------------------
bool vtkSICountedDoubleVectorProperty::ReadXMLAttributes(vtkSIProxy* proxyhelper, vtkPVXMLElement* element)
{
  if (!this->Superclass::ReadXMLAttributes(proxyhelper, element))
  {
    return false;
  }
  plantmorph::servermanager::ReadCountAttributes(element, this->ElementCountCommand, this->FixedCount);
  return true;
}

//------------------------------------------------------------------------------
bool vtkSICountedDoubleVectorProperty::Push(vtkSMMessage* message, int offset)
{
  const int count = message->GetExtension(ProxyState::property, offset).value().float64_size();
  return plantmorph::servermanager::CountedPush(
    this->GetXMLName(), count, this->FixedCount, this->GetInformationOnly(), this->ElementCountCommand,
    this->GetVTKObject(), [&]() { return this->Superclass::Push(message, offset); },
    [this](vtkClientServerStream& stream) { return this->ProcessMessage(stream); },
    [this](const std::string& error) { vtkErrorMacro(<< error); });
}

//------------------------------------------------------------------------------
void vtkSICountedDoubleVectorProperty::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ElementCountCommand: " << this->ElementCountCommand << "\n";
  os << indent << "FixedCount: " << this->FixedCount << "\n";
}
