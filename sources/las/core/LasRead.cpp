// SPDX-License-Identifier: GPL-3.0-or-later
#include "LasBytes.h"
#include "LasFile.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <set>
#include <sstream>

namespace plantmorph
{
namespace
{
using las::GetDouble;
using las::GetSigned;
using las::GetText;
using las::GetUnsigned;

/// The header as the file says it (before any check).
struct RawHeader
{
  std::string signature;
  int versionMajor = 0, versionMinor = 0;
  std::uint16_t headerSize = 0;
  std::uint32_t offsetToPoints = 0;
  std::uint32_t vlrCount = 0;
  int formatByte = 0;
  std::uint16_t recordLength = 0;
  std::uint32_t legacyCount = 0;
  std::uint64_t count = 0; ///< the 64-bit count of LAS 1.4 (0 before)
  std::uint64_t evlrStart = 0;
  std::uint32_t evlrCount = 0;
  double scale[3] = { 0, 0, 0 }, offset[3] = { 0, 0, 0 };
  LasHeaderInfo info;
};

std::string Quote(const std::string& text)
{
  std::string shown;
  for (unsigned char c : text)
  {
    if (c >= 32 && c < 127)
    {
      shown += static_cast<char>(c);
    }
    else
    {
      static const char* hex = "0123456789abcdef";
      shown += std::string("\\x") + hex[c >> 4] + hex[c & 15];
    }
  }
  return "'" + shown + "'";
}

std::string HeaderField(const std::string& field, const std::string& value)
{
  return "header field '" + field + "' = " + value;
}

bool ReadAt(std::istream& in, std::uint64_t at, unsigned char* bytes, std::size_t size)
{
  in.clear();
  in.seekg(static_cast<std::streamoff>(at));
  in.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(size));
  return static_cast<std::size_t>(in.gcount()) == size;
}

RawHeader DecodeHeader(const unsigned char* h, std::size_t available)
{
  RawHeader r;
  r.signature = std::string(reinterpret_cast<const char*>(h), 4);
  r.info.fileSourceId = static_cast<std::uint16_t>(GetUnsigned(h + 4, 2));
  r.info.globalEncoding = static_cast<std::uint16_t>(GetUnsigned(h + 6, 2));
  r.versionMajor = h[24];
  r.versionMinor = h[25];
  r.info.systemIdentifier = GetText(h + 26, 32);
  r.info.generatingSoftware = GetText(h + 58, 32);
  r.info.creationDay = static_cast<std::uint16_t>(GetUnsigned(h + 90, 2));
  r.info.creationYear = static_cast<std::uint16_t>(GetUnsigned(h + 92, 2));
  r.headerSize = static_cast<std::uint16_t>(GetUnsigned(h + 94, 2));
  r.offsetToPoints = static_cast<std::uint32_t>(GetUnsigned(h + 96, 4));
  r.vlrCount = static_cast<std::uint32_t>(GetUnsigned(h + 100, 4));
  r.formatByte = h[104];
  r.recordLength = static_cast<std::uint16_t>(GetUnsigned(h + 105, 2));
  r.legacyCount = static_cast<std::uint32_t>(GetUnsigned(h + 107, 4));
  for (int k = 0; k < 3; ++k)
  {
    r.scale[k] = GetDouble(h + 131 + 8 * k);
    r.offset[k] = GetDouble(h + 155 + 8 * k);
  }
  if (r.versionMinor >= 4 && available >= kLasHeaderSize14)
  {
    r.evlrStart = GetUnsigned(h + 235, 8);
    r.evlrCount = static_cast<std::uint32_t>(GetUnsigned(h + 243, 4));
    r.count = GetUnsigned(h + 247, 8);
  }
  return r;
}

/// Checks the header's fields against each other and the file's size; sets `points` (the number of records).
std::string CheckHeader(const RawHeader& r, std::uint64_t fileSize, std::uint64_t& points)
{
  if (r.signature != "LASF")
  {
    return HeaderField("File Signature", Quote(r.signature)) + ": not a LAS file (the signature is 'LASF')";
  }
  if (r.versionMajor != 1 || r.versionMinor > 4)
  {
    return HeaderField("Version", std::to_string(r.versionMajor) + "." + std::to_string(r.versionMinor)) +
      ": LAS 1.0 to 1.4 are read";
  }
  const std::uint16_t least = r.versionMinor >= 4 ? kLasHeaderSize14
    : r.versionMinor == 3                         ? kLasHeaderSize13
                                                  : kLasHeaderSize12;
  if (r.headerSize < least)
  {
    return HeaderField("Header Size", std::to_string(r.headerSize)) + ": LAS 1." + std::to_string(r.versionMinor) +
      " needs at least " + std::to_string(least);
  }
  if (r.headerSize > fileSize)
  {
    return HeaderField("Header Size", std::to_string(r.headerSize)) + " is more than the file's " +
      std::to_string(fileSize) + " bytes";
  }
  if (r.offsetToPoints < r.headerSize || r.offsetToPoints > fileSize)
  {
    return HeaderField("Offset to Point Data", std::to_string(r.offsetToPoints)) + ": not between the header's " +
      std::to_string(r.headerSize) + " bytes and the file's " + std::to_string(fileSize);
  }
  if (r.formatByte & 0xC0)
  {
    return HeaderField("Point Data Record Format", std::to_string(r.formatByte)) +
      ": its compression bits are set, so this is a LAZ (LASzip-compressed) file. Only uncompressed LAS is read: "
      "decompress it first (laszip -i file.laz -o file.las, or pdal translate file.laz file.las)";
  }
  if (r.formatByte > 10)
  {
    return HeaderField("Point Data Record Format", std::to_string(r.formatByte)) + ": LAS point formats are 0 to 10";
  }
  if (r.recordLength < LasPointRecordLength(r.formatByte))
  {
    return HeaderField("Point Data Record Length", std::to_string(r.recordLength)) + ": point format " +
      std::to_string(r.formatByte) + " needs at least " + std::to_string(LasPointRecordLength(r.formatByte)) + " bytes";
  }
  const char* axes[3] = { "X", "Y", "Z" };
  for (int k = 0; k < 3; ++k)
  {
    if (!std::isfinite(r.scale[k]) || r.scale[k] == 0)
    {
      std::ostringstream value;
      value << r.scale[k];
      return HeaderField(std::string(axes[k]) + " scale factor", value.str()) + ": must be finite and not zero";
    }
    if (!std::isfinite(r.offset[k]))
    {
      return HeaderField(std::string(axes[k]) + " offset", "not a finite number");
    }
  }
  points = r.legacyCount;
  const char* countField = "Legacy Number of Point Records";
  if (r.versionMinor >= 4 && r.count != 0)
  {
    if (r.legacyCount != 0 && r.legacyCount != r.count)
    {
      return HeaderField("Legacy Number of Point Records", std::to_string(r.legacyCount)) +
        " disagrees with 'Number of Point Records' = " + std::to_string(r.count);
    }
    points = r.count;
    countField = "Number of Point Records";
  }
  const std::uint64_t room = fileSize - r.offsetToPoints;
  if (points > room / r.recordLength)
  {
    return HeaderField(countField, std::to_string(points)) + ": that many records of " +
      std::to_string(r.recordLength) + " bytes from byte " + std::to_string(r.offsetToPoints) +
      " need more than the file's " + std::to_string(fileSize) + " bytes";
  }
  return "";
}

/// One described extra-bytes dimension and where it lies in the record.
struct ExtraSlot
{
  LasType type = LasType::UInt8;
  int components = 1;
  std::size_t offset = 0; ///< byte in the record
  std::size_t field = 0;  ///< index in LasCloud::fields
  bool keep = true;       ///< false: undocumented bytes, skipped
};

/// Parses an Extra Bytes record's descriptors into `cloud`'s fields and `slots`.
std::string ParseExtraBytes(const std::vector<unsigned char>& body, const std::string& where, std::size_t recordBase,
  std::size_t recordLength, LasCloud& cloud, std::vector<ExtraSlot>& slots)
{
  if (body.size() % kLasExtraBytesDescriptorSize != 0)
  {
    return where + " (Extra Bytes): its length " + std::to_string(body.size()) + " is not a multiple of " +
      std::to_string(kLasExtraBytesDescriptorSize);
  }
  slots.clear();
  std::size_t at = recordBase;
  for (std::size_t j = 0; j < body.size() / kLasExtraBytesDescriptorSize; ++j)
  {
    const unsigned char* d = body.data() + j * kLasExtraBytesDescriptorSize;
    const int type = d[2], options = d[3];
    const std::string name = GetText(d + 4, 32);
    const std::string label = where + " (Extra Bytes) descriptor " + std::to_string(j) + " " + Quote(name);
    if (type > 30)
    {
      return label + ": data type " + std::to_string(type) + " is not one of 0-30";
    }
    ExtraSlot slot;
    slot.offset = at;
    std::size_t bytes = static_cast<std::size_t>(options); // type 0: 'options' holds the number of bytes
    if (type == 0)
    {
      slot.keep = false;
    }
    else
    {
      slot.type = static_cast<LasType>((type - 1) % 10 + 1);
      slot.components = (type - 1) / 10 + 1;
      bytes = LasTypeSize(slot.type) * static_cast<std::size_t>(slot.components);
    }
    at += bytes;
    if (at > recordLength)
    {
      return label + ": the extra bytes reach byte " + std::to_string(at) + " of a record, beyond the header's " +
        "'Point Data Record Length' = " + std::to_string(recordLength);
    }
    if (!slot.keep)
    {
      slots.push_back(slot);
      continue;
    }
    LasField field;
    field.name = name.empty() ? "Extra" + std::to_string(j) : name;
    field.type = slot.type;
    field.components = slot.components;
    field.extra = true;
    field.scaled = (options & 0x18) != 0;
    field.description = GetText(d + 160, 32);
    for (int k = 0; k < 3; ++k)
    {
      field.scale[k] = (options & 0x08) ? GetDouble(d + 112 + 8 * k) : 1.0;
      field.offset[k] = (options & 0x10) ? GetDouble(d + 136 + 8 * k) : 0.0;
    }
    slot.field = cloud.fields.size();
    slots.push_back(slot);
    cloud.fields.push_back(std::move(field));
  }
  return "";
}

bool IsExtraBytesRecord(const unsigned char* h)
{
  return GetText(h + 2, 16) == "LASF_Spec" && GetUnsigned(h + 18, 2) == 4;
}

/// Walks the VLRs (between the header and the point data) and the EVLRs (after the points); parses the Extra Bytes
/// record (the last one found) into `cloud` and `slots`.
std::string ReadRecords(std::istream& in, const RawHeader& r, std::uint64_t fileSize, std::uint64_t pointEnd,
  LasCloud& cloud, std::vector<ExtraSlot>& slots)
{
  std::vector<unsigned char> extraBody;
  std::string extraWhere;
  std::uint64_t at = r.headerSize;
  if (r.vlrCount > (r.offsetToPoints - r.headerSize) / kLasVlrHeaderSize)
  {
    return HeaderField("Number of Variable Length Records", std::to_string(r.vlrCount)) + ": that many " +
      std::to_string(kLasVlrHeaderSize) + "-byte VLR headers do not fit in the " +
      std::to_string(r.offsetToPoints - r.headerSize) + " bytes between the header and 'Offset to Point Data'";
  }
  unsigned char h[kLasEvlrHeaderSize];
  for (std::uint32_t v = 0; v < r.vlrCount; ++v)
  {
    const std::string where = "VLR " + std::to_string(v);
    if (at + kLasVlrHeaderSize > r.offsetToPoints || !ReadAt(in, at, h, kLasVlrHeaderSize))
    {
      return where + ": its header runs past 'Offset to Point Data' = " + std::to_string(r.offsetToPoints);
    }
    const std::uint64_t length = GetUnsigned(h + 20, 2);
    const std::uint64_t body = at + kLasVlrHeaderSize;
    if (body + length > r.offsetToPoints)
    {
      return where + " (user " + Quote(GetText(h + 2, 16)) + ", record " + std::to_string(GetUnsigned(h + 18, 2)) +
        "): its 'Record Length After Header' = " + std::to_string(length) +
        " runs past 'Offset to Point Data' = " + std::to_string(r.offsetToPoints);
    }
    if (IsExtraBytesRecord(h))
    {
      extraBody.resize(length);
      if (!ReadAt(in, body, extraBody.data(), length))
      {
        return where + ": cannot be read";
      }
      extraWhere = where;
    }
    at = body + length;
  }
  if (r.versionMinor >= 4 && r.evlrCount > 0)
  {
    if (r.evlrStart < pointEnd || r.evlrStart > fileSize)
    {
      return HeaderField("Start of First Extended Variable Length Record", std::to_string(r.evlrStart)) +
        ": not between the end of the point records (" + std::to_string(pointEnd) + ") and the file's end (" +
        std::to_string(fileSize) + ")";
    }
    if (r.evlrCount > (fileSize - r.evlrStart) / kLasEvlrHeaderSize)
    {
      return HeaderField("Number of Extended Variable Length Records", std::to_string(r.evlrCount)) +
        ": that many 60-byte EVLR headers do not fit in the file after byte " + std::to_string(r.evlrStart);
    }
    at = r.evlrStart;
    for (std::uint32_t v = 0; v < r.evlrCount; ++v)
    {
      const std::string where = "EVLR " + std::to_string(v);
      if (at > fileSize - kLasEvlrHeaderSize || !ReadAt(in, at, h, kLasEvlrHeaderSize))
      {
        return where + ": its header runs past the end of the file";
      }
      const std::uint64_t length = GetUnsigned(h + 20, 8);
      const std::uint64_t body = at + kLasEvlrHeaderSize;
      if (length > fileSize - body)
      {
        return where + " (user " + Quote(GetText(h + 2, 16)) + ", record " + std::to_string(GetUnsigned(h + 18, 2)) +
          "): its 'Record Length After Header' = " + std::to_string(length) + " runs past the end of the file";
      }
      if (IsExtraBytesRecord(h))
      {
        extraBody.resize(length);
        if (!ReadAt(in, body, extraBody.data(), length))
        {
          return where + ": cannot be read";
        }
        extraWhere = where;
      }
      at = body + length;
    }
  }
  return extraWhere.empty()
    ? ""
    : ParseExtraBytes(extraBody, extraWhere, LasPointRecordLength(r.formatByte), r.recordLength, cloud, slots);
}

/// Decodes `count` records of `block` into the cloud's arrays (standard fields first, in `standard`'s order).
void DecodeRecords(const unsigned char* block, std::size_t count, const RawHeader& r, const las::StandardSlot* standard,
  int standardCount, const std::vector<ExtraSlot>& slots, LasCloud& cloud)
{
  for (std::size_t i = 0; i < count; ++i)
  {
    const unsigned char* p = block + i * r.recordLength;
    for (int k = 0; k < 3; ++k)
    {
      cloud.xyz.push_back(r.offset[k] + r.scale[k] * static_cast<double>(GetSigned(p + 4 * k, 4)));
    }
    for (int s = 0; s < standardCount; ++s)
    {
      const las::StandardSlot& slot = standard[s];
      std::vector<double>& values = cloud.fields[static_cast<std::size_t>(s)].values;
      if (slot.bits > 0)
      {
        values.push_back(static_cast<double>((p[slot.offset] >> slot.shift) & ((1 << slot.bits) - 1)));
        continue;
      }
      const std::size_t size = LasTypeSize(slot.type);
      for (int c = 0; c < slot.components; ++c)
      {
        values.push_back(las::GetValue(p + slot.offset + size * static_cast<std::size_t>(c), slot.type));
      }
    }
    for (const ExtraSlot& slot : slots)
    {
      if (!slot.keep)
      {
        continue;
      }
      LasField& field = cloud.fields[slot.field];
      const std::size_t size = LasTypeSize(slot.type);
      for (int c = 0; c < slot.components; ++c)
      {
        const double raw = las::GetValue(p + slot.offset + size * static_cast<std::size_t>(c), slot.type);
        field.values.push_back(field.scaled ? raw * field.scale[c] + field.offset[c] : raw);
      }
    }
  }
}

bool EndsWith(const LasField& f, const std::string& end)
{
  return f.extra && f.components == 1 && f.name.size() > end.size() &&
    f.name.compare(f.name.size() - end.size(), end.size(), end) == 0;
}

/// The number of extra dimensions from `i` on named Name_X, Name_Y, Name_Z (exactly 3) or Name_0, Name_1, ... (2 or
/// more) of one type, one component each; 1 when there is no such run.
std::size_t ComponentRun(const std::vector<LasField>& fields, std::size_t i)
{
  const bool xyz = EndsWith(fields[i], "_X");
  if (!xyz && !EndsWith(fields[i], "_0"))
  {
    return 1;
  }
  const std::string base = fields[i].name.substr(0, fields[i].name.size() - 2);
  const auto label = [xyz](
                       std::size_t c) { return xyz ? std::string(1, static_cast<char>('X' + c)) : std::to_string(c); };
  std::size_t run = 1;
  while (i + run < fields.size() && (!xyz || run < 3) && fields[i + run].extra && fields[i + run].components == 1 &&
    fields[i + run].type == fields[i].type && fields[i + run].name == base + "_" + label(run))
  {
    ++run;
  }
  return xyz && run != 3 ? 1 : run;
}

/// The `run` one-component fields from `i` on as one field of `run` components named without the suffix (their
/// values freed).
LasField Merged(std::vector<LasField>& fields, std::size_t i, std::size_t run, std::size_t n)
{
  LasField merged;
  merged.name = fields[i].name.substr(0, fields[i].name.size() - 2);
  merged.type = fields[i].type;
  merged.extra = true;
  merged.description = fields[i].description;
  merged.components = static_cast<int>(run);
  merged.values.assign(n * run, 0.0);
  for (std::size_t c = 0; c < run; ++c)
  {
    LasField& part = fields[i + c];
    merged.scaled = merged.scaled || part.scaled;
    for (std::size_t p = 0; p < n; ++p)
    {
      merged.values[p * run + c] = part.values[p];
    }
    std::vector<double>().swap(part.values);
  }
  if (merged.scaled)
  {
    merged.type = LasType::Double; // scaled components: the values are doubles already
  }
  return merged;
}

/// Runs of extra dimensions Name_X, Name_Y, Name_Z or Name_0, Name_1, ... of one type become one field Name of
/// several components (the writer's split). Then an extra field named like a standard attribute takes its name when
/// its description says it stands in for it (kLasInPlaceOf: PlantMorph's writer, which leaves the standard attribute
/// zero), else it is renamed Name_extra (Name_extra2, ... when that is taken too), and so is an extra field named
/// like an earlier one: every array has its own name. The rule reads the header alone, never the values, so every
/// piece of a file names its arrays alike.
void SettleNames(LasCloud& cloud)
{
  std::vector<LasField>& fields = cloud.fields;
  // One pass (a run merged moves on past it), so a file of thousands of such dimensions stays linear.
  std::vector<LasField> settled;
  settled.reserve(fields.size());
  for (std::size_t i = 0; i < fields.size();)
  {
    const std::size_t run = ComponentRun(fields, i);
    if (run < 2)
    {
      settled.push_back(std::move(fields[i++]));
      continue;
    }
    settled.push_back(Merged(fields, i, run, cloud.Size()));
    i += run;
  }
  fields = std::move(settled);
  std::map<std::string, std::size_t> standard; // name -> index of the standard field
  for (std::size_t s = 0; s < fields.size(); ++s)
  {
    if (!fields[s].extra)
    {
      standard.emplace(fields[s].name, s);
    }
  }
  std::set<std::string> taken;
  for (const LasField& field : fields)
  {
    taken.insert(field.name);
  }
  std::map<std::string, int> renamed; // name -> the last suffix number given to it
  std::set<std::string> seen;
  for (LasField& extra : fields)
  {
    if (!extra.extra)
    {
      continue;
    }
    const auto same = standard.find(extra.name);
    const bool inPlace = extra.description.rfind(kLasInPlaceOf, 0) == 0;
    if (same != standard.end() && inPlace && !fields[same->second].name.empty())
    {
      fields[same->second].name.clear(); // dropped below
      seen.insert(extra.name);
      continue;
    }
    if (same == standard.end() && seen.insert(extra.name).second)
    {
      continue;
    }
    const std::string base = extra.name + "_extra";
    int& k = renamed[base];
    std::string name;
    do
    {
      name = ++k == 1 ? base : base + std::to_string(k);
    } while (taken.count(name) != 0);
    taken.insert(name);
    seen.insert(name);
    extra.name = name;
  }
  fields.erase(
    std::remove_if(fields.begin(), fields.end(), [](const LasField& f) { return f.name.empty(); }), fields.end());
}

/// Reads `points` records from record `first` on.
std::string ReadPoints(std::istream& in, const RawHeader& r, std::uint64_t first, std::uint64_t points,
  const std::vector<ExtraSlot>& slots, LasCloud& cloud, const std::function<bool(double)>& progress)
{
  int standardCount = 0;
  const las::StandardSlot* standard = las::StandardSlots(r.formatByte, standardCount);
  // The standard fields first (their order is the slots'), then the extra ones ParseExtraBytes appended; every
  // field's values reserved once (the count is checked against the file's size), so memory is the arrays alone.
  std::vector<LasField> fields(static_cast<std::size_t>(standardCount));
  for (int s = 0; s < standardCount; ++s)
  {
    LasField& field = fields[static_cast<std::size_t>(s)];
    field.name = standard[s].name;
    field.type = standard[s].type;
    field.components = standard[s].components;
  }
  // Only the described dimensions are decoded (each has a byte at least, so the work per record is bounded by its
  // length; undocumented ones may be any number of zero-byte descriptors).
  std::vector<ExtraSlot> moved;
  for (ExtraSlot slot : slots)
  {
    if (slot.keep)
    {
      slot.field += static_cast<std::size_t>(standardCount);
      moved.push_back(slot);
    }
  }
  std::move(cloud.fields.begin(), cloud.fields.end(), std::back_inserter(fields));
  cloud.fields = std::move(fields);
  for (LasField& field : cloud.fields)
  {
    field.values.reserve(static_cast<std::size_t>(points) * static_cast<std::size_t>(field.components));
  }
  cloud.xyz.reserve(static_cast<std::size_t>(points) * 3);
  const std::size_t perBlock = std::max<std::size_t>(1, kLasBlockBytes / r.recordLength);
  std::vector<unsigned char> block(perBlock * r.recordLength);
  in.clear();
  in.seekg(static_cast<std::streamoff>(r.offsetToPoints + first * r.recordLength));
  for (std::uint64_t done = 0; done < points;)
  {
    const std::size_t count = static_cast<std::size_t>(std::min<std::uint64_t>(perBlock, points - done));
    in.read(reinterpret_cast<char*>(block.data()), static_cast<std::streamsize>(count * r.recordLength));
    if (static_cast<std::size_t>(in.gcount()) != count * r.recordLength)
    {
      return "point record " + std::to_string(first + done + static_cast<std::uint64_t>(in.gcount()) / r.recordLength) +
        ": the file ends inside it";
    }
    DecodeRecords(block.data(), count, r, standard, standardCount, moved, cloud);
    done += count;
    if (progress && !progress(static_cast<double>(done) / static_cast<double>(points)))
    {
      return "reading stopped at point record " + std::to_string(first + done);
    }
  }
  return "";
}

} // namespace

