// SPDX-License-Identifier: GPL-3.0-or-later
// What the counted vector properties (vtkSICountedDoubleVectorProperty, vtkSICountedIntVectorProperty) share: the
// reading of their XML attributes and the push that checks the count. `Property` is the counted class, `Superclass`
// ParaView's vector property it extends; the counted class befriends nothing: it passes what the push needs.
#ifndef PlantMorphCountedPush_h
#define PlantMorphCountedPush_h

#include "vtkClientServerStream.h"
#include "vtkPVXMLElement.h"

#include <functional>
#include <sstream>
#include <string>

namespace plantmorph
{
namespace servermanager
{
/// The element-count command (empty without one) and the fixed count (number_of_elements of a property that is not
/// repeated; -1 for a repeated one) of a property's XML element.
inline void ReadCountAttributes(vtkPVXMLElement* element, std::string& countCommand, int& fixedCount)
{
  const char* command = element->GetAttribute("element_count_command");
  countCommand = command ? command : "";
  int repeat = 0;
  int elements = -1;
  element->GetScalarAttribute("repeat_command", &repeat);
  element->GetScalarAttribute("number_of_elements", &elements);
  fixedCount = repeat ? -1 : elements;
}

/// The push of a counted property given `count` values. A fixed-size property given another count (a state file
/// edited or written by a script) would make ParaView call the set method with the wrong number of arguments, which
/// the interpreter reports as "could not find requested method ... Aborting execution" and which stops the rest of
/// the proxy's state (its Input among it): the pipeline loses its connections. Those values are not pushed; the
/// object hears the count (and refuses to run, naming the property) or, without a count command, `report` says the
/// error. Otherwise the usual push (`push`: clean command, the rows), then the raw count, so the object can compare
/// it with the rows it received. `invoke` runs a stream on the server.
inline bool CountedPush(const char* name, int count, int fixedCount, bool informationOnly,
  const std::string& countCommand, vtkObjectBase* object, const std::function<bool()>& push,
  const std::function<bool(vtkClientServerStream&)>& invoke,
  const std::function<void(const std::string&)>& report)
{
  const bool wrongCount = fixedCount > 0 && count != fixedCount && !informationOnly;
  if (wrongCount && countCommand.empty())
  {
    std::ostringstream message;
    message << name << ": " << count << " numbers, " << fixedCount
            << " expected: the value is not set (the previous one is kept)";
    report(message.str());
    return true;
  }
  if (!wrongCount)
  {
    const bool pushed = push();
    if (!pushed || countCommand.empty() || informationOnly)
    {
      return pushed;
    }
  }
  vtkClientServerStream stream;
  stream << vtkClientServerStream::Invoke << object << countCommand.c_str() << count << vtkClientServerStream::End;
  return invoke(stream);
}
} // namespace servermanager
} // namespace plantmorph

#endif
