// SPDX-License-Identifier: GPL-3.0-or-later
// The LAS reader and writer alone (sources/las/core/LasFile.h): round trips of every written point format and
// version, bit for bit within the scale; a file's header checked byte by byte against the layout of the LAS 1.4 R15
// specification (tables 3 and 4, the Extra Bytes VLR of section 2.6); a file written by hand read back; malformed
// files refused with the field named and nothing read.
#include "LasFile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using plantmorph::LasCloud;
using plantmorph::LasField;
using plantmorph::LasType;

namespace
{
std::uint64_t U(const std::string& bytes, std::size_t at, int size)
{
  std::uint64_t v = 0;
  for (int i = size - 1; i >= 0; --i)
  {
    v = (v << 8) | static_cast<unsigned char>(bytes.at(at + static_cast<std::size_t>(i)));
  }
  return v;
}

double D(const std::string& bytes, std::size_t at)
{
  const std::uint64_t bits = U(bytes, at, 8);
  double d;
  std::memcpy(&d, &bits, 8);
  return d;
}

void PutU(std::string& bytes, std::size_t at, std::uint64_t v, int size)
{
  for (int i = 0; i < size; ++i)
  {
    bytes[at + static_cast<std::size_t>(i)] = static_cast<char>((v >> (8 * i)) & 0xFF);
  }
}

void PutD(std::string& bytes, std::size_t at, double d)
{
  std::uint64_t bits;
  std::memcpy(&bits, &d, 8);
  PutU(bytes, at, bits, 8);
}

LasField Field(const std::string& name, LasType type, int components = 1)
{
  LasField f;
  f.name = name;
  f.type = type;
  f.components = components;
  return f;
}

/// A cloud of `n` points with every standard attribute `format` has (random values in range) and PlantMorph's
/// labels and scan arrays as extras.
LasCloud TestCloud(int format, std::size_t n, unsigned seed)
{
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> coordinate(-3.0, 7.0);
  LasCloud cloud;
  cloud.header.creationDay = 42;
  cloud.header.creationYear = 2024;
  for (std::size_t i = 0; i < 3 * n; ++i)
  {
    cloud.xyz.push_back(coordinate(random) + (i % 3 == 2 ? 100.0 : 0.0));
  }
  const bool modern = format >= 6;
  const auto ints = [&](LasField f, int lo, int hi) {
    std::uniform_int_distribution<int> value(lo, hi);
    for (std::size_t i = 0; i < n * static_cast<std::size_t>(f.components); ++i)
    {
      f.values.push_back(value(random));
    }
    cloud.fields.push_back(f);
  };
  ints(Field("Intensity", LasType::UInt16), 0, 65535);
  ints(Field("ReturnNumber", LasType::UInt8), 1, modern ? 15 : 7);
  ints(Field("NumberOfReturns", LasType::UInt8), 1, modern ? 15 : 7);
  ints(Field("ScanDirectionFlag", LasType::UInt8), 0, 1);
  ints(Field("EdgeOfFlightLine", LasType::UInt8), 0, 1);
  ints(Field("Classification", LasType::UInt8), 0, modern ? 255 : 31);
  ints(Field("ClassificationFlags", LasType::UInt8), 0, modern ? 15 : 7);
  if (modern)
  {
    ints(Field("ScannerChannel", LasType::UInt8), 0, 3);
    ints(Field("ScanAngle", LasType::Int16), -30000, 30000);
  }
  else
  {
    ints(Field("ScanAngleRank", LasType::Int8), -90, 90);
  }
  ints(Field("UserData", LasType::UInt8), 0, 255);
  ints(Field("PointSourceId", LasType::UInt16), 0, 65535);
  if (format == 1 || format == 3 || modern)
  {
    LasField time = Field("GpsTime", LasType::Double);
    for (std::size_t i = 0; i < n; ++i)
    {
      time.values.push_back(1.0e9 + 0.001 * static_cast<double>(i) + 1e-7 * static_cast<double>(random() % 1000));
    }
    cloud.fields.push_back(time);
  }
  if (format == 2 || format == 3 || format >= 7)
  {
    ints(Field("RGB", LasType::UInt16, 3), 0, 65535);
  }
  if (format == 8)
  {
    ints(Field("NIR", LasType::UInt16), 0, 65535);
  }
  ints(Field("LeafId", LasType::Int32), -1, 40);
  ints(Field("Organ", LasType::UInt8), 0, 4);
  ints(Field("BranchId", LasType::Int64), -1, 100000);
  ints(Field("BeamId", LasType::Int64), 0, 2000000000);
  ints(Field("ScanPosition", LasType::Int32), 0, 7);
  LasField range = Field("Range", LasType::Double);
  LasField normals = Field("Normals", LasType::Float, 3);
  for (std::size_t i = 0; i < n; ++i)
  {
    range.values.push_back(coordinate(random) * 1e-3 + 2.0);
    for (int k = 0; k < 3; ++k)
    {
      normals.values.push_back(static_cast<float>(coordinate(random) / 7.0));
    }
  }
  cloud.fields.push_back(range);
  cloud.fields.push_back(normals);
  return cloud;
}

std::string Write(
  const LasCloud& cloud, const plantmorph::LasWriteOptions& options, plantmorph::LasWriteReport* report = nullptr)
{
  std::ostringstream out;
  const std::string error = plantmorph::WriteLas(out, cloud, options, report);
  EXPECT_EQ(error, "");
  return out.str();
}

std::string Read(const std::string& bytes, LasCloud& cloud)
{
  std::istringstream in(bytes);
  return plantmorph::ReadLas(in, bytes.size(), cloud);
}

/// Reads `bytes`, expecting an error that contains `named`, and nothing read.
void ExpectRefused(const std::string& bytes, const std::string& named)
{
  LasCloud cloud;
  const std::string error = Read(bytes, cloud);
  EXPECT_NE(error.find(named), std::string::npos) << "error: '" << error << "', expected it to name '" << named << "'";
  EXPECT_EQ(cloud.Size(), 0u);
  EXPECT_TRUE(cloud.fields.empty());
}
} // namespace

