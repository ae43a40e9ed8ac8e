// SPDX-License-Identifier: GPL-3.0-or-later
// LAS point clouds (ASPRS LAS 1.2 and 1.4 R15), read and written without VTK so that the parser is unit-tested and
// fuzzed alone (testing/fuzz/las_fuzzer.cpp). The reader and writer of LASReader and the LAS writer
// (sources/las/vtk/, docs/formats/las.md).
//
// Read: versions 1.0 to 1.4, point data record formats 0 to 10 (4, 5, 9 and 10 without their waveform packets),
// scale and offset, every standard attribute, and the extra bytes described by the Extra Bytes VLR or EVLR
// (user "LASF_Spec", record 4; types 1-10 and the deprecated 2- and 3-element types 11-30). LAZ (the compression
// bits of the point format byte) is refused with a message saying so.
// Written: LAS 1.2 (formats 0-3) or 1.4 (formats 6-8), every numeric attribute that is not a standard one of the
// format as an extra-bytes dimension described in the Extra Bytes VLR.
//
// Reading is one pass over the file (header, VLRs, points in blocks of at most kLasBlockBytes, EVLRs), linear in its
// size. Every header field is checked against the file's size before anything is allocated: a file that claims more
// points, VLRs or extra bytes than it holds is refused with the field's name, never a huge allocation.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

namespace plantmorph
{

/// Bytes of point records read at a time.
constexpr std::size_t kLasBlockBytes = std::size_t(1) << 16;
/// The header sizes of LAS 1.0-1.2, 1.3 and 1.4.
constexpr std::uint16_t kLasHeaderSize12 = 227;
constexpr std::uint16_t kLasHeaderSize13 = 235;
constexpr std::uint16_t kLasHeaderSize14 = 375;
/// A VLR's and an EVLR's header, and one extra-bytes descriptor.
constexpr std::size_t kLasVlrHeaderSize = 54;
constexpr std::size_t kLasEvlrHeaderSize = 60;
constexpr std::size_t kLasExtraBytesDescriptorSize = 192;

/// The storage types of the Extra Bytes VLR (codes 1-10), used for every attribute.
enum class LasType : std::uint8_t
{
  UInt8 = 1,
  Int8 = 2,
  UInt16 = 3,
  Int16 = 4,
  UInt32 = 5,
  Int32 = 6,
  UInt64 = 7,
  Int64 = 8,
  Float = 9,
  Double = 10,
};

/// Bytes of one value of `type`.
std::size_t LasTypeSize(LasType type);

/// The minimum record length of point format 0-10 (0 for another format).
std::uint16_t LasPointRecordLength(int format);

/// One per-point attribute: a standard one (named as kLasStandardNames lists) or an extra-bytes dimension.
struct LasField
{
  std::string name;
  LasType type = LasType::Double; ///< the storage type (the values are exact in a double for every type but
                                  ///< 64-bit integers beyond 2^53)
  int components = 1;
  std::vector<double> values; ///< point after point, `components` each; already scaled when `scaled`
  bool extra = false;         ///< an extra-bytes dimension (else a standard attribute of the point format)
  bool scaled = false;        ///< extra bytes with a scale or an offset: values = raw * scale + offset
  std::array<double, 3> scale{ { 1, 1, 1 } };
  std::array<double, 3> offset{ { 0, 0, 0 } };
  std::string description; ///< the extra-bytes descriptor's description
};

/// The standard attributes: Intensity, ReturnNumber, NumberOfReturns, ScanDirectionFlag, EdgeOfFlightLine,
/// Classification, ClassificationFlags (bit 0 synthetic, 1 key-point, 2 withheld, 3 overlap), ScannerChannel,
/// ScanAngleRank (formats 0-5, degrees), ScanAngle (formats 6-10, units of 0.006 degrees), UserData, PointSourceId,
/// GpsTime, RGB (3 components), NIR.
extern const char* const kLasStandardNames[15];

/// The description the writer gives an extra-bytes dimension written in place of a standard attribute of the same
/// name whose values do not fit it (a double Intensity): the reader then gives it the name and drops the standard
/// attribute (left zero); an extra dimension named like a standard attribute without it, or like an earlier extra
/// one, is read as Name_extra (Name_extra2, ... when that name is taken), so every array read has its own name.
extern const char* const kLasInPlaceOf;

/// The header fields kept with a cloud (read from a file; the writer takes them when it can).
struct LasHeaderInfo
{
  int versionMajor = 1;
  int versionMinor = 4;
  int pointFormat = 6;
  std::uint16_t pointRecordLength = 0;
  std::uint64_t pointCount = 0; ///< the file's point records (every piece's)
  std::uint16_t fileSourceId = 0;
  std::uint16_t globalEncoding = 0;
  std::uint16_t creationDay = 0;
  std::uint16_t creationYear = 0;
  std::string systemIdentifier;
  std::string generatingSoftware;
  std::array<double, 3> scale{ { 0, 0, 0 } }; ///< 0: none (the writer picks them)
  std::array<double, 3> offset{ { 0, 0, 0 } };
};

struct LasCloud
{
  LasHeaderInfo header;
  std::vector<double> xyz; ///< x, y, z per point (scaled and offset)
  std::vector<LasField> fields;

