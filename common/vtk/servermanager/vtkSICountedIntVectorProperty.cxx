// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSICountedIntVectorProperty.h"

#include "CountedPush.h"
#include "vtkClientServerStream.h"
#include "vtkObjectFactory.h"
#include "vtkPVXMLElement.h"
#include "vtkSMMessage.h"

vtkStandardNewMacro(vtkSICountedIntVectorProperty);

//------------------------------------------------------------------------------
vtkSICountedIntVectorProperty::vtkSICountedIntVectorProperty() = default;

//------------------------------------------------------------------------------
vtkSICountedIntVectorProperty::~vtkSICountedIntVectorProperty() = default;

//------------------------------------------------------------------------------
bool vtkSICountedIntVectorProperty::ReadXMLAttributes(vtkSIProxy* proxyhelper, vtkPVXMLElement* element)
{
  if (!this->Superclass::ReadXMLAttributes(proxyhelper, element))
  {
    return false;
  }
  plantmorph::servermanager::ReadCountAttributes(element, this->ElementCountCommand, this->FixedCount);
  return true;
}

//------------------------------------------------------------------------------
bool vtkSICountedIntVectorProperty::Push(vtkSMMessage* message, int offset)
{
  const int count = message->GetExtension(ProxyState::property, offset).value().integer_size();
  return plantmorph::servermanager::CountedPush(
    this->GetXMLName(), count, this->FixedCount, this->GetInformationOnly(), this->ElementCountCommand,
    this->GetVTKObject(), [&]() { return this->Superclass::Push(message, offset); },
    [this](vtkClientServerStream& stream) { return this->ProcessMessage(stream); },
    [this](const std::string& error) { vtkErrorMacro(<< error); });
}

//------------------------------------------------------------------------------
void vtkSICountedIntVectorProperty::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ElementCountCommand: " << this->ElementCountCommand << "\n";
  os << indent << "FixedCount: " << this->FixedCount << "\n";
}