struct FormatCase
{
  int versionMinor;
  int format;
};

class LasRoundTrip : public ::testing::TestWithParam<FormatCase>
{
};

TEST_P(LasRoundTrip, EveryAttributeComesBackAndTheBytesAreStable)
{
  const FormatCase c = GetParam();
  const LasCloud cloud = TestCloud(c.format, 2500, 7u + static_cast<unsigned>(c.format));
  plantmorph::LasWriteOptions options;
  options.versionMinor = c.versionMinor;
  options.pointFormat = c.format;
  plantmorph::LasWriteReport report;
  const std::string bytes = Write(cloud, options, &report);
  EXPECT_EQ(report.pointFormat, c.format);
  EXPECT_EQ(report.extra,
    (std::vector<std::string>{
      "LeafId", "Organ", "BranchId", "BeamId", "ScanPosition", "Range", "Normals_X", "Normals_Y", "Normals_Z" }));
  LasCloud back;
  ASSERT_EQ(Read(bytes, back), "");
  EXPECT_EQ(back.header.versionMinor, c.versionMinor);
  EXPECT_EQ(back.header.pointFormat, c.format);
  ASSERT_EQ(back.Size(), cloud.Size());
  for (std::size_t i = 0; i < cloud.xyz.size(); ++i)
  {
    const double scale = report.scale[i % 3];
    ASSERT_LE(std::fabs(back.xyz[i] - cloud.xyz[i]), 0.5 * scale * (1 + 1e-6)) << "coordinate " << i;
  }
  for (const LasField& field : cloud.fields)
  {
    const LasField* read = back.Find(field.name);
    ASSERT_NE(read, nullptr) << field.name;
    EXPECT_EQ(read->type, field.type) << field.name;
    EXPECT_EQ(read->components, field.components) << field.name;
    EXPECT_EQ(read->values, field.values) << field.name;
  }
  // The cloud read back, written again with its own scale and offset, gives the same bytes.
  EXPECT_EQ(Write(back, options), bytes);
}

INSTANTIATE_TEST_SUITE_P(EveryWrittenFormat, LasRoundTrip,
  ::testing::Values(FormatCase{ 2, 0 }, FormatCase{ 2, 1 }, FormatCase{ 2, 2 }, FormatCase{ 2, 3 }, FormatCase{ 4, 0 },
    FormatCase{ 4, 1 }, FormatCase{ 4, 2 }, FormatCase{ 4, 3 }, FormatCase{ 4, 6 }, FormatCase{ 4, 7 },
    FormatCase{ 4, 8 }),
  [](const ::testing::TestParamInfo<FormatCase>& info) {
    return "Las1" + std::to_string(info.param.versionMinor) + "Format" + std::to_string(info.param.format);
  });

