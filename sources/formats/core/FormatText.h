// SPDX-License-Identifier: GPL-3.0-or-later
// What the MTG and QSM parsers share: a bounded line reader (one pass over the stream in 64 KiB blocks, at most one
// line held) and the small text functions (fields split at a separator, trimming, name normalisation, numbers written
// so that they read back bit for bit). Plain C++17, no VTK.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

namespace plantmorph
{

/// Reads a stream line by line ('\n' ends a line, a '\r' before it is dropped), refusing a line longer than
/// `maxLength` characters or holding a NUL byte. Linear in the stream; holds one block and one line.
class LineReader
{
public:
  LineReader(std::istream& in, std::size_t maxLength);
  /// The next line into `line` (without its end); false at the end of the stream or on an error (Error() then
  /// says "line N: ...").
  bool Next(std::string& line);
  /// The number of the line last returned (1 for the first).
  std::size_t Number() const { return this->Count; }
  const std::string& Error() const { return this->Failure; }

private:
  std::istream& In;
  std::size_t MaxLength;
  std::vector<char> Block;
  std::size_t Position = 0;
  std::size_t Filled = 0;
  std::size_t Count = 0;
  bool Ended = false;
  std::string Failure;
};

/// The fields of `line` split at every `separator` (empty fields kept: "a\t\tb" has three).
std::vector<std::string> SplitAt(const std::string& line, char separator);
/// `text` without leading and trailing blanks (spaces, tabs, '\r').
std::string Trim(const std::string& text);
/// Lower case, with everything from the first '(' on dropped (units: "radius (m)") and without blanks, '_', '-',
/// '.' and quotes: "start_X", "startX" and "Start X" all give "startx".
std::string NormalName(const std::string& name);
/// A whole field as a finite decimal number (plantmorph/TextNumbers.h); false if it is anything else.
bool ParseWholeNumber(const std::string& field, double& value);
/// `value` in the shortest decimal form that reads back as the same double (std::to_chars: no locale).
std::string ExactNumber(double value);

} // namespace plantmorph
