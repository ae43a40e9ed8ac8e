// SPDX-License-Identifier: GPL-3.0-or-later
// PointCloudText (sources/leaf_cloud/core): Leaf Cloud Reader's text format. Every value read back exactly, lines
// across the reader's 64 KiB blocks, the header and comment conventions, and hostile files refused with the line and
// reason.
#include "PointCloudText.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace plantmorph
{
namespace
{
std::string Read(const std::string& text, PointCloudText& cloud)
{
  std::istringstream in(text);
  return ReadPointCloudText(in, cloud);
}

void ExpectRefused(const std::string& text, const std::string& words)
{
  PointCloudText cloud;
  const std::string error = Read(text, cloud);
  EXPECT_NE(error.find(words), std::string::npos) << error;
  EXPECT_EQ(cloud.columns, 0u);
  EXPECT_TRUE(cloud.values.empty());
}

TEST(PointCloudText, ScanFormatWithHeaderCommentsAndMixedSeparators)
{
  PointCloudText cloud;
  ASSERT_EQ(
    Read("x, y; z\tq\n# a comment\n// another\n\n  \r\n1,2,3,4\n5 6 7 8\r\n-1;-2 ; -3,\t-4\n.5 , 1e2  3e-1 4\n", cloud),
    "");
  EXPECT_EQ(cloud.columns, 4u);
  EXPECT_EQ(cloud.Rows(), 4u);
  EXPECT_EQ(cloud.values, (std::vector<double>{ 1, 2, 3, 4, 5, 6, 7, 8, -1, -2, -3, -4, 0.5, 100, 0.3, 4 }));
  EXPECT_EQ(cloud.header, "x, y; z\tq");
  EXPECT_EQ(SplitHeaderNames(cloud.header), (std::vector<std::string>{ "x", "y", "z", "q" }));
  EXPECT_EQ(SplitHeaderNames("a,,b\r"), (std::vector<std::string>{ "a", "", "b" }));
}

TEST(PointCloudText, HeaderNamesInEverySeparatorAndQuoted)
{
  const std::vector<std::string> xyz{ "id", "x", "y", "z" };
  EXPECT_EQ(SplitHeaderNames("id x y z"), xyz);
  EXPECT_EQ(SplitHeaderNames("  id   x y  z\r"), xyz);
  EXPECT_EQ(SplitHeaderNames("id,x,y,z"), xyz);
  EXPECT_EQ(SplitHeaderNames("id;x;y;z"), xyz);
  EXPECT_EQ(SplitHeaderNames("id\tx\ty\tz"), xyz);
  EXPECT_EQ(SplitHeaderNames("\"id\",\"x\", 'y' ,z"), xyz);
}

TEST(PointCloudText, ByteOrderMarkIsSkipped)
{
  PointCloudText cloud;
  ASSERT_EQ(Read("\xEF\xBB\xBF"
                 "1 2 3\n4 5 6\n",
              cloud),
    "");
  EXPECT_EQ(cloud.values, (std::vector<double>{ 1, 2, 3, 4, 5, 6 })); // the first data line kept
  EXPECT_EQ(cloud.header, "");
  ASSERT_EQ(Read("\xEF\xBB\xBFx,y,z\n1,2,3\n", cloud), "");
  EXPECT_EQ(cloud.header, "x,y,z");
  EXPECT_EQ(SplitHeaderNames(cloud.header)[0], "x");
  std::istringstream in("\xEF\xBB\xBF"
                        "1 2 3\n");
  EXPECT_TRUE(LooksLikePointCloudText(in));
}

TEST(PointCloudText, CarriageReturnOnlyLineEndsAreRefusedWithTheReason)
{
  ExpectRefused("x y z\r1 2 3\r4 5 6\r", "line 1: its lines end in a carriage return alone (old Mac line ends)");
  ExpectRefused("1 2 3\r4 5 6\r", "line 1: its lines end in a carriage return alone");
  ExpectRefused("1 2 3\n4 5 6\r7 8 9\n", "line 2: its lines end in a carriage return alone");
  PointCloudText cloud;
  ASSERT_EQ(Read("x y z\r\n1 2 3\r\n4 5 6\r\r\n", cloud), ""); // CRLF (and a stray CR before it) still read
  EXPECT_EQ(cloud.Rows(), 2u);
}

TEST(PointCloudText, DecimalCommasAreRefusedWithTheReason)
{
  ExpectRefused("1,5 2,5 3,5\n", "line 1: decimal commas ('1,5' would read as two numbers)");
  ExpectRefused("x;y;z\n1,5;2,5;3,5\n", "line 2: decimal commas ('1,5'");
  ExpectRefused("1 2 3\n4 -2,25\t6\n", "line 2: decimal commas ('-2,25'");
  ExpectRefused("x y z\n1.5 2 3\n1 2,5 3\n", "line 3: decimal commas ('2,5'");
  ExpectRefused("1,5 2 3,5\n", "line 1: decimal commas ('1,5'");
  // Commas as column separators, with or without spaces, are not decimal commas.
  PointCloudText cloud;
  for (const char* text :
    { "1,5,2\n", "1, 5, 2\n", "1.5,2.5, 3.5\n", "1 ,2 ,3\n", "10,20,30,40\n", "0.5 -0,1\n", "1e3 2,3\n" })
  {
    EXPECT_EQ(Read(text, cloud), "") << text;
    EXPECT_GE(cloud.columns, 3u) << text;
  }
}

TEST(PointCloudText, ValuesAcrossBlocksEqualPrintf)
{
  // About 3 MB: lines straddle the 64 KiB read blocks; every value comes back as printf's %.17g round trip.
  std::string text;
  std::vector<double> expected;
  char line[128];
  for (int i = 0; i < 60000; ++i)
  {
    const double v[3] = { i * 0.001 + 1.0 / 3.0, -i * 1.25e-7, 1e10 / (i + 1) };
    std::snprintf(line, sizeof(line), "%.17g %.17g,%.17g\n", v[0], v[1], v[2]);
    text += line;
    expected.insert(expected.end(), v, v + 3);
  }
  text.pop_back(); // the last line without its newline
  ASSERT_GT(text.size(), 2u << 20);
  std::istringstream in(text);
  std::vector<std::uint64_t> progress;
  PointCloudText cloud;
  ASSERT_EQ(ReadPointCloudText(in, cloud,
              [&](std::uint64_t bytes) {
                progress.push_back(bytes);
                return true;
              }),
    "");
  EXPECT_EQ(cloud.values, expected);
  ASSERT_EQ(progress.size(), (text.size() + (1u << 20) - 1) >> 20); // one report per MiB, and the end
  EXPECT_EQ(progress.back(), text.size());
  EXPECT_LT(progress[0], progress[1]);

  std::istringstream again(text);
  EXPECT_EQ(
    ReadPointCloudText(again, cloud, [](std::uint64_t) { return false; }), "reading stopped after 1048576 bytes");
  EXPECT_TRUE(cloud.values.empty());
}

TEST(PointCloudText, InconsistentFilesAreErrorsWithTheLine)
{
  ExpectRefused("1 2 3\n4 5\n", "line 2: 2 columns where the first data line has 3");
  ExpectRefused("1 2\n", "line 1: 2 column(s); a point needs at least x, y, z");
  ExpectRefused("x y z\n1 2 3\n4 five 6\n", "line 3: not a list of finite numbers");
  ExpectRefused("1 2 3\n4 5 6x\n", "line 2: not a list");
  ExpectRefused("# only comments\n\n", "no data line");
  ExpectRefused("", "no data line");
  ExpectRefused("x y z\n", "no data line");
  ExpectRefused("1 2 3\n0x10 1 2\n", "line 2: not a list"); // hexadecimal is not read
}

TEST(PointCloudText, HostileFilesAreRefused)
{
  // The former hang: one line of 2*10^6 columns (8 MB).
  std::string wide;
  for (int i = 0; i < 2000000; ++i)
    wide += "1.5 ";
  ExpectRefused(wide.substr(0, kMaxPointCloudLineLength - 10) + "\n", "line 1: more than 1000 columns");
  ExpectRefused(wide + "\n", "line 1: longer than 1048576 characters");
  ExpectRefused("1 2 3\n" + std::string(3000000, ' ') + "\n", "line 2: longer than");
  ExpectRefused("1 2 3\n4 " + std::string(1, '\0') + " 5 6\n", "line 2: not a list");
  ExpectRefused("1 2 3\n4 5 " + std::string(10000000, '9') + "\n", "line 2: longer than"); // 10^7 digits
  ExpectRefused("1 2 3\n4 5 " + std::string(600, '9') + "\n", "line 2: column 3 is a number of more than 512");
  ExpectRefused("1 2 3\n4 5 1e400\n", "line 2: column 3 is a number beyond the range of a double");
  ExpectRefused("1e400 2 3\n", "line 1: column 1 is a number beyond"); // not taken for a header
  ExpectRefused("\"1\",\"2\",\"3\n", "no data line"); // an unterminated quote: a header line, then nothing
  std::string junk;
  for (int i = 0; i < 200000; ++i)
    junk += static_cast<char>((static_cast<unsigned>(i) * 7919u + 13u) % 256u);
  PointCloudText cloud;
  EXPECT_NE(Read(junk, cloud), "");
  EXPECT_TRUE(cloud.values.empty());
}

/// The file read as `count` pieces (as MPI ranks read it), in order: the values concatenated, the first error with
/// its line number in the file (counted as the reader does: the pieces' own lines added up).
struct ByPieces
{
  std::vector<double> values;
  std::size_t columns = 0;
  std::string error;
  int failures = 0;
};

ByPieces ReadByPieces(const std::string& text, const std::vector<std::uint64_t>& cuts)
{
  ByPieces result;
  std::uint64_t number = 1;
  for (std::size_t p = 0; p + 1 < cuts.size(); ++p)
  {
    std::istringstream in(text);
    PointCloudTextPiece piece;
    piece.begin = cuts[p];
    piece.end = p + 2 == cuts.size() ? UINT64_MAX : cuts[p + 1];
    PointCloudText cloud;
    const std::string error = ReadPointCloudTextPiece(in, piece, cloud);
    number = piece.firstNumber ? piece.firstNumber : number;
    if (!error.empty())
    {
      EXPECT_TRUE(cloud.values.empty());
      ++result.failures;
      if (result.error.empty())
      {
        const std::uint64_t line = piece.errorNumberInFile ? piece.errorNumber : number - 1 + piece.errorNumber;
        result.error = "line " + std::to_string(line) + ": " + piece.errorWhat;
      }
    }
    if (cloud.Rows() > 0)
    {
      EXPECT_TRUE(result.columns == 0 || result.columns == cloud.columns);
      result.columns = cloud.columns;
    }
    result.values.insert(result.values.end(), cloud.values.begin(), cloud.values.end());
    number += piece.lines;
  }
  return result;
}

std::vector<std::uint64_t> EvenCuts(std::size_t size, std::size_t count)
{
  std::vector<std::uint64_t> cuts;
  for (std::size_t p = 0; p <= count; ++p)
  {
    cuts.push_back(size * p / count);
  }
  return cuts;
}

std::string BigText()
{
  std::string text = "# scan\n\nx y z w\r\n";
  for (int i = 0; i < 30000; ++i)
  {
    text += std::to_string(i) + " " + std::to_string(i * 0.25) + ", " +
      std::string(static_cast<std::size_t>(i % 9), ' ') + std::to_string(-i) + ";" + std::to_string(i % 17) +
      (i % 5 ? "\n" : "\r\n");
    if (i % 997 == 0)
    {
      text += "// a comment\n\n";
    }
  }
  return text + "1 2 3 4"; // no newline at the end
}

TEST(PointCloudText, PiecesTileTheFileInOrder)
{
  const std::vector<std::string> texts = { "# c\n\nx,y,z\r\n1,2,3\r\n4 5 6\n// c\n7;8;9\n\n10 11 12", "1 2 3\n",
    "1 2 3", std::string(5000, '#') + "\n" + "x y z\n" + std::string(3000, '\n') + "1 2 3\n4 5 6\n", "x y z\n\n",
    BigText() };
  for (const std::string& text : texts)
  {
    PointCloudText whole;
    const std::string wholeError = Read(text, whole);
    for (std::size_t count = 1; count <= 9; ++count)
    {
      const ByPieces pieces = ReadByPieces(text, EvenCuts(text.size(), count));
      if (!wholeError.empty())
      {
        EXPECT_EQ(wholeError, "no data line"); // only "x y z\n\n": no piece may fail, none has a point
        EXPECT_EQ(pieces.failures, 0);
        EXPECT_TRUE(pieces.values.empty());
        continue;
      }
      EXPECT_EQ(pieces.failures, 0) << pieces.error;
      EXPECT_EQ(pieces.values, whole.values) << count << " pieces of a " << text.size() << "-byte file";
      EXPECT_EQ(pieces.columns, whole.columns);
    }
  }
  // Two pieces cut at every byte of a small file: lines at, before and after the cut.
  const std::string& small = texts[0];
  PointCloudText whole;
  ASSERT_EQ(Read(small, whole), "");
  for (std::uint64_t cut = 0; cut <= small.size(); ++cut)
  {
    EXPECT_EQ(ReadByPieces(small, { 0, cut, small.size() }).values, whole.values) << "cut at " << cut;
  }
}

TEST(PointCloudText, PiecesReportTheWholeFilesErrorWithItsLineNumber)
{
  std::string lines;
  for (int i = 0; i < 5000; ++i)
  {
    lines += std::to_string(i) + " 1 2\n";
  }
  for (const std::string& text : { "x y z\n" + lines + "4 five 6\n" + lines, "# c\n" + lines + "4 5\n" + lines,
         lines + lines + "1 2 1e999\n", "1 2 3\n" + lines + std::string(2000000, ' ') + "\n" + lines })
  {
    PointCloudText whole;
    const std::string expected = Read(text, whole);
    ASSERT_NE(expected, "");
    for (std::size_t count = 2; count <= 7; ++count)
    {
      const ByPieces pieces = ReadByPieces(text, EvenCuts(text.size(), count));
      EXPECT_EQ(pieces.error, expected) << count << " pieces";
      EXPECT_EQ(pieces.failures, 1) << count << " pieces"; // only the piece that holds the line
    }
  }
  // An error before the first data line is every later piece's (each reads the head): the same message.
  const std::string early = "x y z\nnot numbers here\n" + lines;
  PointCloudText whole;
  const std::string expected = Read(early, whole);
  EXPECT_EQ(ReadByPieces(early, EvenCuts(early.size(), 4)).error, expected);
}

TEST(PointCloudText, OnlyTheFilesFirstLineLosesAByteOrderMarkInPiecesToo)
{
  // Found by the fuzzer: a piece whose first line is not the file's must not skip a byte order mark there.
  const std::string text = "\xEF\xBB\xBF"
                           "1 2 3\n\n\xEF\xBB\xBF";
  ExpectRefused(text, "line 3: ");
  for (std::size_t count = 1; count <= 8; ++count)
  {
    const ByPieces pieces = ReadByPieces(text, EvenCuts(text.size(), count));
    EXPECT_GE(pieces.failures, 1) << count << " pieces";
  }
  const std::string good = "\xEF\xBB\xBF"
                           "x y z\n1 2 3\n4 5 6\n";
  for (std::size_t count = 1; count <= 8; ++count)
  {
    const ByPieces pieces = ReadByPieces(good, EvenCuts(good.size(), count));
    EXPECT_EQ(pieces.failures, 0) << count << " pieces: " << pieces.error;
    EXPECT_EQ(pieces.values, (std::vector<double>{ 1, 2, 3, 4, 5, 6 })) << count << " pieces";
  }
}

TEST(PointCloudText, LooksLikeAPointCloud)
{
  const auto looks = [](const std::string& text) {
    std::istringstream in(text);
    return LooksLikePointCloudText(in);
  };
  EXPECT_TRUE(looks("x,y,z\n# c\n1,2,3\n"));
  EXPECT_FALSE(looks("a,b\n1,2\n"));
  EXPECT_FALSE(looks(std::string(3u << 20, '1')));
  EXPECT_FALSE(looks(std::string(25, '\n') + "1 2 3\n"));
}
} // namespace
} // namespace plantmorph
