// SPDX-License-Identifier: GPL-3.0-or-later
// TextNumbers: the bounded number scanner agrees with strtod on ordinary numbers (bit for bit) and refuses what
// the text parsers must refuse.
#include <plantmorph/TextNumbers.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

namespace plantmorph
{
namespace
{
NumberStatus Scan(const std::string& text, double& value, std::size_t& used)
{
  const char* next = nullptr;
  const NumberStatus status = ScanNumber(text.data(), text.data() + text.size(), next, value);
  used = static_cast<std::size_t>(next - text.data());
  return status;
}

TEST(TextNumbers, AgreesWithStrtodBitForBit)
{
  for (const char* text : { "0", "-0", "+5", ".5", "5.", "-.5e-3", "1.5E+03", "0.1", "1e-310", "4e-320",
         "-1.7976931348623157e308", "123456789012345678901234567890", "3.14159265358979323846264338327950288",
         "2.2250738585072011e-308", "0.30000000000000004" })
  {
    double value = -1.0;
    std::size_t used = 0;
    ASSERT_EQ(Scan(text, value, used), NumberStatus::Ok) << text;
    EXPECT_EQ(used, std::string(text).size()) << text;
    const double expected = std::strtod(text, nullptr);
    EXPECT_EQ(std::memcmp(&value, &expected, sizeof(double)), 0) << text << " " << value << " " << expected;
  }
}

TEST(TextNumbers, StopsWhereTheNumberEnds)
{
  double value = 0.0;
  std::size_t used = 0;
  EXPECT_EQ(Scan("1e", value, used), NumberStatus::Ok); // an e without digits is not part of the number
  EXPECT_EQ(used, 1u);
  EXPECT_EQ(Scan("-2.5.5", value, used), NumberStatus::Ok);
  EXPECT_EQ(value, -2.5);
  EXPECT_EQ(used, 4u);
  EXPECT_EQ(Scan("7,8", value, used), NumberStatus::Ok);
  EXPECT_EQ(used, 1u);
}

TEST(TextNumbers, RefusesWhatIsNotANumber)
{
  double value = 42.0;
  std::size_t used = 0;
  for (const char* text : { "", "-", "+", ".", "e5", "inf", "nan", "x1", " 1" })
  {
    EXPECT_EQ(Scan(text, value, used), NumberStatus::NotANumber) << text;
    EXPECT_EQ(used, 0u);
  }
  EXPECT_EQ(value, 42.0);
  EXPECT_EQ(Scan("1e999", value, used), NumberStatus::NotFinite);
  EXPECT_EQ(Scan("-" + std::string(400, '9'), value, used), NumberStatus::NotFinite);
  EXPECT_EQ(Scan("1e-999", value, used), NumberStatus::Ok); // underflow reads as zero
  EXPECT_EQ(value, 0.0);
  EXPECT_EQ(Scan("0." + std::string(400, '0') + "1", value, used), NumberStatus::Ok);
  EXPECT_EQ(value, 0.0);
  EXPECT_EQ(Scan(std::string(kMaxNumberLength, '1'), value, used), NumberStatus::NotFinite);
  const std::string huge(10000000, '7');
  EXPECT_EQ(Scan(huge + " 1", value, used), NumberStatus::TooLong);
  EXPECT_EQ(used, huge.size()); // the whole run, scanned once
  EXPECT_NE(DescribeNumberStatus(NumberStatus::TooLong).find("512"), std::string::npos);
}

TEST(TextNumbers, ExcerptShowsPrintableText)
{
  const std::string text = std::string("ab\0\x01\xff", 5) + std::string(100, 'c');
  EXPECT_EQ(Excerpt(text.data(), text.data() + text.size(), 8), "ab???ccc...");
  EXPECT_EQ(Excerpt(text.data(), text.data() + 2), "ab");
}
} // namespace
} // namespace plantmorph
