// format() (types/text_format.h): the whole text whatever its length, the same
// text as printf for the conversions the library uses; and the helpers built on
// it (csvNumber, ubxTypeText, minutesSecondsText), which used to cut at fixed
// 16- to 512-byte buffers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "ppp_bayes_tree/io/ubx/ubx_framer.h"
#include "ppp_bayes_tree/types/number_text.h"
#include "ppp_bayes_tree/types/text_format.h"

namespace ppp {
namespace {

/// What snprintf writes into a buffer far larger than the text.
template <typename... Args>
std::string reference(const char* printf_format, Args... args) {
  std::vector<char> buf(1 << 16);
  std::snprintf(buf.data(), buf.size(), printf_format, args...);
  return buf.data();
}

TEST(TextFormat, SameTextAsPrintf) {
  EXPECT_EQ(format("%.3f", 1.23456), "1.235");
  EXPECT_EQ(format("%-30s|", "name"), reference("%-30s|", "name"));
  EXPECT_EQ(format("%04d-%02d-%02d", 2026, 5, 13), "2026-05-13");
  EXPECT_EQ(format("%.*f", 4, -0.00004), "-0.0000");
  EXPECT_EQ(format("%zu sats %7.2f %%", std::size_t{12}, 99.5), "12 sats   99.50 %");
  EXPECT_EQ(format("%19.12E", 6.02214076e23), reference("%19.12E", 6.02214076e23));
  EXPECT_EQ(format("%g", std::nan("")), "nan");
  EXPECT_EQ(format("%s", ""), "");
}

TEST(TextFormat, LongTextsAreWhole) {
  // Longer than every buffer the old helpers had (48, 64, 128, 160, 256, 512 bytes).
  const std::string long_name(1500, 'x');
  const std::string text = format("%s: state x%u refused (%s)", long_name.c_str(), 7u, long_name.c_str());
  EXPECT_EQ(text, long_name + ": state x7 refused (" + long_name + ")");
  EXPECT_EQ(format("%.600f", 1.0).size(), 602u);  // "1." and 600 zeros
  EXPECT_EQ(format("%-700s|", "a").size(), 701u);
  EXPECT_EQ(format("%.500e", 1.0), reference("%.500e", 1.0));
}

TEST(TextFormat, TextsAroundTheStackBufferAreWhole) {
  // format() writes into a 256-byte buffer first and again into a string when the
  // text is longer: every length around that edge comes out whole.
  for (std::size_t n = 250; n <= 262; ++n) {
    const std::string body(n, 'y');
    EXPECT_EQ(format("%s", body.c_str()), body) << n;
    EXPECT_EQ(format("%s%d", body.c_str(), 7), body + "7") << n;
  }
}

TEST(TextFormat, TextBuiltOnFormatIsWhole) {
  // csvNumber had a 64-byte buffer: 100 decimals were cut to 63 characters.
  EXPECT_EQ(csvNumber("%.100f", 1.0).size(), 102u);
  EXPECT_EQ(csvNumber("%.4f", 1.5), "1.5000");
  EXPECT_EQ(csvNumber("%.4f", std::nan("")), "");
  EXPECT_EQ(ubxTypeText(0x0215), "0x02 0x15");  // RXM-RAWX
  EXPECT_EQ(ubxTypeText(0x0A09), "0x0A 0x09");
  EXPECT_EQ(minutesSecondsText(725.4), "12:05");  // rounded to the second
  EXPECT_EQ(minutesSecondsText(59.6), "1:00");
  EXPECT_EQ(minutesSecondsText(0.0), "0:00");
  EXPECT_EQ(minutesSecondsText(600000.0), "10000:00");
}

}  // namespace
}  // namespace ppp
