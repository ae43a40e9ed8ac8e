// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSICountedDoubleVectorProperty.h"

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
  const char* command = element->GetAttribute("element_count_command");
  this->ElementCountCommand = command ? command : "";
  return true;
}

//------------------------------------------------------------------------------
bool vtkSICountedDoubleVectorProperty::Push(vtkSMMessage* message, int offset)
{
  // The rows first (ParaView's own push: clean command, one command per whole row), then the raw count, so the
  // object can compare the count with the rows it received.
  const bool pushed = this->Superclass::Push(message, offset);
  if (!pushed || this->ElementCountCommand.empty() || this->GetInformationOnly())
  {
    return pushed;
  }
  const int count = message->GetExtension(ProxyState::property, offset).value().float64_size();
  vtkClientServerStream stream;
  stream << vtkClientServerStream::Invoke << this->GetVTKObject() << this->ElementCountCommand.c_str() << count
         << vtkClientServerStream::End;
  return this->ProcessMessage(stream);
}

//------------------------------------------------------------------------------
void vtkSICountedDoubleVectorProperty::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ElementCountCommand: " << this->ElementCountCommand << "\n";
}