  std::size_t Size() const { return this->xyz.size() / 3; }
  const LasField* Find(const std::string& name) const;
};

/// Which point records to read: piece `piece` of `pieces` holds records [N piece / pieces, N (piece + 1) / pieces)
/// of the file's N, so the pieces in order hold every record once, in file order (MPI ranks' pieces).
struct LasPiece
{
  int piece = 0;
  int pieces = 1;
};

/// Reads a LAS file of `fileSize` bytes from `in`: the header and the VLRs and EVLRs whole, and the point records of
/// `piece` (all by default). `progress` (optional) gets the fraction read after each block and returns false to
/// stop (an error then). Returns "" or the error naming the header field, VLR or point record at fault (for the
/// caller to prefix with the file's name); `cloud` is then empty. A header's error is every piece's alike; only a
/// read that is stopped, or a file that shrinks while it is read, fails one piece alone.
std::string ReadLas(std::istream& in, std::uint64_t fileSize, LasCloud& cloud,
  const std::function<bool(double)>& progress = {}, LasPiece piece = {});

/// True if the stream starts with the signature "LASF".
bool LooksLikeLas(std::istream& in);

struct LasWriteOptions
{
  int versionMinor = 4; ///< 2 (LAS 1.2) or 4 (LAS 1.4)
  int pointFormat = -1; ///< -1: the smallest of the version's formats that holds the cloud's GpsTime, RGB, NIR
  /// 0: the cloud's header.scale and offset when every point fits them, else picked (LasAutoScale); > 0: this
  /// scale on every axis, the offset picked.
  double scale = 0;
  std::string generatingSoftware = "PlantMorph";
};

/// Empty when the options are valid; otherwise the message naming the option.
std::string ValidateLasWriteOptions(const LasWriteOptions& options);

/// The scale (a power of ten, at most 1e-9) and offset of one axis whose coordinates span [lo, hi]: the finest
/// scale whose integers reach both ends from the offset (the middle of the span rounded to the scale).
void LasAutoScale(double lo, double hi, double& scale, double& offset);

/// What a write did: the fields written as standard attributes and as extra bytes, and the scale and offset.
struct LasWriteReport
{
  int pointFormat = 0;
  std::vector<std::string> standard;
  std::vector<std::string> extra;
  std::array<double, 3> scale{ { 0, 0, 0 } };
  std::array<double, 3> offset{ { 0, 0, 0 } };
};

/// Writes `cloud` as LAS. A field named like a standard attribute of the chosen format, with integer values in its
/// range (and 3 components for RGB), is written there; every other field (and a standard one out of range, then
/// described kLasInPlaceOf) as an extra-bytes dimension under its name (at most 32 characters: longer ones are cut; a component k of a field with
/// several is the dimension Name_X, Name_Y, Name_Z for 3 components, Name_k otherwise). Returns "" or the error
/// (non-finite coordinates, a field of the wrong size, too many extra bytes for a record).
std::string WriteLas(
  std::ostream& out, const LasCloud& cloud, const LasWriteOptions& options, LasWriteReport* report = nullptr);

} // namespace plantmorph
