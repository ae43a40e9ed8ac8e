// SPDX-License-Identifier: GPL-3.0-or-later
// Little-endian bytes of the LAS format (LasRead.cpp, LasWrite.cpp): values read from and written into byte buffers
// whatever the machine's byte order, and the layout of the point formats.
#pragma once

#include "LasFile.h"

#include <cstdint>
#include <cstring>
#include <string>

namespace plantmorph
{
namespace las
{

inline std::uint64_t GetUnsigned(const unsigned char* p, int bytes)
{
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i)
  {
    v = (v << 8) | p[i];
  }
  return v;
}

inline std::int64_t GetSigned(const unsigned char* p, int bytes)
{
  const std::uint64_t u = GetUnsigned(p, bytes);
  if (bytes == 8)
  {
    std::int64_t s;
    std::memcpy(&s, &u, 8);
    return s;
  }
  const std::uint64_t sign = std::uint64_t(1) << (8 * bytes - 1);
  return static_cast<std::int64_t>(u ^ sign) - static_cast<std::int64_t>(sign);
}

inline double GetDouble(const unsigned char* p)
{
  const std::uint64_t bits = GetUnsigned(p, 8);
  double d;
  std::memcpy(&d, &bits, 8);
  return d;
}

inline float GetFloat(const unsigned char* p)
{
  const auto bits = static_cast<std::uint32_t>(GetUnsigned(p, 4));
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

inline void PutUnsigned(unsigned char* p, std::uint64_t v, int bytes)
{
  for (int i = 0; i < bytes; ++i)
  {
    p[i] = static_cast<unsigned char>(v >> (8 * i));
  }
}

inline void PutSigned(unsigned char* p, std::int64_t v, int bytes)
{
  std::uint64_t u;
  std::memcpy(&u, &v, 8);
  PutUnsigned(p, u, bytes);
}

inline void PutDouble(unsigned char* p, double d)
{
  std::uint64_t bits;
  std::memcpy(&bits, &d, 8);
  PutUnsigned(p, bits, 8);
}

inline void PutFloat(unsigned char* p, float f)
{
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  PutUnsigned(p, bits, 4);
}

/// A fixed-size text field (NUL-padded) as a string, cut at the first NUL.
inline std::string GetText(const unsigned char* p, std::size_t size)
{
  std::size_t n = 0;
  while (n < size && p[n] != 0)
  {
    ++n;
  }
  return std::string(reinterpret_cast<const char*>(p), n);
}

inline void PutText(unsigned char* p, const std::string& text, std::size_t size)
{
  std::memset(p, 0, size);
  std::memcpy(p, text.data(), text.size() < size ? text.size() : size);
}

/// One value of `type` at `p`, as a double.
double GetValue(const unsigned char* p, LasType type);
/// Writes `value` (already checked to fit) as `type` at `p`.
void PutValue(unsigned char* p, LasType type, double value);
/// Whether `value` is storable as `type` exactly (an integer in range for the integer types; finite or not for the
/// floating types).
bool Fits(LasType type, double value);

/// Where a standard attribute lies in a point record of a format.
struct StandardSlot
{
  const char* name;
  LasType type;
  int components;
  int offset; ///< byte in the record
  int shift;  ///< for bit fields: the first bit (else 0)
  int bits;   ///< for bit fields: the number of bits (else 0: the whole value)
};

/// The standard attributes of point format `format` (0-10) and their places; `count` gets their number.
const StandardSlot* StandardSlots(int format, int& count);

} // namespace las
} // namespace plantmorph
