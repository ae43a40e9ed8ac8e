// SPDX-License-Identifier: GPL-3.0-or-later
#include "FormatText.h"

#include <plantmorph/TextNumbers.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>

namespace plantmorph
{

LineReader::LineReader(std::istream& in, std::size_t maxLength)
  : In(in)
  , MaxLength(maxLength)
  , Block(std::size_t(1) << 16)
{
}

bool LineReader::Next(std::string& line)
{
  line.clear();
  if (!this->Failure.empty())
  {
    return false;
  }
  bool any = false;
  for (;;)
  {
    if (this->Position == this->Filled)
    {
      if (this->Ended)
      {
        break;
      }
      this->In.read(this->Block.data(), static_cast<std::streamsize>(this->Block.size()));
      this->Filled = static_cast<std::size_t>(this->In.gcount());
      this->Position = 0;
      if (this->Filled == 0)
      {
        this->Ended = true;
        break;
      }
    }
    any = true;
    const char* begin = this->Block.data() + this->Position;
    const std::size_t available = this->Filled - this->Position;
    const auto* newline = static_cast<const char*>(std::memchr(begin, '\n', available));
    const std::size_t take = newline ? static_cast<std::size_t>(newline - begin) : available;
    if (line.size() + take > this->MaxLength)
    {
      this->Failure =
        "line " + std::to_string(this->Count + 1) + ": longer than " + std::to_string(this->MaxLength) + " characters";
      return false;
    }
    line.append(begin, take);
    this->Position += take + (newline ? 1 : 0);
    if (newline)
    {
      break;
    }
  }
  if (!any)
  {
    return false;
  }
  ++this->Count;
  if (!line.empty() && line.back() == '\r')
  {
    line.pop_back();
  }
  if (line.find('\0') != std::string::npos)
  {
    this->Failure = "line " + std::to_string(this->Count) + ": holds a NUL byte (a binary file?)";
    return false;
  }
  return true;
}

std::vector<std::string> SplitAt(const std::string& line, char separator)
{
  std::vector<std::string> fields;
  std::size_t from = 0;
  for (;;)
  {
    const std::size_t at = line.find(separator, from);
    fields.push_back(line.substr(from, at == std::string::npos ? std::string::npos : at - from));
    if (at == std::string::npos)
    {
      return fields;
    }
    from = at + 1;
  }
}

std::string Trim(const std::string& text)
{
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  std::size_t begin = 0, end = text.size();
  while (begin < end && blank(text[begin]))
  {
    ++begin;
  }
  while (end > begin && blank(text[end - 1]))
  {
    --end;
  }
  return text.substr(begin, end - begin);
}

std::string NormalName(const std::string& name)
{
  std::string out;
  for (const char c : name.substr(0, name.find('(')))
  {
    if (c == ' ' || c == '\t' || c == '_' || c == '-' || c == '.' || c == '"' || c == '\'' || c == '\r')
    {
      continue;
    }
    out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return out;
}

bool ParseWholeNumber(const std::string& field, double& value)
{
  const char* begin = field.data();
  const char* end = begin + field.size();
  const char* next = begin;
  return !field.empty() && ScanNumber(begin, end, next, value) == NumberStatus::Ok && next == end;
}

std::string ExactNumber(double value)
{
  char text[64];
  const auto written = std::to_chars(text, text + sizeof(text), value); // shortest exact form, no locale
  return std::string(text, written.ptr);
}

} // namespace plantmorph