TEST(LasFile, AutomaticFormatHoldsTheAttributes)
{
  plantmorph::LasWriteOptions options;
  options.versionMinor = 4;
  plantmorph::LasWriteReport report;
  Write(TestCloud(8, 10, 1), options, &report);
  EXPECT_EQ(report.pointFormat, 8);
  Write(TestCloud(7, 10, 1), options, &report);
  EXPECT_EQ(report.pointFormat, 7);
  Write(TestCloud(0, 10, 1), options, &report);
  EXPECT_EQ(report.pointFormat, 6);
  options.versionMinor = 2;
  Write(TestCloud(3, 10, 1), options, &report);
  EXPECT_EQ(report.pointFormat, 3);
  Write(TestCloud(0, 10, 1), options, &report);
  EXPECT_EQ(report.pointFormat, 0);
}

TEST(LasFile, AttributesTheFormatLacksBecomeExtraBytes)
{
  // A format-8 cloud written as LAS 1.2 format 0: GPS time, RGB, NIR, the 4-bit returns and the wide
  // classification do not fit, so they are extra bytes and come back whole.
  const LasCloud cloud = TestCloud(8, 300, 3);
  plantmorph::LasWriteOptions options;
  options.versionMinor = 2;
  options.pointFormat = 0;
  const std::string bytes = Write(cloud, options);
  LasCloud back;
  ASSERT_EQ(Read(bytes, back), "");
  for (const char* name : { "GpsTime", "RGB", "NIR", "ScanAngle", "ScannerChannel", "LeafId" })
  {
    const LasField* read = back.Find(name);
    ASSERT_NE(read, nullptr) << name;
    EXPECT_EQ(read->values, cloud.Find(name)->values) << name;
  }
}

TEST(LasFile, AutoScaleIsTheFinestPowerOfTenThatHoldsTheExtent)
{
  std::mt19937 random(5);
  for (int trial = 0; trial < 200; ++trial)
  {
    const double centre = std::ldexp(std::uniform_real_distribution<double>(-1, 1)(random), trial % 40);
    const double half = std::ldexp(1.0, trial % 45 - 20);
    double scale = 0, offset = 0;
    plantmorph::LasAutoScale(centre - half, centre + half, scale, offset);
    const double reach = std::max(std::fabs(centre + half - offset), std::fabs(centre - half - offset)) / scale;
    EXPECT_LT(reach, 2.0e9);
    const double exponent = std::log10(scale);
    EXPECT_NEAR(exponent, std::round(exponent), 1e-9);
    if (scale > 1.5e-9)
    {
      EXPECT_GE(reach * 10, 2.0e9) << "a ten times finer scale would hold [" << centre - half << ", " << centre + half
                                   << "]";
    }
  }
}

