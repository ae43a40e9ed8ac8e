// The text format of Leaf Cloud Reader (vtkLeafCloudReader; docs/methods/comparison.md, the leaf scans in data/leaf-clouds/), parsed
// without VTK so that it is unit-tested and fuzzed alone (testing/fuzz/).
//
// One point per line, numbers separated by commas, semicolons, spaces or tabs. Blank lines and lines starting with
// '#' or '//' are skipped; so is a first line that is not numeric (a header). Every data line must have the same
// number of columns, at least 3 and at most kMaxPointCloudColumns. Numbers are decimal (plantmorph/TextNumbers.h: at
// most 512 characters, finite as doubles; "inf", "nan" and hexadecimal are refused).
//
// Reading is one pass over the file in blocks, linear in its size, holding at most one line of at most
// kMaxPointCloudLineLength characters besides the values; hostile input (binary junk, NUL bytes, enormous lines or
// numbers) is refused with the line number and the reason.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <istream>
#include <string>
#include <vector>

namespace plantmorph
{

/// Most columns of a data line (the scans have 3 to 10).
constexpr std::size_t kMaxPointCloudColumns = 1000;
/// Most characters of one line (header or data).
constexpr std::size_t kMaxPointCloudLineLength = std::size_t(1) << 20;

enum class CloudLineKind
{
  Skip,    ///< blank or comment
  Data,    ///< finite numbers
  Bad,     ///< not a list of numbers (a header if it is the first line)
  Refused, ///< hostile: too many columns, a number too long or beyond a double's range; always an error
};

/// Splits one line [begin, end) (no '\n') into values; `why` says what is wrong for Bad and Refused.
CloudLineKind ParseCloudLine(const char* begin, const char* end, std::vector<double>& values, std::string& why);

struct PointCloudText
{
  std::size_t columns = 0;
  std::vector<double> values; ///< row-major, rows * columns
  std::string header;         ///< the first line when it is not numeric, else empty

  std::size_t Rows() const { return this->columns ? this->values.size() / this->columns : 0; }
};

/// The header's names: split at ',', ';' and tabs, surrounding spaces and '\r' dropped.
std::vector<std::string> SplitHeaderNames(const std::string& header);

/// Reads the whole stream into `cloud` (in blocks of 64 KiB). `progress` (optional) gets the bytes read so far
/// after each further MiB and at the end, and returns false to stop reading (an error then). Returns an empty string or "line N: ..." (or
/// "no data line") for the caller to prefix with the file's name; `cloud` is then empty.
std::string ReadPointCloudText(
  std::istream& in, PointCloudText& cloud, const std::function<bool(std::uint64_t)>& progress = {});

/// True if one of the first 20 lines (within the first kMaxPointCloudLineLength bytes) is a data line of 3 or more
/// columns, and no earlier one is a data line with fewer.
bool LooksLikePointCloudText(std::istream& in);

} // namespace plantmorph
