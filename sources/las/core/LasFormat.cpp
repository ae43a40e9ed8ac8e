// SPDX-License-Identifier: GPL-3.0-or-later
#include "LasBytes.h"
#include "LasFile.h"

#include <cmath>

namespace plantmorph
{

const char* const kLasStandardNames[15] = { "Intensity", "ReturnNumber", "NumberOfReturns", "ScanDirectionFlag",
  "EdgeOfFlightLine", "Classification", "ClassificationFlags", "ScannerChannel", "ScanAngleRank", "ScanAngle",
  "UserData", "PointSourceId", "GpsTime", "RGB", "NIR" };

const char* const kLasInPlaceOf = "in place of the LAS attribute";

std::size_t LasTypeSize(LasType type)
{
  switch (type)
  {
    case LasType::UInt8:
    case LasType::Int8:
      return 1;
    case LasType::UInt16:
    case LasType::Int16:
      return 2;
    case LasType::UInt32:
    case LasType::Int32:
    case LasType::Float:
      return 4;
    default:
      return 8;
  }
}

std::uint16_t LasPointRecordLength(int format)
{
  static const std::uint16_t lengths[11] = { 20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67 };
  return format >= 0 && format <= 10 ? lengths[format] : 0;
}

const LasField* LasCloud::Find(const std::string& name) const
{
  for (const LasField& field : this->fields)
  {
    if (field.name == name)
    {
      return &field;
    }
  }
  return nullptr;
}

namespace las
{

double GetValue(const unsigned char* p, LasType type)
{
  switch (type)
  {
    case LasType::UInt8:
    case LasType::UInt16:
    case LasType::UInt32:
    case LasType::UInt64:
      return static_cast<double>(GetUnsigned(p, static_cast<int>(LasTypeSize(type))));
    case LasType::Int8:
    case LasType::Int16:
    case LasType::Int32:
    case LasType::Int64:
      return static_cast<double>(GetSigned(p, static_cast<int>(LasTypeSize(type))));
    case LasType::Float:
      return GetFloat(p);
    default:
      return GetDouble(p);
  }
}

bool Fits(LasType type, double value)
{
  if (type == LasType::Float || type == LasType::Double)
  {
    return true;
  }
  if (!std::isfinite(value) || std::floor(value) != value)
  {
    return false;
  }
  const int bits = 8 * static_cast<int>(LasTypeSize(type));
  const bool isSigned =
    type == LasType::Int8 || type == LasType::Int16 || type == LasType::Int32 || type == LasType::Int64;
  const double lo = isSigned ? -std::ldexp(1.0, bits - 1) : 0.0;
  const double hi = isSigned ? std::ldexp(1.0, bits - 1) : std::ldexp(1.0, bits); // exclusive
  return value >= lo && value < hi;
}

void PutValue(unsigned char* p, LasType type, double value)
{
  switch (type)
  {
    case LasType::UInt8:
    case LasType::UInt16:
    case LasType::UInt32:
    case LasType::UInt64:
      PutUnsigned(p, static_cast<std::uint64_t>(value), static_cast<int>(LasTypeSize(type)));
      break;
    case LasType::Int8:
    case LasType::Int16:
    case LasType::Int32:
    case LasType::Int64:
      PutSigned(p, static_cast<std::int64_t>(value), static_cast<int>(LasTypeSize(type)));
      break;
    case LasType::Float:
      PutFloat(p, static_cast<float>(value));
      break;
    default:
      PutDouble(p, value);
  }
}

const StandardSlot* StandardSlots(int format, int& count)
{
  using T = LasType;
  // Formats 0-5 (LAS 1.4 R15 tables 7-12): the 20 bytes of format 0, then GPS time and/or RGB.
  static const StandardSlot legacy[12] = { { "Intensity", T::UInt16, 1, 12, 0, 0 },
    { "ReturnNumber", T::UInt8, 1, 14, 0, 3 }, { "NumberOfReturns", T::UInt8, 1, 14, 3, 3 },
    { "ScanDirectionFlag", T::UInt8, 1, 14, 6, 1 }, { "EdgeOfFlightLine", T::UInt8, 1, 14, 7, 1 },
    { "Classification", T::UInt8, 1, 15, 0, 5 }, { "ClassificationFlags", T::UInt8, 1, 15, 5, 3 },
    { "ScanAngleRank", T::Int8, 1, 16, 0, 0 }, { "UserData", T::UInt8, 1, 17, 0, 0 },
    { "PointSourceId", T::UInt16, 1, 18, 0, 0 }, { "GpsTime", T::Double, 1, 20, 0, 0 },
    { "RGB", T::UInt16, 3, 20, 0, 0 } };
  static const StandardSlot legacyRgbAfterTime[12] = { legacy[0], legacy[1], legacy[2], legacy[3], legacy[4], legacy[5],
    legacy[6], legacy[7], legacy[8], legacy[9], legacy[10], { "RGB", T::UInt16, 3, 28, 0, 0 } };
  static const StandardSlot legacyRgb[11] = { legacy[0], legacy[1], legacy[2], legacy[3], legacy[4], legacy[5],
    legacy[6], legacy[7], legacy[8], legacy[9], legacy[11] };
  // Formats 6-10 (tables 13-17): the 30 bytes of format 6, then RGB and NIR.
  static const StandardSlot modern[14] = { { "Intensity", T::UInt16, 1, 12, 0, 0 },
    { "ReturnNumber", T::UInt8, 1, 14, 0, 4 }, { "NumberOfReturns", T::UInt8, 1, 14, 4, 4 },
    { "ClassificationFlags", T::UInt8, 1, 15, 0, 4 }, { "ScannerChannel", T::UInt8, 1, 15, 4, 2 },
    { "ScanDirectionFlag", T::UInt8, 1, 15, 6, 1 }, { "EdgeOfFlightLine", T::UInt8, 1, 15, 7, 1 },
    { "Classification", T::UInt8, 1, 16, 0, 0 }, { "UserData", T::UInt8, 1, 17, 0, 0 },
    { "ScanAngle", T::Int16, 1, 18, 0, 0 }, { "PointSourceId", T::UInt16, 1, 20, 0, 0 },
    { "GpsTime", T::Double, 1, 22, 0, 0 }, { "RGB", T::UInt16, 3, 30, 0, 0 }, { "NIR", T::UInt16, 1, 36, 0, 0 } };
  switch (format)
  {
    case 0:
      count = 10;
      return legacy;
    case 1:
    case 4:
      count = 11;
      return legacy;
    case 2:
      count = 11;
      return legacyRgb;
    case 3:
    case 5:
      count = 12;
      return legacyRgbAfterTime;
    case 6:
    case 9:
      count = 12;
      return modern;
    case 7:
      count = 13;
      return modern;
    case 8:
    case 10:
      count = 14;
      return modern;
    default:
      count = 0;
      return nullptr;
  }
}

} // namespace las
} // namespace plantmorph