TEST(LasFile, HeaderOfLas14MatchesTheSpecificationLayout)
{
  const LasCloud cloud = TestCloud(7, 50, 9);
  plantmorph::LasWriteOptions options;
  plantmorph::LasWriteReport report;
  const std::string b = Write(cloud, options, &report);
  const std::size_t extras = 9; // LeafId, Organ, BranchId, BeamId, ScanPosition, Range, Normals_X/Y/Z
  const std::size_t vlr = 54 + 192 * extras;
  EXPECT_EQ(b.substr(0, 4), "LASF");                      // File Signature
  EXPECT_EQ(U(b, 6, 2), 16u);                             // Global Encoding: WKT bit (formats 6-10)
  EXPECT_EQ(U(b, 24, 1), 1u);                             // Version Major
  EXPECT_EQ(U(b, 25, 1), 4u);                             // Version Minor
  EXPECT_EQ(b.substr(26, 5), std::string("OTHER"));       // System Identifier
  EXPECT_EQ(b.substr(58, 10), std::string("PlantMorph")); // Generating Software
  EXPECT_EQ(U(b, 90, 2), 42u);                            // File Creation Day of Year
  EXPECT_EQ(U(b, 92, 2), 2024u);                          // File Creation Year
  EXPECT_EQ(U(b, 94, 2), 375u);                           // Header Size
  EXPECT_EQ(U(b, 96, 4), 375u + vlr);                     // Offset to Point Data
  EXPECT_EQ(U(b, 100, 4), 1u);                            // Number of Variable Length Records
  EXPECT_EQ(U(b, 104, 1), 7u);                            // Point Data Record Format
  const std::size_t length = 36 + 4 + 1 + 8 + 8 + 4 + 8 + 3 * 4;
  EXPECT_EQ(U(b, 105, 2), length); // Point Data Record Length
  EXPECT_EQ(U(b, 107, 4), 0u);     // Legacy Number of Point Records (format 7)
  for (int r = 0; r < 5; ++r)
  {
    EXPECT_EQ(U(b, 111 + 4 * static_cast<std::size_t>(r), 4), 0u); // Legacy Number of Points by Return
  }
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_EQ(D(b, 131 + 8 * static_cast<std::size_t>(k)), report.scale[static_cast<std::size_t>(k)]);
    EXPECT_EQ(D(b, 155 + 8 * static_cast<std::size_t>(k)), report.offset[static_cast<std::size_t>(k)]);
  }
  double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
  LasCloud back;
  ASSERT_EQ(Read(b, back), "");
  for (std::size_t i = 0; i < back.xyz.size(); ++i)
  {
    lo[i % 3] = std::min(lo[i % 3], back.xyz[i]);
    hi[i % 3] = std::max(hi[i % 3], back.xyz[i]);
  }
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_EQ(D(b, 179 + 16 * static_cast<std::size_t>(k)), hi[k]); // Max X, Y, Z
    EXPECT_EQ(D(b, 187 + 16 * static_cast<std::size_t>(k)), lo[k]); // Min X, Y, Z
  }
  EXPECT_EQ(U(b, 227, 8), 0u);  // Start of Waveform Data Packet Record
  EXPECT_EQ(U(b, 235, 8), 0u);  // Start of First Extended Variable Length Record
  EXPECT_EQ(U(b, 243, 4), 0u);  // Number of Extended Variable Length Records
  EXPECT_EQ(U(b, 247, 8), 50u); // Number of Point Records
  std::uint64_t byReturn[15] = {};
  for (double r : cloud.Find("ReturnNumber")->values)
  {
    ++byReturn[static_cast<int>(r) - 1];
  }
  for (std::size_t r = 0; r < 15; ++r)
  {
    EXPECT_EQ(U(b, 255 + 8 * r, 8), byReturn[r]) << "Number of Points by Return " << r + 1;
  }
  // The Extra Bytes VLR: header (reserved, user id, record id, length, description), then 192-byte descriptors.
  EXPECT_EQ(b.substr(377, 9), "LASF_Spec");
  EXPECT_EQ(U(b, 393, 2), 4u);
  EXPECT_EQ(U(b, 395, 2), 192u * extras);
  const std::size_t first = 375 + 54;
  EXPECT_EQ(U(b, first + 2, 1), 6u); // LeafId: data type 6, a 32-bit signed integer
  EXPECT_EQ(U(b, first + 3, 1), 0u); // options: no scale, offset, no_data, min, max
  EXPECT_EQ(b.substr(first + 4, 6), std::string("LeafId\0", 7).substr(0, 6));
  EXPECT_EQ(U(b, first + 192 + 2, 1), 1u);      // Organ: unsigned char
  EXPECT_EQ(U(b, first + 2 * 192 + 2, 1), 8u);  // BranchId: 64-bit signed
  EXPECT_EQ(U(b, first + 5 * 192 + 2, 1), 10u); // Range: double
  EXPECT_EQ(U(b, first + 6 * 192 + 2, 1), 9u);  // Normals_X: float
  // The first point record: X, Y, Z as integers of the scale and offset, intensity, then RGB at byte 30.
  const std::size_t p = 375 + vlr;
  EXPECT_EQ(b.size(), p + 50 * length);
  const double x = D(b, 155) + D(b, 131) * static_cast<double>(static_cast<std::int32_t>(U(b, p, 4)));
  EXPECT_EQ(x, back.xyz[0]);
  EXPECT_EQ(U(b, p + 12, 2), cloud.Find("Intensity")->values[0]);
  EXPECT_EQ(U(b, p + 30, 2), cloud.Find("RGB")->values[0]);
  EXPECT_EQ(static_cast<std::int32_t>(U(b, p + 36, 4)), cloud.Find("LeafId")->values[0]);
}

