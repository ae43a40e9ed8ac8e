// SPDX-License-Identifier: GPL-3.0-or-later
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

/// One piece of a file read in parallel (MPI ranks): the byte range [begin, end). A piece reads the lines whose
/// preceding newline lies in its range (the non-empty piece at begin 0 also the file's first line): the first line it reads
/// starts after the first newline at or after `begin`, and it reads through the line that crosses `end`. Pieces
/// that tile the file read every line once, in file order.
struct PointCloudTextPiece
{
  std::uint64_t begin = 0;
  std::uint64_t end = UINT64_MAX;
  // Out:
  std::uint64_t lines = 0;       ///< lines the piece owns (its range's), counted when no error stopped it
  std::uint64_t firstNumber = 0; ///< the file's line number of the piece's first line when known, else 0
  std::uint64_t errorNumber = 0; ///< on error: the line's number in the file, or in the piece (its first line 1)
  bool errorNumberInFile = true; ///< whether errorNumber counts the file's lines (else the piece's: the caller adds
                                 ///< the lines of the pieces before)
  std::string errorWhat;         ///< on error: what is wrong with the line (the message is "line N: what")
  bool found = false;            ///< the file has a data line before the piece's end (header and columns known)
};

/// Reads one piece of a seekable stream. The file's head (every line before its first data line: comments, the
/// header) is read first by every piece, up to its own end at most, to learn the header and the column count; then
/// the piece's own lines are parsed as ReadPointCloudText would (the same checks, the same values). Linear in the
/// head plus the piece; one line of at most kMaxPointCloudLineLength held. Returns "" (the cloud may be empty: a
/// piece without data lines) or the error, `cloud` then empty. "no data line" is never returned: only all pieces
/// together can tell.
std::string ReadPointCloudTextPiece(std::istream& in, PointCloudTextPiece& piece, PointCloudText& cloud,
  const std::function<bool(std::uint64_t)>& progress = {});

/// True if one of the first 20 lines (within the first kMaxPointCloudLineLength bytes) is a data line of 3 or more
/// columns, and no earlier one is a data line with fewer.
bool LooksLikePointCloudText(std::istream& in);

} // namespace plantmorph
