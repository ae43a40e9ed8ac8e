// SPDX-License-Identifier: GPL-3.0-or-later
// The one phrasing of a bad-parameter message, shared by every method's validators and wrappers:
//   "<Property> = <value> is outside the accepted range <range>[ (<note>)]"
// `range` is written as the user reads it: "[3, 256]", "(0, 1e6]", "{3, 5}". Plain C++, no VTK.
#pragma once

#include <sstream>
#include <string>

namespace plantmorph
{

/// The message for `property` = `value` outside `range`, with an optional explanatory `note` in parentheses.
template <class T>
std::string OutOfRange(
  const std::string& property, const T& value, const std::string& range, const std::string& note = std::string())
{
  std::ostringstream message;
  message << property << " = " << value << " is outside the accepted range " << range;
  if (!note.empty())
    message << " (" << note << ")";
  return message.str();
}

/// Empty when `ok`, else OutOfRange(property, value, range, note): validators chain these.
template <class T>
std::string CheckRange(bool ok, const std::string& property, const T& value, const std::string& range,
  const std::string& note = std::string())
{
  return ok ? std::string() : OutOfRange(property, value, range, note);
}

} // namespace plantmorph