TEST(LasFile, HeaderOfLas12MatchesTheSpecificationLayout)
{
  const LasCloud cloud = TestCloud(1, 64, 11);
  plantmorph::LasWriteOptions options;
  options.versionMinor = 2;
  options.pointFormat = 1;
  const std::string b = Write(cloud, options);
  EXPECT_EQ(U(b, 25, 1), 2u);
  EXPECT_EQ(U(b, 94, 2), 227u);                // Header Size
  EXPECT_EQ(U(b, 96, 4), 227u + 54 + 192 * 9); // Offset to Point Data
  EXPECT_EQ(U(b, 104, 1), 1u);
  EXPECT_EQ(U(b, 105, 2), 28u + 4 + 1 + 8 + 8 + 4 + 8 + 12);
  EXPECT_EQ(U(b, 107, 4), 64u); // Number of Point Records (legacy, the only one in 1.2)
  std::uint64_t byReturn[5] = {};
  for (double r : cloud.Find("ReturnNumber")->values)
  {
    if (r <= 5)
    {
      ++byReturn[static_cast<int>(r) - 1];
    }
  }
  for (std::size_t r = 0; r < 5; ++r)
  {
    EXPECT_EQ(U(b, 111 + 4 * r, 4), byReturn[r]) << "Number of Points by Return " << r + 1;
  }
  EXPECT_EQ(b.substr(229, 9), "LASF_Spec"); // the VLR right after the 227-byte header
}

namespace
{
/// A LAS 1.4 file written byte by byte: format 6, 2 points, one extra-bytes dimension "HitObjectId" (uint16)
/// with 4 undocumented bytes after it, as HELIOS++ and others write them.
std::string HandWrittenFile()
{
  const std::size_t vlr = 54 + 2 * 192, length = 30 + 2 + 4;
  std::string b(375 + vlr + 2 * length, '\0');
  b.replace(0, 4, "LASF");
  PutU(b, 24, 1, 1);
  PutU(b, 25, 4, 1);
  PutU(b, 94, 375, 2);
  PutU(b, 96, 375 + vlr, 4);
  PutU(b, 100, 1, 4);
  PutU(b, 104, 6, 1);
  PutU(b, 105, length, 2);
  PutD(b, 131, 0.01), PutD(b, 139, 0.01), PutD(b, 147, 0.001);
  PutD(b, 155, 1000), PutD(b, 163, 2000), PutD(b, 171, 0);
  PutU(b, 247, 2, 8);
  b.replace(375 + 2, 9, "LASF_Spec");
  PutU(b, 375 + 18, 4, 2);
  PutU(b, 375 + 20, 2 * 192, 2);
  const std::size_t d = 375 + 54;
  PutU(b, d + 2, 3, 1);
  b.replace(d + 4, 11, "HitObjectId");
  PutU(b, d + 192 + 2, 0, 1); // undocumented bytes: options holds their number
  PutU(b, d + 192 + 3, 4, 1);
  for (std::size_t i = 0; i < 2; ++i)
  {
    const std::size_t p = 375 + vlr + i * length;
    PutU(b, p, static_cast<std::uint32_t>(static_cast<std::int32_t>(-150 + 300 * static_cast<int>(i))), 4);
    PutU(b, p + 4, 25, 4);
    PutU(b, p + 8, 1234567, 4);
    PutU(b, p + 12, 777 + i, 2);
    PutU(b, p + 14, 0x21 + i, 1); // return 1 (2) of 2
    PutU(b, p + 15, 0x0A, 1);     // flags: key-point and overlap
    PutU(b, p + 16, 5 + i, 1);    // classification
    PutU(b, p + 18, static_cast<std::uint16_t>(static_cast<std::int16_t>(-500)), 2);
    PutD(b, p + 22, 12.5 + static_cast<double>(i));
    PutU(b, p + 30, 40000 + i, 2);
    PutU(b, p + 32, 0xDEADBEEF, 4);
  }
  return b;
}
} // namespace

