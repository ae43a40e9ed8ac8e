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
  int repeat = 0;
  int elements = -1;
  element->GetScalarAttribute("repeat_command", &repeat);
  element->GetScalarAttribute("number_of_elements", &elements);
  this->FixedCount = repeat ? -1 : elements;
  return true;
}

//------------------------------------------------------------------------------
bool vtkSICountedDoubleVectorProperty::Push(vtkSMMessage* message, int offset)
{
  const int count = message->GetExtension(ProxyState::property, offset).value().float64_size();
  if (this->FixedCount > 0 && count != this->FixedCount && !this->GetInformationOnly())
  {
    // A fixed-size property given another count (a state file edited or written by a script): ParaView's push
    // would call the set method with the wrong number of arguments, which the interpreter reports as "could not
    // find requested method ... Aborting execution" and which stops the rest of the proxy's state (its Input
    // among it): the pipeline loses its connections. The values are not pushed; the object hears the count (and
    // refuses to run, naming the property) or, without a count command, the error is said here.
    if (this->ElementCountCommand.empty())
    {
      vtkErrorMacro(<< this->GetXMLName() << ": " << count << " numbers, " << this->FixedCount
                    << " expected: the value is not set (the previous one is kept)");
      return true;
    }
    vtkClientServerStream stream;
    stream << vtkClientServerStream::Invoke << this->GetVTKObject() << this->ElementCountCommand.c_str() << count
           << vtkClientServerStream::End;
    return this->ProcessMessage(stream);
  }
  // The rows first (ParaView's own push: clean command, one command per whole row), then the raw count, so the
  // object can compare the count with the rows it received.
  const bool pushed = this->Superclass::Push(message, offset);
  if (!pushed || this->ElementCountCommand.empty() || this->GetInformationOnly())
  {
    return pushed;
  }
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
  os << indent << "FixedCount: " << this->FixedCount << "\n";
}
