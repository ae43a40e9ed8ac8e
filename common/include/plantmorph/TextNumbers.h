// SPDX-License-Identifier: GPL-3.0-or-later
// Bounded, locale-independent scanning of decimal numbers for the plugin's text parsers (stroke files, point-cloud
// text). Plain C++17, no VTK.
//
// A number is [+-] (digits [. digits] | . digits) [(e|E) [+-] digits], at most kMaxNumberLength characters (a longer
// run of number characters is refused, so a 10^7-digit token costs one linear scan and gives a clear error). The
// value is the correctly rounded double (std::from_chars, the same value strtod gives in the C locale); a value
// beyond the double range is refused as not finite, one below the smallest subnormal becomes +-0. "inf", "nan" and
// hexadecimal are not numbers here.
#pragma once

#include <cstddef>
#include <string>

namespace plantmorph
{

/// The longest number token accepted, in characters (a double printed with 17 significant digits needs 24; this
/// leaves room for fixed-point output of large or tiny values).
constexpr std::size_t kMaxNumberLength = 512;

enum class NumberStatus
{
  Ok,
  NotANumber, ///< no number starts at the position (next is left there)
  TooLong,    ///< more than kMaxNumberLength characters (next is past the whole run of number characters)
  NotFinite,  ///< its magnitude overflows a double
};

/// Scans one number starting exactly at p (no leading white space skipped), never reading at or past end. On Ok,
/// value holds it and next points past it; otherwise see NumberStatus.
NumberStatus ScanNumber(const char* p, const char* end, const char*& next, double& value);

/// A short description of a failed status for error messages, e.g. "a number of more than 512 characters".
std::string DescribeNumberStatus(NumberStatus status);

/// Shows at most `limit` characters of [begin, end) in an error message, with control and non-ASCII bytes as '?'
/// and "..." when cut.
std::string Excerpt(const char* begin, const char* end, std::size_t limit = 40);

} // namespace plantmorph
