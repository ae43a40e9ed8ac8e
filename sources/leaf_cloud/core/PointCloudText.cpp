// SPDX-License-Identifier: GPL-3.0-or-later
#include "PointCloudText.h"

#include <plantmorph/TextNumbers.h>

#include <algorithm>
#include <cstring>

namespace plantmorph
{

namespace
{
bool IsBlank(char c)
{
  return c == ' ' || c == '\t' || c == '\r';
}

/// The UTF-8 byte order mark some editors write at the start of a file.
constexpr char kByteOrderMark[] = "\xEF\xBB\xBF";

bool StartsWithByteOrderMark(const char* begin, const char* end)
{
  return end - begin >= 3 && std::memcmp(begin, kByteOrderMark, 3) == 0;
}

/// A carriage return inside the line (not only before its end): the file's lines end in CR alone.
bool HasInnerCarriageReturn(const char* begin, const char* end)
{
  while (end > begin && end[-1] == '\r')
  {
    --end;
  }
  return std::memchr(begin, '\r', static_cast<std::size_t>(end - begin)) != nullptr;
}

/// A field digits,digits on a line that, split at blanks and semicolons, has two or more fields and no '.' or
/// exponent in any: a decimal comma ("1,5 2,5 3,5" or "1,5;2,5;3,5"), which would read as two numbers. Empty when
/// there is none. (A line with decimal points, "0.5 1,2", uses commas as separators.)
std::string DecimalCommaField(const char* begin, const char* end)
{
  const auto separator = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == ';'; };
  std::size_t fields = 0;
  std::string found;
  for (const char* p = begin; p < end;)
  {
    while (p < end && separator(*p))
    {
      ++p;
    }
    const char* q = p;
    while (q < end && !separator(*q))
    {
      ++q;
    }
    if (q == p)
    {
      break;
    }
    ++fields;
    if (std::find_if(p, q, [](char c) { return c == '.' || c == 'e' || c == 'E'; }) != q)
    {
      return {};
    }
    const char* d = p + (*p == '+' || *p == '-');
    const char* comma = static_cast<const char*>(std::memchr(d, ',', static_cast<std::size_t>(q - d)));
    const auto digits = [](const char* a, const char* b) {
      return a < b && std::all_of(a, b, [](char c) { return c >= '0' && c <= '9'; });
    };
    if (found.empty() && comma && digits(d, comma) && digits(comma + 1, q))
    {
      found.assign(p, q);
    }
    p = q;
  }
  return fields >= 2 ? found : std::string();
}

/// The reader's state between lines.
class CloudBuilder
{
public:
  explicit CloudBuilder(PointCloudText& cloud)
    : Cloud(cloud)
  {
  }

  /// One line [begin, end); false with Error set when the file must be refused.
  bool Line(const char* begin, const char* end)
  {
    ++this->Number;
    if (static_cast<std::size_t>(end - begin) > kMaxPointCloudLineLength)
    {
      return this->Fail("longer than " + std::to_string(kMaxPointCloudLineLength) + " characters");
    }
    const bool fileStart = this->FileStart;
    this->FileStart = false;
    if (fileStart && StartsWithByteOrderMark(begin, end))
    {
      begin += 3; // the UTF-8 byte order mark is not part of the first line
    }
    if (std::memchr(begin, '\r', static_cast<std::size_t>(end - begin)) && HasInnerCarriageReturn(begin, end))
    {
      return this->Fail("its lines end in a carriage return alone (old Mac line ends), which are not read: convert "
                        "the file to LF or CRLF line ends");
    }
    std::string why;
    const CloudLineKind kind = ParseCloudLine(begin, end, this->Row, why);
    if (kind == CloudLineKind::Skip)
    {
      return true;
    }
    if (kind == CloudLineKind::Bad && this->FirstLine)
    {
      this->FirstLine = false; // a header line
      this->Cloud.header.assign(begin, end);
      return true;
    }
    if (kind != CloudLineKind::Data)
    {
      return this->Fail(why + ": '" + Excerpt(begin, end, 80) + "'");
    }
    this->FirstLine = false;
    if (this->Cloud.columns == 0)
    {
      this->Cloud.columns = this->Row.size();
      if (this->Cloud.columns < 3)
      {
        return this->Fail(std::to_string(this->Cloud.columns) + " column(s); a point needs at least x, y, z");
      }
    }
    else if (this->Row.size() != this->Cloud.columns)
    {
      return this->Fail(std::to_string(this->Row.size()) + " columns where the first data line has " +
        std::to_string(this->Cloud.columns));
    }
    this->Cloud.values.insert(this->Cloud.values.end(), this->Row.begin(), this->Row.end());
    return true;
  }

