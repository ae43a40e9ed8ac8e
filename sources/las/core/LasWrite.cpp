// SPDX-License-Identifier: GPL-3.0-or-later
#include "LasBytes.h"
#include "LasFile.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ctime>
#include <limits>
#include <set>

namespace plantmorph
{
namespace
{
using las::PutDouble;
using las::PutText;
using las::PutUnsigned;

/// A field written into a standard slot or as one extra-bytes dimension (component `component` of `field`).
struct Placement
{
  const LasField* field = nullptr;
  int component = 0;
  const las::StandardSlot* slot = nullptr; ///< null: an extra-bytes dimension
  std::size_t offset = 0;                  ///< the extra dimension's byte in the record
  LasType type = LasType::Double;          ///< the extra dimension's type
  std::string name;                        ///< the extra dimension's name
  bool inPlaceOf = false;                  ///< the extra dimension has the name of a standard attribute of the format
};

/// Whether `field` fits `slot`: its components, integer values within the slot's bits or type.
bool FitsSlot(const LasField& field, const las::StandardSlot& slot, std::size_t n)
{
  if (field.components != slot.components || field.values.size() != n * static_cast<std::size_t>(slot.components))
  {
    return false;
  }
  const double top = slot.bits > 0 ? static_cast<double>((1 << slot.bits) - 1) : 0.0;
  return std::all_of(field.values.begin(), field.values.end(),
    [&](double v) { return slot.bits > 0 ? (std::floor(v) == v && v >= 0 && v <= top) : las::Fits(slot.type, v); });
}

const las::StandardSlot* SlotNamed(int format, const std::string& name)
{
  int count = 0;
  const las::StandardSlot* slots = las::StandardSlots(format, count);
  for (int s = 0; s < count; ++s)
  {
    if (name == slots[s].name)
    {
      return &slots[s];
    }
  }
  return nullptr;
}

/// The smallest format of the version holding the cloud's GpsTime, RGB and NIR (when they fit).
int AutoFormat(const LasCloud& cloud, int versionMinor)
{
  const std::size_t n = cloud.Size();
  const auto fits = [&](const char* name, int format) {
    const LasField* field = cloud.Find(name);
    const las::StandardSlot* slot = SlotNamed(format, name);
    return field && slot && FitsSlot(*field, *slot, n);
  };
  if (versionMinor >= 4)
  {
    return fits("NIR", 8) ? 8 : fits("RGB", 7) ? 7 : 6;
  }
  return (fits("GpsTime", 1) ? 1 : 0) + (fits("RGB", 2) ? 2 : 0);
}

/// The extra dimension names of a field's components.
std::string ComponentName(const LasField& field, int c)
{
  std::string name = field.name;
  if (field.components == 3)
  {
    name += std::string("_") + static_cast<char>('X' + c);
  }
  else if (field.components > 1)
  {
    name += "_" + std::to_string(c);
  }
  return name.substr(0, 32);
}

std::string Place(const LasCloud& cloud, int format, std::vector<Placement>& placements, std::size_t& recordLength)
{
  const std::size_t n = cloud.Size();
  recordLength = LasPointRecordLength(format);
  std::set<const las::StandardSlot*> used;
  for (const LasField& field : cloud.fields)
  {
    if (field.components < 1 || field.values.size() != n * static_cast<std::size_t>(field.components))
    {
      return "field '" + field.name + "' has " + std::to_string(field.values.size()) + " values for " +
        std::to_string(n) + " points of " + std::to_string(field.components) + " components";
    }
    const las::StandardSlot* slot = SlotNamed(format, field.name);
    // A second field of the same name (a cloud's arrays need not be unique) goes to the extra bytes.
    if (slot && used.count(slot) == 0 && FitsSlot(field, *slot, n))
    {
      used.insert(slot);
      Placement p;
      p.field = &field;
      p.slot = slot;
      placements.push_back(p);
      continue;
    }
    for (int c = 0; c < field.components; ++c)
    {
      Placement p;
      p.field = &field;
      p.component = c;
      p.offset = recordLength;
      p.type = field.scaled ||
          std::all_of(field.values.begin(), field.values.end(), [&](double v) { return las::Fits(field.type, v); })
        ? field.type
        : LasType::Double;
      p.name = ComponentName(field, c);
      p.inPlaceOf = slot != nullptr && field.components == 1 && used.count(slot) == 0;
      recordLength += LasTypeSize(p.type);
      placements.push_back(p);
    }
    if (slot && field.components == 1)
    {
      used.insert(slot); // written in place of the standard attribute, which stays zero
    }
  }
  if (recordLength > 65535)
  {
    return "the attributes need " + std::to_string(recordLength) + " bytes per point, more than a LAS record's 65535";
  }
  return "";
}

/// The Extra Bytes VLR (header and descriptors) for the extra placements.
std::vector<unsigned char> ExtraBytesRecord(const std::vector<Placement>& placements)
{
  std::vector<unsigned char> record(kLasVlrHeaderSize, 0);
  PutText(record.data() + 2, "LASF_Spec", 16);
  PutUnsigned(record.data() + 18, 4, 2);
  PutText(record.data() + 22, "Extra Bytes", 32);
  for (const Placement& p : placements)
  {
    if (p.slot)
    {
      continue;
    }
    unsigned char d[kLasExtraBytesDescriptorSize] = {};
    d[2] = static_cast<unsigned char>(p.type);
    const bool scaled = p.field->scaled && p.type == p.field->type;
    d[3] = scaled ? 0x18 : 0;
    PutText(d + 4, p.name, 32);
    if (scaled)
    {
      PutDouble(d + 112, p.field->scale[static_cast<std::size_t>(p.component)]);
      PutDouble(d + 136, p.field->offset[static_cast<std::size_t>(p.component)]);
    }
    PutText(d + 160, p.inPlaceOf ? std::string(kLasInPlaceOf) : p.field->description, 32);
    record.insert(record.end(), d, d + kLasExtraBytesDescriptorSize);
  }
  PutUnsigned(record.data() + 20, record.size() - kLasVlrHeaderSize, 2);
  return record;
}

/// The scale and offset of the three axes, and the quantised extent; "" or why the coordinates cannot be written.
std::string ChooseScale(const LasCloud& cloud, const LasWriteOptions& options, LasWriteReport& report,
  std::array<double, 3>& lo, std::array<double, 3>& hi)
{
  const std::size_t n = cloud.Size();
  lo.fill(n ? std::numeric_limits<double>::infinity() : 0.0);
  hi.fill(n ? -std::numeric_limits<double>::infinity() : 0.0);
  for (std::size_t i = 0; i < 3 * n; ++i)
  {
    const double v = cloud.xyz[i];
    if (!std::isfinite(v))
    {
      return "point " + std::to_string(i / 3) + " has a coordinate that is not finite";
    }
    lo[i % 3] = std::min(lo[i % 3], v);
    hi[i % 3] = std::max(hi[i % 3], v);
  }
  const double limit = 2147483647.0;
  const auto fits = [&](double scale, double offset, int k) {
    return scale > 0 && std::isfinite(offset) && std::fabs(std::round((lo[k] - offset) / scale)) <= limit &&
      std::fabs(std::round((hi[k] - offset) / scale)) <= limit;
  };
  bool keep = options.scale == 0;
  for (int k = 0; k < 3; ++k)
  {
    keep = keep && fits(cloud.header.scale[k], cloud.header.offset[k], k);
  }
  for (int k = 0; k < 3; ++k)
  {
    if (keep)
    {
      report.scale[k] = cloud.header.scale[k];
      report.offset[k] = cloud.header.offset[k];
      continue;
    }
    LasAutoScale(lo[k], hi[k], report.scale[k], report.offset[k]);
    if (options.scale > 0)
    {
      report.scale[k] = options.scale;
      report.offset[k] = std::round(0.5 * (lo[k] + hi[k]) / options.scale) * options.scale + 0.0;
    }
    if (!fits(report.scale[k], report.offset[k], k))
    {
      return "coordinates from " + std::to_string(lo[k]) + " to " + std::to_string(hi[k]) +
        " do not fit the 32-bit integers of LAS at scale " + std::to_string(report.scale[k]) +
        (options.scale > 0 ? " (the Scale asked for)" : "");
    }
  }
  return "";
}

void EncodeRecord(unsigned char* p, std::size_t i, const LasCloud& cloud, const std::vector<Placement>& placements,
  const LasWriteReport& report)
{
  for (int k = 0; k < 3; ++k)
  {
    const double q = std::round((cloud.xyz[3 * i + static_cast<std::size_t>(k)] - report.offset[k]) / report.scale[k]);
    las::PutSigned(p + 4 * k, static_cast<std::int64_t>(q), 4);
  }
  for (const Placement& place : placements)
  {
    const LasField& field = *place.field;
    const std::size_t components = static_cast<std::size_t>(field.components);
    if (place.slot)
    {
      const las::StandardSlot& slot = *place.slot;
      if (slot.bits > 0)
      {
        p[slot.offset] = static_cast<unsigned char>(
          p[slot.offset] | (static_cast<unsigned>(field.values[i]) << static_cast<unsigned>(slot.shift)));
        continue;
      }
      for (std::size_t c = 0; c < components; ++c)
      {
        las::PutValue(p + slot.offset + c * LasTypeSize(slot.type), slot.type, field.values[i * components + c]);
      }
      continue;
    }
    double v = field.values[i * components + static_cast<std::size_t>(place.component)];
    if (field.scaled && place.type == field.type)
    {
      const auto c = static_cast<std::size_t>(place.component);
      v = std::round((v - field.offset[c]) / field.scale[c]);
      v = las::Fits(place.type, v) ? v : 0.0;
    }
    las::PutValue(p + place.offset, place.type, v);
  }
}

} // namespace

std::string ValidateLasWriteOptions(const LasWriteOptions& options)
{
  if (options.versionMinor != 2 && options.versionMinor != 4)
  {
    return "Version = 1." + std::to_string(options.versionMinor) + ": LAS 1.2 or 1.4 is written";
  }
  const bool legacy = options.pointFormat >= 0 && options.pointFormat <= 3;
  const bool modern = options.pointFormat >= 6 && options.pointFormat <= 8;
  if (options.pointFormat != -1 && !legacy && !(modern && options.versionMinor == 4))
  {
    return "PointFormat = " + std::to_string(options.pointFormat) + ": LAS 1." + std::to_string(options.versionMinor) +
      " is written with point format " + (options.versionMinor == 4 ? "0-3 or 6-8" : "0-3") +
      " (or -1: chosen from the attributes)";
  }
  if (!(options.scale >= 0) || !std::isfinite(options.scale))
  {
    return "Scale = " + std::to_string(options.scale) + ": must be 0 (chosen) or a positive number";
  }
  return "";
}

void LasAutoScale(double lo, double hi, double& scale, double& offset)
{
  static const double powers[] = { 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3, 1e4, 1e5,
    1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12 };
  const double middle = 0.5 * lo + 0.5 * hi;
  for (double candidate : powers)
  {
    offset = std::round(middle / candidate) * candidate + 0.0; // + 0.0: never -0
    const double reach = std::max(std::fabs(hi - offset), std::fabs(lo - offset)) / candidate;
    scale = candidate;
    if (reach < 2.0e9)
    {
      return;
    }
  }
}

std::string WriteLas(std::ostream& out, const LasCloud& cloud, const LasWriteOptions& options, LasWriteReport* report)
{
  LasWriteReport own;
  LasWriteReport& r = report ? *report : own;
  r = LasWriteReport();
  std::string error = ValidateLasWriteOptions(options);
  if (!error.empty())
  {
    return error;
  }
  const std::size_t n = cloud.Size();
  const bool v14 = options.versionMinor == 4;
  if (!v14 && n > 0xFFFFFFFFull)
  {
    return "LAS 1.2 holds at most 4294967295 points, the cloud has " + std::to_string(n) + ": write LAS 1.4";
  }
  const int format = options.pointFormat >= 0 ? options.pointFormat : AutoFormat(cloud, options.versionMinor);
  r.pointFormat = format;
  std::vector<Placement> placements;
  std::size_t recordLength = 0;
  error = Place(cloud, format, placements, recordLength);
  std::array<double, 3> lo, hi;
  if (error.empty())
  {
    error = ChooseScale(cloud, options, r, lo, hi);
  }
  if (!error.empty())
  {
    return error;
  }
  const bool extras = recordLength > LasPointRecordLength(format);
  const std::vector<unsigned char> vlr = extras ? ExtraBytesRecord(placements) : std::vector<unsigned char>();
  const std::size_t headerSize = v14 ? kLasHeaderSize14 : kLasHeaderSize12;
  unsigned char h[kLasHeaderSize14] = {};
  std::memcpy(h, "LASF", 4);
  PutUnsigned(h + 4, cloud.header.fileSourceId, 2);
  PutUnsigned(h + 6, (cloud.header.globalEncoding & 1u) | (v14 && format >= 6 ? 16u : 0u), 2);
  h[24] = 1;
  h[25] = static_cast<unsigned char>(options.versionMinor);
  PutText(h + 26, cloud.header.systemIdentifier.empty() ? "OTHER" : cloud.header.systemIdentifier, 32);
  PutText(h + 58, options.generatingSoftware, 32);
  std::uint16_t day = cloud.header.creationDay, year = cloud.header.creationYear;
  if (year == 0)
  {
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    day = static_cast<std::uint16_t>(utc.tm_yday + 1);
    year = static_cast<std::uint16_t>(utc.tm_year + 1900);
  }
  PutUnsigned(h + 90, day, 2);
  PutUnsigned(h + 92, year, 2);
  PutUnsigned(h + 94, headerSize, 2);
  PutUnsigned(h + 96, headerSize + vlr.size(), 4);
  PutUnsigned(h + 100, extras ? 1 : 0, 4);
  h[104] = static_cast<unsigned char>(format);
  PutUnsigned(h + 105, recordLength, 2);
  std::uint64_t byReturn[15] = {};
  const LasField* returns = cloud.Find("ReturnNumber");
  const bool returnsWritten =
    std::any_of(placements.begin(), placements.end(), [&](const Placement& p) { return p.slot && p.field == returns; });
  for (std::size_t i = 0; returnsWritten && i < n; ++i)
  {
    const auto number = static_cast<int>(returns->values[i]);
    if (number >= 1 && number <= 15)
    {
      ++byReturn[number - 1];
    }
  }
  const bool legacyCounts = format <= 5 && n <= 0xFFFFFFFFull;
  PutUnsigned(h + 107, legacyCounts ? n : 0, 4);
  for (int k = 0; k < 5; ++k)
  {
    PutUnsigned(h + 111 + 4 * k, legacyCounts ? byReturn[k] : 0, 4);
  }
  for (int k = 0; k < 3; ++k)
  {
    const auto quantised = [&](double v) {
      return r.offset[k] + r.scale[k] * std::round((v - r.offset[k]) / r.scale[k]) + 0.0;
    };
    PutDouble(h + 131 + 8 * k, r.scale[k]);
    PutDouble(h + 155 + 8 * k, r.offset[k]);
    PutDouble(h + 179 + 16 * k, quantised(hi[k]));
    PutDouble(h + 187 + 16 * k, quantised(lo[k]));
  }
  if (v14)
  {
    PutUnsigned(h + 247, n, 8);
    for (int k = 0; k < 15; ++k)
    {
      PutUnsigned(h + 255 + 8 * k, byReturn[k], 8);
    }
  }
  out.write(reinterpret_cast<const char*>(h), static_cast<std::streamsize>(headerSize));
  out.write(reinterpret_cast<const char*>(vlr.data()), static_cast<std::streamsize>(vlr.size()));
  const std::size_t perBlock = std::max<std::size_t>(1, kLasBlockBytes / recordLength);
  std::vector<unsigned char> block;
  for (std::size_t done = 0; done < n && out;)
  {
    const std::size_t count = std::min(perBlock, n - done);
    block.assign(count * recordLength, 0);
    for (std::size_t i = 0; i < count; ++i)
    {
      EncodeRecord(block.data() + i * recordLength, done + i, cloud, placements, r);
    }
    out.write(reinterpret_cast<const char*>(block.data()), static_cast<std::streamsize>(block.size()));
    done += count;
  }
  for (const Placement& p : placements)
  {
    (p.slot ? r.standard : r.extra).push_back(p.slot ? p.field->name : p.name);
  }
  out.flush();
  return out ? "" : "writing failed (is the disk full?)";
}

} // namespace plantmorph