bool LooksLikeLas(std::istream& in)
{
  char signature[4] = { 0, 0, 0, 0 };
  in.read(signature, 4);
  return in.gcount() == 4 && std::string(signature, 4) == "LASF";
}

std::string ReadLas(std::istream& in, std::uint64_t fileSize, LasCloud& cloud,
  const std::function<bool(double)>& progress, LasPiece piece)
{
  cloud = LasCloud();
  unsigned char h[kLasHeaderSize14] = {};
  const std::size_t available = static_cast<std::size_t>(std::min<std::uint64_t>(fileSize, kLasHeaderSize14));
  if (fileSize >= 4 && ReadAt(in, 0, h, 4) && std::string(reinterpret_cast<const char*>(h), 4) != "LASF")
  {
    return HeaderField("File Signature", Quote(std::string(reinterpret_cast<const char*>(h), 4))) +
      ": not a LAS file (the signature is 'LASF')";
  }
  if (fileSize < kLasHeaderSize12 || !ReadAt(in, 0, h, available))
  {
    return "header: the file has " + std::to_string(fileSize) + " bytes, fewer than the " +
      std::to_string(kLasHeaderSize12) + " of a LAS header";
  }
  const RawHeader r = DecodeHeader(h, available);
  std::uint64_t points = 0;
  std::string error = CheckHeader(r, fileSize, points);
  std::vector<ExtraSlot> slots;
  if (error.empty())
  {
    error = ReadRecords(in, r, fileSize, r.offsetToPoints + points * r.recordLength, cloud, slots);
  }
  if (error.empty())
  {
    const auto pieces = static_cast<std::uint64_t>(std::max(1, piece.pieces));
    const auto p = static_cast<std::uint64_t>(std::min(std::max(0, piece.piece), std::max(1, piece.pieces) - 1));
    // points * k / pieces without overflowing 64 bits.
    const auto cut = [&](std::uint64_t k) { return points / pieces * k + points % pieces * k / pieces; };
    error = ReadPoints(in, r, cut(p), cut(p + 1) - cut(p), slots, cloud, progress);
  }
  if (!error.empty())
  {
    cloud = LasCloud();
    return error;
  }
  cloud.header = r.info;
  cloud.header.versionMajor = r.versionMajor;
  cloud.header.versionMinor = r.versionMinor;
  cloud.header.pointFormat = r.formatByte;
  cloud.header.pointRecordLength = r.recordLength;
  cloud.header.pointCount = points;
  for (int k = 0; k < 3; ++k)
  {
    cloud.header.scale[static_cast<std::size_t>(k)] = r.scale[k];
    cloud.header.offset[static_cast<std::size_t>(k)] = r.offset[k];
  }
  SettleNames(cloud);
  return "";
}

} // namespace plantmorph