  bool Fail(const std::string& what)
  {
    this->What = what;
    this->Error = "line " + std::to_string(this->Number) + ": " + what;
    return false;
  }

  PointCloudText& Cloud;
  std::vector<double> Row;
  std::size_t Number = 0;
  bool FirstLine = true;
  bool FileStart = true; ///< the next line is the file's first (at offset 0): a byte order mark there is skipped
  std::string Error;
  std::string What;
};

enum class ScanStop
{
  End,     ///< the stream ended, or the next line starts after `last`
  ByLine,  ///< the visitor returned false
  TooLong, ///< a line longer than kMaxPointCloudLineLength (it starts at `lineStart`)
  ByProgress,
};

/// Visits the lines of `in` from offset `from` (a line's start) whose start offset is at most `last`, in order:
/// visit(begin, end, start) for each, false stopping. Blocks of 64 KiB, one partial line carried (bounded).
template <typename Visit>
ScanStop ScanLines(std::istream& in, std::uint64_t from, std::uint64_t last, Visit&& visit,
  const std::function<bool(std::uint64_t)>& progress, std::uint64_t& bytes)
{
  in.clear();
  in.seekg(static_cast<std::streamoff>(from));
  std::vector<char> block(std::size_t(1) << 16);
  std::string carry;
  std::uint64_t offset = from, lineStart = from, reported = 0;
  bytes = 0;
  while (in && lineStart <= last)
  {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n == 0)
    {
      break;
    }
    const char* p = block.data();
    const char* end = p + n;
    while (p < end && lineStart <= last)
    {
      const auto* newline = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
      if (!newline)
      {
        carry.append(p, end);
        if (carry.size() > kMaxPointCloudLineLength)
        {
          return ScanStop::TooLong;
        }
        break;
      }
      bool ok = true;
      if (carry.empty())
      {
        ok = visit(p, newline, lineStart);
      }
      else
      {
        carry.append(p, newline);
        ok = visit(carry.data(), carry.data() + carry.size(), lineStart);
        carry.clear();
      }
      if (!ok)
      {
        return ScanStop::ByLine;
      }
      lineStart = offset + static_cast<std::uint64_t>(newline - block.data()) + 1;
      p = newline + 1;
    }
    offset += n;
    bytes += n;
    if (progress && bytes / (std::uint64_t(1) << 20) > reported / (std::uint64_t(1) << 20))
    {
      reported = bytes;
      if (!progress(bytes))
      {
        return ScanStop::ByProgress;
      }
    }
  }
  if (!carry.empty() && lineStart <= last && !visit(carry.data(), carry.data() + carry.size(), lineStart))
  {
    return ScanStop::ByLine;
  }
  return ScanStop::End;
}

/// The offset just after the first newline at or after `begin` and before `end`; 0 when there is none.
std::uint64_t FirstLineAfter(std::istream& in, std::uint64_t begin, std::uint64_t end)
{
  in.clear();
  in.seekg(static_cast<std::streamoff>(begin));
  std::vector<char> block(std::size_t(1) << 16);
  std::uint64_t offset = begin;
  while (in && offset < end)
  {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    const auto* newline = static_cast<const char*>(std::memchr(block.data(), '\n', n));
    if (newline)
    {
      const std::uint64_t at = offset + static_cast<std::uint64_t>(newline - block.data());
      return at < end ? at + 1 : 0;
    }
    offset += n;
    if (n == 0)
    {
      break;
    }
  }
  return 0;
}
} // namespace

CloudLineKind ParseCloudLine(const char* begin, const char* end, std::vector<double>& values, std::string& why)
{
  values.clear();
  const char* p = begin;
  while (p < end && IsBlank(*p))
  {
    ++p;
  }
  if (p == end || *p == '#' || (end - p >= 2 && p[0] == '/' && p[1] == '/'))
  {
    return CloudLineKind::Skip;
  }
  bool commaChecked = false;
  while (p < end)
  {
    while (p < end && IsBlank(*p))
    {
      ++p;
    }
    if (p >= end)
    {
      break;
    }
    if (values.size() == kMaxPointCloudColumns)
    {
      why = "more than " + std::to_string(kMaxPointCloudColumns) + " columns (the most read)";
      return CloudLineKind::Refused;
    }
    double v = 0.0;
    const char* next = nullptr;
    const NumberStatus status = ScanNumber(p, end, next, v);
    if (status != NumberStatus::Ok)
    {
      why = "column " + std::to_string(values.size() + 1) + " is " + DescribeNumberStatus(status);
      if (status == NumberStatus::NotANumber)
      {
        why = "not a list of finite numbers separated by commas, semicolons or spaces (column " +
          std::to_string(values.size() + 1) + ")";
        return CloudLineKind::Bad;
      }
      return CloudLineKind::Refused;
    }
    values.push_back(v);
    p = next;
    if (p < end && *p == ',' && !commaChecked)
    {
      commaChecked = true;
      if (const std::string field = DecimalCommaField(begin, end); !field.empty())
      {
        why = "decimal commas ('" + field +
          "' would read as two numbers): write decimals with '.'; commas, "
          "semicolons, spaces and tabs separate the columns";
        return CloudLineKind::Refused;
      }
    }
    while (p < end && IsBlank(*p))
    {
      ++p;
    }
    if (p < end && (*p == ',' || *p == ';'))
    {
      ++p;
    }
    else if (p < end && !(*(p - 1) == ' ' || *(p - 1) == '\t'))
    {
      why = "not a list of finite numbers separated by commas, semicolons or spaces (junk after column " +
        std::to_string(values.size()) + ")";
      return CloudLineKind::Bad; // two numbers glued together, or junk after a number
    }
  }
  return values.empty() ? CloudLineKind::Skip : CloudLineKind::Data;
}

