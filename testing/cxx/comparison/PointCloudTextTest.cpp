// PointCloudText (comparison/core): Leaf Cloud Reader's text format. Every value read back exactly, lines across the
// reader's 64 KiB blocks, the header and comment conventions, and hostile files refused with the line and reason.
#include "PointCloudText.h"

#include <gtest/gtest.h>

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
  // The hang: one line of 2*10^6 columns (8 MB).
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