TEST(LasFile, ReadsAFileWrittenByHand)
{
  LasCloud cloud;
  ASSERT_EQ(Read(HandWrittenFile(), cloud), "");
  ASSERT_EQ(cloud.Size(), 2u);
  EXPECT_DOUBLE_EQ(cloud.xyz[0], 1000 - 1.5);
  EXPECT_DOUBLE_EQ(cloud.xyz[1], 2000.25);
  EXPECT_DOUBLE_EQ(cloud.xyz[2], 1234.567);
  EXPECT_DOUBLE_EQ(cloud.xyz[3], 1000 + 1.5);
  const auto values = [&](const char* name) {
    return cloud.Find(name) ? cloud.Find(name)->values : std::vector<double>{};
  };
  EXPECT_EQ(values("Intensity"), (std::vector<double>{ 777, 778 }));
  EXPECT_EQ(values("ReturnNumber"), (std::vector<double>{ 1, 2 }));
  EXPECT_EQ(values("NumberOfReturns"), (std::vector<double>{ 2, 2 }));
  EXPECT_EQ(values("ClassificationFlags"), (std::vector<double>{ 10, 10 }));
  EXPECT_EQ(values("Classification"), (std::vector<double>{ 5, 6 }));
  EXPECT_EQ(values("ScanAngle"), (std::vector<double>{ -500, -500 }));
  EXPECT_EQ(values("GpsTime"), (std::vector<double>{ 12.5, 13.5 }));
  EXPECT_EQ(values("HitObjectId"), (std::vector<double>{ 40000, 40001 }));
  EXPECT_EQ(cloud.Find("HitObjectId")->type, LasType::UInt16);
  EXPECT_EQ(cloud.fields.size(), 13u); // 12 attributes of format 6 and the one described dimension
}

TEST(LasFile, ScaledExtraBytesAreReadAsScaledValues)
{
  std::string b = HandWrittenFile();
  const std::size_t d = 375 + 54;
  PutU(b, d + 3, 0x18, 1); // scale and offset given
  PutD(b, d + 112, 0.5);
  PutD(b, d + 136, -3.0);
  LasCloud cloud;
  ASSERT_EQ(Read(b, cloud), "");
  EXPECT_EQ(cloud.Find("HitObjectId")->values, (std::vector<double>{ 40000 * 0.5 - 3, 40001 * 0.5 - 3 }));
  // Written back with the same scale and offset: the raw integers again.
  plantmorph::LasWriteOptions options;
  LasCloud again;
  ASSERT_EQ(Read(Write(cloud, options), again), "");
  EXPECT_EQ(again.Find("HitObjectId")->values, cloud.Find("HitObjectId")->values);
  EXPECT_TRUE(again.Find("HitObjectId")->scaled);
}

TEST(LasFile, MalformedFilesAreRefusedNamingTheField)
{
  const std::string good = HandWrittenFile();
  ExpectRefused(good.substr(0, 100), "fewer than the 227");
  ExpectRefused("", "fewer than the 227");
  std::string b = good;
  b[0] = 'X';
  ExpectRefused(b, "File Signature");
  b = good;
  PutU(b, 247, 3, 8);
  ExpectRefused(b, "'Number of Point Records' = 3");
  PutU(b, 247, std::uint64_t(1) << 61, 8);
  ExpectRefused(b, "'Number of Point Records' = 2305843009213693952");
  b = good;
  PutU(b, 107, 7, 4);
  ExpectRefused(b, "Legacy Number of Point Records");
  b = good;
  PutU(b, 105, 29, 2);
  ExpectRefused(b, "'Point Data Record Length' = 29");
  b = good;
  PutU(b, 105, 31, 2); // long enough for format 6, too short for its extra bytes
  ExpectRefused(b, "Extra Bytes");
  b = good;
  PutU(b, 375 + 20, 5000, 2);
  ExpectRefused(b, "VLR 0");
  b = good;
  PutU(b, 375 + 20, 100, 2);
  ExpectRefused(b, "not a multiple of 192");
  b = good;
  PutU(b, 100, 40, 4);
  ExpectRefused(b, "Number of Variable Length Records");
  b = good;
  PutU(b, 96, 1u << 30, 4);
  ExpectRefused(b, "Offset to Point Data");
  b = good;
  PutU(b, 94, 300, 2);
  ExpectRefused(b, "Header Size");
  b = good;
  PutU(b, 25, 7, 1);
  ExpectRefused(b, "Version");
  b = good;
  PutD(b, 139, 0.0);
  ExpectRefused(b, "Y scale factor");
  b = good;
  PutU(b, 104, 6 | 0x80, 1);
  ExpectRefused(b, "LAZ");
  b = good;
  PutU(b, 104, 12, 1);
  ExpectRefused(b, "Point Data Record Format");
  b = good;
  PutU(b, 375 + 54 + 2, 31, 1);
  ExpectRefused(b, "data type 31");
  b = good;
  PutU(b, 243, 1, 4);
  PutU(b, 235, b.size() + 10, 8);
  ExpectRefused(b, "Start of First Extended Variable Length Record");
  b = good;
  PutU(b, 243, 1000, 4);
  PutU(b, 235, b.size(), 8);
  ExpectRefused(b, "Number of Extended Variable Length Records");
}