std::vector<std::string> SplitHeaderNames(const std::string& header)
{
  std::vector<std::string> names;
  // Separated by commas, semicolons or tabs when it has any, else by runs of spaces.
  const bool delimited = header.find_first_of(",;\t") != std::string::npos;
  const auto separator = [&](char c) { return delimited ? c == ',' || c == ';' || c == '\t' : c == ' '; };
  std::size_t start = 0;
  for (std::size_t i = 0; i <= header.size(); ++i)
  {
    if (i == header.size() || separator(header[i]))
    {
      std::size_t b = start, e = i;
      while (b < e && (header[b] == ' ' || header[b] == '\r'))
        ++b;
      while (e > b && (header[e - 1] == ' ' || header[e - 1] == '\r'))
        --e;
      if (e - b >= 2 && (header[b] == '"' || header[b] == '\'') && header[e - 1] == header[b])
      {
        ++b, --e; // a quoted name
      }
      if (!delimited && e == b)
      {
        start = i + 1;
        continue; // runs of spaces
      }
      names.emplace_back(header, b, e - b);
      start = i + 1;
    }
  }
  return names;
}

std::string ReadPointCloudText(
  std::istream& in, PointCloudText& cloud, const std::function<bool(std::uint64_t)>& progress)
{
  cloud = PointCloudText();
  CloudBuilder builder(cloud);
  // Small blocks (64 KiB) keep the buffer in cache and cheap to allocate; progress is reported per MiB.
  constexpr std::uint64_t reportEvery = std::uint64_t(1) << 20;
  std::vector<char> block(std::size_t(1) << 16);
  std::string carry; // the start of a line that continues in the next block
  std::uint64_t bytes = 0;
  std::uint64_t reported = 0;
  const auto fail = [&](const std::string& error) {
    cloud = PointCloudText();
    return error;
  };
  while (in)
  {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n == 0)
    {
      break;
    }
    bytes += n;
    const char* p = block.data();
    const char* end = p + n;
    while (p < end)
    {
      const auto* newline = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
      if (!newline)
      {
        carry.append(p, end);
        if (carry.size() > kMaxPointCloudLineLength)
        {
          ++builder.Number;
          builder.Fail("longer than " + std::to_string(kMaxPointCloudLineLength) + " characters");
          return fail(builder.Error);
        }
        break;
      }
      bool ok = true;
      if (carry.empty())
      {
        ok = builder.Line(p, newline);
      }
      else
      {
        carry.append(p, newline);
        ok = builder.Line(carry.data(), carry.data() + carry.size());
        carry.clear();
      }
      if (!ok)
      {
        return fail(builder.Error);
      }
      p = newline + 1;
    }
    const bool last = n < block.size();
    if (progress && (bytes / reportEvery > reported / reportEvery || (last && bytes != reported)))
    {
      reported = bytes;
      if (!progress(bytes))
      {
        return fail("reading stopped after " + std::to_string(bytes) + " bytes");
      }
    }
  }
  if (progress && bytes != reported && !progress(bytes))
  {
    return fail("reading stopped after " + std::to_string(bytes) + " bytes");
  }
  if (!carry.empty() && !builder.Line(carry.data(), carry.data() + carry.size()))
  {
    return fail(builder.Error);
  }
  if (cloud.columns == 0)
  {
    return fail("no data line");
  }
  return {};
}

