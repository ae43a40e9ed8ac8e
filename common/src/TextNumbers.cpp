// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/TextNumbers.h>

#include <algorithm>
#include <charconv>
#include <system_error>

namespace plantmorph
{

namespace
{
bool IsDigit(char c)
{
  return c >= '0' && c <= '9';
}

/// For a number std::from_chars found out of range: true if it overflows, false if it underflows. [begin, end) is
/// the mantissa (digits with at most one point), `exponent` the (saturated) value after its e.
bool Overflows(const char* begin, const char* end, long long exponent)
{
  const char* point = std::find(begin, end, '.');
  for (const char* p = begin; p < end; ++p)
  {
    if (*p == '.' || *p == '0')
    {
      continue;
    }
    // The value is 0.d... * 10^(position + exponent), d the first non-zero digit.
    const long long position = p < point ? static_cast<long long>(point - p) : -static_cast<long long>(p - point - 1);
    return position + exponent > 0;
  }
  return false;
}
} // namespace

NumberStatus ScanNumber(const char* p, const char* end, const char*& next, double& value)
{
  next = p;
  const char* q = p;
  bool negative = false;
  if (q < end && (*q == '+' || *q == '-'))
  {
    negative = *q == '-';
    ++q;
  }
  const char* mantissa = q;
  std::size_t digits = 0;
  while (q < end && IsDigit(*q) && static_cast<std::size_t>(q - p) <= kMaxNumberLength)
  {
    ++q;
    ++digits;
  }
  if (q < end && *q == '.')
  {
    ++q;
    while (q < end && IsDigit(*q) && static_cast<std::size_t>(q - p) <= kMaxNumberLength)
    {
      ++q;
      ++digits;
    }
  }
  if (digits == 0)
  {
    return NumberStatus::NotANumber;
  }
  const char* mantissaEnd = q;
  long long exponent = 0;
  if (q + 1 < end && (*q == 'e' || *q == 'E'))
  {
    const char* e = q + 1;
    bool negativeExponent = false;
    if (*e == '+' || *e == '-')
    {
      negativeExponent = *e == '-';
      ++e;
    }
    if (e < end && IsDigit(*e))
    {
      while (e < end && IsDigit(*e) && static_cast<std::size_t>(e - p) <= kMaxNumberLength)
      {
        exponent = exponent < 100000000 ? exponent * 10 + (*e - '0') : exponent;
        ++e;
      }
      exponent = negativeExponent ? -exponent : exponent;
      q = e;
    }
  }
  if (static_cast<std::size_t>(q - p) > kMaxNumberLength)
  {
    // Skip the rest of the run so that the caller's error names the whole token, then refuse it.
    while (q < end && (IsDigit(*q) || *q == '.' || *q == 'e' || *q == 'E' || *q == '+' || *q == '-'))
    {
      ++q;
    }
    next = q;
    return NumberStatus::TooLong;
  }
  double v = 0.0;
  const auto result = std::from_chars(mantissa, q, v, std::chars_format::general);
  next = q;
  if (result.ec == std::errc::result_out_of_range)
  {
    if (Overflows(mantissa, mantissaEnd, exponent))
    {
      return NumberStatus::NotFinite;
    }
    v = 0.0;
  }
  else if (result.ec != std::errc() || result.ptr != q)
  {
    next = p;
    return NumberStatus::NotANumber;
  }
  value = negative ? -v : v;
  return NumberStatus::Ok;
}

std::string DescribeNumberStatus(NumberStatus status)
{
  switch (status)
  {
    case NumberStatus::Ok:
      return "a number";
    case NumberStatus::NotANumber:
      return "not a number";
    case NumberStatus::TooLong:
      return "a number of more than " + std::to_string(kMaxNumberLength) + " characters";
    case NumberStatus::NotFinite:
      return "a number beyond the range of a double (about +-1.8e308)";
  }
  return "not a number";
}

std::string Excerpt(const char* begin, const char* end, std::size_t limit)
{
  std::string text;
  for (const char* p = begin; p < end && text.size() < limit; ++p)
  {
    const auto c = static_cast<unsigned char>(*p);
    text += c >= 32 && c < 127 ? static_cast<char>(c) : '?';
  }
  if (static_cast<std::size_t>(end - begin) > limit)
  {
    text += "...";
  }
  return text;
}

} // namespace plantmorph