TEST(LasFile, EveryTruncationIsRefusedOrReadsWhole)
{
  const std::string good = HandWrittenFile();
  for (std::size_t size = 0; size < good.size(); ++size)
  {
    LasCloud cloud;
    const std::string error = Read(good.substr(0, size), cloud);
    EXPECT_NE(error, "") << "a file cut at byte " << size << " was read";
    EXPECT_EQ(cloud.Size(), 0u);
  }
}

TEST(LasFile, WriterRefusesBadOptionsAndCoordinates)
{
  plantmorph::LasWriteOptions options;
  options.versionMinor = 3;
  EXPECT_NE(plantmorph::ValidateLasWriteOptions(options).find("Version"), std::string::npos);
  options.versionMinor = 2;
  options.pointFormat = 6;
  EXPECT_NE(plantmorph::ValidateLasWriteOptions(options).find("PointFormat"), std::string::npos);
  options = plantmorph::LasWriteOptions();
  options.scale = -1;
  EXPECT_NE(plantmorph::ValidateLasWriteOptions(options).find("Scale"), std::string::npos);
  LasCloud cloud = TestCloud(6, 3, 2);
  cloud.xyz[4] = std::nan("");
  std::ostringstream out;
  EXPECT_NE(plantmorph::WriteLas(out, cloud, plantmorph::LasWriteOptions()).find("point 1"), std::string::npos);
  cloud = TestCloud(6, 3, 2);
  options = plantmorph::LasWriteOptions();
  options.scale = 1e-12;
  EXPECT_NE(plantmorph::WriteLas(out, cloud, options).find("Scale asked for"), std::string::npos);
}

TEST(LasFile, OffsetsAndExtentsAreNeverNegativeZero)
{
  // A cloud around the origin: the offset rounds to zero and must be written +0 (a -0 made a re-written file differ
  // from the first in its header).
  LasCloud cloud = TestCloud(6, 20, 4);
  for (std::size_t i = 0; i < cloud.xyz.size(); ++i)
  {
    cloud.xyz[i] = (i % 2 ? -1e-12 : 0.0);
  }
  plantmorph::LasWriteReport report;
  const std::string b = Write(cloud, plantmorph::LasWriteOptions(), &report);
  for (std::size_t at = 155; at < 227; at += 8)
  {
    EXPECT_FALSE(std::signbit(D(b, at))) << "header double at byte " << at;
  }
}

TEST(LasFile, AnExtraDimensionTakesAStandardNameOnlyWhenItSaysSo)
{
  // A double Intensity does not fit LAS's 16-bit one: written as extra bytes "in place of" it, read back under its
  // name, the zero standard attribute dropped.
  LasCloud cloud = TestCloud(6, 30, 8);
  LasField* intensity = nullptr;
  for (LasField& field : cloud.fields)
  {
    intensity = field.name == "Intensity" ? &field : intensity;
  }
  intensity->type = LasType::Double;
  intensity->values[3] = 0.25;
  const std::string bytes = Write(cloud, plantmorph::LasWriteOptions());
  LasCloud back;
  ASSERT_EQ(Read(bytes, back), "");
  ASSERT_NE(back.Find("Intensity"), nullptr);
  EXPECT_TRUE(back.Find("Intensity")->extra);
  EXPECT_EQ(back.Find("Intensity")->values, intensity->values);
  EXPECT_EQ(back.Find("Intensity_extra"), nullptr);
  // The same file with another description (another tool's dimension of that name): both are kept, the extra one
  // renamed.
  std::string other = bytes;
  const std::size_t descriptions = 375 + 54;
  bool found = false;
  for (std::size_t d = descriptions; d + 192 <= 375 + 54 + U(bytes, 375 + 20, 2); d += 192)
  {
    if (bytes.substr(d + 4, 10) == std::string("Intensity\0", 10))
    {
      other.replace(d + 160, 5, "hits!");
      found = true;
    }
  }
  ASSERT_TRUE(found);
  ASSERT_EQ(Read(other, back), "");
  ASSERT_NE(back.Find("Intensity_extra"), nullptr);
  EXPECT_EQ(back.Find("Intensity_extra")->values, intensity->values);
  EXPECT_FALSE(back.Find("Intensity")->extra);
}