std::string ReadPointCloudTextPiece(std::istream& in, PointCloudTextPiece& piece, PointCloudText& cloud,
  const std::function<bool(std::uint64_t)>& progress)
{
  cloud = PointCloudText();
  piece.lines = piece.firstNumber = piece.errorNumber = 0;
  piece.errorNumberInFile = true;
  piece.errorWhat.clear();
  piece.found = false;
  const auto fail = [&](const CloudBuilder& builder, bool inFile) {
    cloud = PointCloudText();
    piece.errorNumber = builder.Number;
    piece.errorNumberInFile = inFile;
    piece.errorWhat = builder.What;
    return "line " + std::to_string(builder.Number) + ": " + builder.What;
  };
  // An empty range owns no line (more pieces than bytes: the file's first line is the first non-empty piece's).
  if (piece.end <= piece.begin)
  {
    return {};
  }
  // 1. The piece's first line: after the first newline at or after begin (the first piece: the file's first line).
  const std::uint64_t first = piece.begin == 0 ? 0 : FirstLineAfter(in, piece.begin, piece.end);
  if (piece.begin > 0 && first == 0)
  {
    return {}; // no line starts in the range
  }
  // 2. The file's head, up to its first data line: the header and the column count.
  std::uint64_t dataStart = 0, bytes = 0;
  PointCloudText head;
  CloudBuilder headBuilder(head);
  if (piece.begin > 0)
  {
    const ScanStop stop = ScanLines(
      in, 0, piece.end,
      [&](const char* b, const char* e, std::uint64_t start) {
        piece.firstNumber = start == first ? headBuilder.Number + 1 : piece.firstNumber;
        if (!headBuilder.Line(b, e) || head.columns)
        {
          dataStart = start;
          return false;
        }
        return true;
      },
      {}, bytes);
    if (stop == ScanStop::TooLong)
    {
      ++headBuilder.Number;
      headBuilder.Fail("longer than " + std::to_string(kMaxPointCloudLineLength) + " characters");
    }
    if (!headBuilder.Error.empty())
    {
      return fail(headBuilder, true);
    }
    if (head.columns == 0)
    {
      return {}; // no data line before the piece's end: the piece has none
    }
    cloud.columns = head.columns;
    cloud.header = head.header;
  }
  // 3. The piece's own lines (those before the first data line are the head's: comments or the header).
  CloudBuilder builder(cloud);
  builder.FirstLine = piece.begin == 0;
  builder.FileStart = piece.begin == 0;
  builder.Number = piece.firstNumber ? piece.firstNumber - 1 : 0;
  const ScanStop stop = ScanLines(
    in, first, piece.end,
    [&](const char* b, const char* e, std::uint64_t start) {
      ++piece.lines;
      if (piece.begin > 0 && start < dataStart)
      {
        ++builder.Number;
        return true;
      }
      return builder.Line(b, e);
    },
    progress, bytes);
  const bool inFile = piece.begin == 0 || piece.firstNumber != 0;
  if (stop == ScanStop::TooLong)
  {
    ++builder.Number;
    builder.Fail("longer than " + std::to_string(kMaxPointCloudLineLength) + " characters");
  }
  if (stop == ScanStop::ByProgress)
  {
    cloud = PointCloudText();
    return "reading stopped after " + std::to_string(bytes) + " bytes";
  }
  if (!builder.Error.empty())
  {
    return fail(builder, inFile);
  }
  if (piece.begin == 0)
  {
    piece.firstNumber = 1;
  }
  piece.found = cloud.columns != 0;
  return {};
}

bool LooksLikePointCloudText(std::istream& in)
{
  // Reads 64 KiB at a time until 20 lines are whole, the file ends or kMaxPointCloudLineLength bytes are read.
  std::string text;
  std::size_t lines = 0;
  bool whole = false;
  while (lines < 20 && text.size() < kMaxPointCloudLineLength)
  {
    const std::size_t old = text.size();
    text.resize(old + (std::size_t(1) << 16));
    in.read(&text[old], static_cast<std::streamsize>(text.size() - old));
    text.resize(old + static_cast<std::size_t>(in.gcount()));
    lines += static_cast<std::size_t>(std::count(text.begin() + static_cast<std::ptrdiff_t>(old), text.end(), '\n'));
    if (!in)
    {
      whole = true; // the file ended inside the buffer
      break;
    }
  }
  std::vector<double> values;
  std::string why;
  std::size_t start = StartsWithByteOrderMark(text.data(), text.data() + text.size()) ? 3 : 0;
  for (int line = 0; line < 20 && start < text.size(); ++line)
  {
    std::size_t newline = text.find('\n', start);
    if (newline == std::string::npos && !whole)
    {
      return false; // a line longer than what was read
    }
    newline = newline == std::string::npos ? text.size() : newline;
    if (ParseCloudLine(text.data() + start, text.data() + newline, values, why) == CloudLineKind::Data)
    {
      return values.size() >= 3;
    }
    start = newline + 1;
  }
  return false;
}

} // namespace plantmorph