TEST(LasFile, EveryArrayReadHasItsOwnName)
{
  // A cloud may hold two arrays of one name (the standard RGB and an extra RGB of three components; an extra Tag
  // twice, beside a Tag_extra). The writer puts the first RGB in the standard attribute and the second in extra bytes
  // (RGB_X, RGB_Y, RGB_Z); read back, every array has a name of its own and its own values.
  LasCloud cloud = TestCloud(7, 20, 11);
  ASSERT_NE(cloud.Find("RGB"), nullptr);
  const std::vector<double> rgb = cloud.Find("RGB")->values;
  LasField second = Field("RGB", LasType::Double, 3);
  LasField tag = Field("Tag", LasType::Int32);
  LasField tagExtra = Field("Tag_extra", LasType::Int32);
  for (std::size_t i = 0; i < 20; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      second.values.push_back(0.5 * static_cast<double>(i) + c);
    }
    tag.values.push_back(static_cast<double>(i));
    tagExtra.values.push_back(-static_cast<double>(i));
  }
  LasField tag2 = tag;
  for (double& v : tag2.values)
  {
    v += 100;
  }
  for (LasField* f : { &second, &tag, &tag2, &tagExtra })
  {
    f->extra = true;
    cloud.fields.push_back(*f);
  }
  const std::string bytes = Write(cloud, plantmorph::LasWriteOptions());
  LasCloud back;
  ASSERT_EQ(Read(bytes, back), "");
  for (std::size_t a = 0; a < back.fields.size(); ++a)
  {
    for (std::size_t b = a + 1; b < back.fields.size(); ++b)
    {
      EXPECT_NE(back.fields[a].name, back.fields[b].name);
    }
  }
  ASSERT_NE(back.Find("RGB"), nullptr);
  EXPECT_FALSE(back.Find("RGB")->extra);
  EXPECT_EQ(back.Find("RGB")->values, rgb);
  ASSERT_NE(back.Find("RGB_extra"), nullptr);
  EXPECT_EQ(back.Find("RGB_extra")->values, second.values);
  ASSERT_NE(back.Find("Tag"), nullptr);
  EXPECT_EQ(back.Find("Tag")->values, tag.values);
  ASSERT_NE(back.Find("Tag_extra2"), nullptr);
  EXPECT_EQ(back.Find("Tag_extra2")->values, tag2.values);
  ASSERT_NE(back.Find("Tag_extra"), nullptr);
  EXPECT_EQ(back.Find("Tag_extra")->values, tagExtra.values);
}

TEST(LasFile, PiecesInOrderAreTheWholeFile)
{
  const std::string bytes = Write(TestCloud(8, 1001, 12), plantmorph::LasWriteOptions());
  LasCloud whole;
  ASSERT_EQ(Read(bytes, whole), "");
  EXPECT_EQ(whole.header.pointCount, 1001u);
  for (int pieces = 1; pieces <= 7; ++pieces)
  {
    std::vector<double> xyz;
    std::vector<std::vector<double>> values(whole.fields.size());
    for (int piece = 0; piece < pieces; ++piece)
    {
      std::istringstream in(bytes);
      LasCloud part;
      ASSERT_EQ(plantmorph::ReadLas(in, bytes.size(), part, {}, plantmorph::LasPiece{ piece, pieces }), "");
      EXPECT_EQ(part.Size(), 1001u * (piece + 1) / pieces - 1001u * piece / pieces);
      ASSERT_EQ(part.fields.size(), whole.fields.size());
      xyz.insert(xyz.end(), part.xyz.begin(), part.xyz.end());
      for (std::size_t f = 0; f < part.fields.size(); ++f)
      {
        EXPECT_EQ(part.fields[f].name, whole.fields[f].name);
        values[f].insert(values[f].end(), part.fields[f].values.begin(), part.fields[f].values.end());
      }
    }
    EXPECT_EQ(xyz, whole.xyz) << pieces << " pieces";
    for (std::size_t f = 0; f < values.size(); ++f)
    {
      EXPECT_EQ(values[f], whole.fields[f].values) << whole.fields[f].name << ", " << pieces << " pieces";
    }
  }
}
