// Exact text forms of numbers: shortest round-trip formatting and strict parsing.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "common/numbers.h"

namespace ffd {
namespace {

// Significant digits of a decimal text as to_chars writes it ("-1.25e-07" -> 3).
int significant_digits(const std::string& text) {
  std::string digits;
  for (char c : text) {
    if (c == 'e' || c == 'E') break;
    if (c >= '0' && c <= '9') digits += c;
  }
  const auto first = digits.find_first_not_of('0');
  if (first == std::string::npos) return 1;
  const auto last = digits.find_last_not_of('0');
  return static_cast<int>(last - first + 1);
}

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

TEST(Numbers, FormatAndParseRoundTripExactlyOverManyMagnitudes) {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> mantissa(1.0, 10.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  std::uniform_int_distribution<std::uint64_t> any_bits;
  std::size_t checked = 0, shortest_checked = 0;
  for (int n = 0; n < 100000; ++n) {
    double x;
    switch (n % 4) {
      case 0:  // decimal magnitudes 1e-300 .. 1e300, both signs
        x = mantissa(rng) * std::pow(10.0, exponent(rng)) * (rng() & 1 ? -1 : 1);
        break;
      case 1:  // mesh-like magnitudes
        x = (mantissa(rng) - 5.5) * std::pow(10.0, exponent(rng) % 7);
        break;
      case 2: {  // any finite bit pattern, subnormals included
        do {
          const std::uint64_t b = any_bits(rng);
          std::memcpy(&x, &b, sizeof x);
        } while (!std::isfinite(x));
        break;
      }
      default:  // short decimals, as hand-written files hold them
        x = std::round(mantissa(rng) * 1e6) / 1e6 * std::pow(10.0, exponent(rng) % 5);
        break;
    }
    const std::string text = format_number(x);
    double back = 0;
    ASSERT_TRUE(parse_finite(text, back)) << text;
    ASSERT_EQ(bits(back), bits(x)) << text;
    const int digits = significant_digits(text);
    if (text.find_first_of(".e") == std::string::npos && std::abs(x) >= 1e16) {
      // An integer-valued double of 17 to 22 digits: to_chars prefers the fixed form when it
      // has fewer characters than the exponent form, and that form spells out the exact
      // integer. It is still never longer than the shortest exponent form.
      char sci[64];
      const auto r = std::to_chars(sci, sci + sizeof sci, x, std::chars_format::scientific);
      ASSERT_LE(text.size(), static_cast<std::size_t>(r.ptr - sci)) << text;
      ++checked;
      continue;
    }
    ASSERT_LE(digits, 17) << text;
    // Shortest: the nearest decimal with one digit fewer does not read back to x.
    if (digits > 1 && std::isnormal(x)) {
      char shorter[64];
      std::snprintf(shorter, sizeof shorter, "%.*e", digits - 2, x);
      double y = 0;
      ASSERT_TRUE(parse_finite(shorter, y)) << shorter;
      EXPECT_NE(y, x) << text << " is not the shortest form: " << shorter << " reads back too";
      ++shortest_checked;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 100000u);
  EXPECT_GT(shortest_checked, 80000u);
}

// format_number_to lays out Dragonbox's digits itself; it must write std::to_chars'
// bytes for every double (but -0, written as 0): random bit patterns (every magnitude,
// subnormals), coordinates, short decimals, powers of two and ten, whole numbers around
// 2^53 (where std::to_chars writes exact integers), and the %f/%e boundaries.
TEST(Numbers, FormatWritesWhatToCharsWrites) {
  std::mt19937_64 rng(21);
  std::size_t checked = 0;
  const auto check = [&](double x) {
    if (!std::isfinite(x)) return;
    char want[64], have[kNumberChars];
    char* want_end = std::to_chars(want, want + sizeof want, x == 0.0 ? 0.0 : x).ptr;
    char* have_end = format_number_to(have, x);
    ASSERT_EQ(std::string(have, have_end), std::string(want, want_end)) << std::hexfloat << x;
    ++checked;
  };
  for (const double x : {0.0, -0.0, 1.0, -1.0, 0.5, 0.1, 1e-5, 1.5e-5, 1e-4, 12345.0, 123456.0, 1e15, 1e16, 9007199254740991.0,
                         9007199254740992.0, 1e21, 1e22, 1e23, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308})
    for (const double sign : {1.0, -1.0}) check(sign * x);
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t bits = rng();
    double x;
    std::memcpy(&x, &bits, sizeof x);
    check(x);
    check(std::uniform_real_distribution<double>(-1000, 1000)(rng));
    check(std::uniform_real_distribution<double>(0, 1)(rng));
    check(static_cast<double>(static_cast<std::int64_t>(rng() % 100000000) - 50000000) / std::pow(10.0, static_cast<int>(rng() % 12)));
    check(std::ldexp(1.0, static_cast<int>(rng() % 2098) - 1074));
    check(static_cast<double>(rng() % (std::uint64_t{1} << 55)));
    check(std::pow(10.0, static_cast<int>(rng() % 50) - 25) * static_cast<double>(1 + rng() % 999));
  }
  EXPECT_GT(checked, 1000000u);
}

TEST(Numbers, ExtremeValuesRoundTrip) {
  for (double x : {std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
                   std::numeric_limits<double>::min(), std::numeric_limits<double>::denorm_min(),
                   -std::numeric_limits<double>::denorm_min(), 0.1, 1.0 / 3.0, 1e22, 1e23, 5e-324,
                   2.2250738585072009e-308, 9007199254740993.0, 0.30000000000000004}) {
    double back = 0;
    ASSERT_TRUE(parse_finite(format_number(x), back)) << format_number(x);
    EXPECT_EQ(bits(back), bits(x)) << format_number(x);
  }
}

TEST(Numbers, FormatsShortAndSpecialValues) {
  EXPECT_EQ(format_number(0.0), "0");
  EXPECT_EQ(format_number(-0.0), "0");  // the sign of zero carries no geometry
  EXPECT_EQ(format_number(1.0), "1");
  EXPECT_EQ(format_number(-2.5), "-2.5");
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(format_number(1.0 / 3.0), "0.3333333333333333");
  EXPECT_EQ(format_number(std::nan("")).find("nan") != std::string::npos, true);
  EXPECT_EQ(format_number(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity()), "-inf");
  std::string s = "v ";
  append_number(s, 1.5);
  EXPECT_EQ(s, "v 1.5");
}

TEST(Numbers, ParseFiniteRejectsMalformedAndNonFiniteText) {
  for (const char* bad : {"", "nan", "NaN", "-nan", "inf", "-inf", "+inf", "infinity", "1e999", "-1e999",
                          "1.0x", "--1", "+-1", "-+1", "++1", "+", "-", ".", "e5", "1e", "1.0 ", " 1.0",
                          "1,5", "0x10", "abc"}) {
    double value = 42;
    EXPECT_FALSE(parse_finite(bad, value)) << "'" << bad << "' was accepted as " << value;
  }
}

TEST(Numbers, ParseFiniteAcceptsOrdinaryForms) {
  const std::pair<const char*, double> cases[] = {
      {"+1.5", 1.5}, {"-1.5", -1.5}, {"0", 0.0},      {"1e5", 1e5},   {"1E5", 1e5},
      {"-2.5e-3", -2.5e-3}, {"3", 3.0}, {"0.1", 0.1}, {"+0", 0.0}, {"1.7976931348623157e308", 1.7976931348623157e308}};
  for (const auto& [text, expect] : cases) {
    double value = -1;
    ASSERT_TRUE(parse_finite(text, value)) << text;
    EXPECT_EQ(value, expect) << text;
  }
  // Correctly rounded: the halfway case between two doubles rounds to even.
  double v = 0;
  ASSERT_TRUE(parse_finite("9007199254740993", v));
  EXPECT_EQ(v, 9007199254740992.0);
}

TEST(Numbers, ParseIntegerIsStrict) {
  long long v = 0;
  EXPECT_TRUE(parse_integer("12", v));
  EXPECT_EQ(v, 12);
  EXPECT_TRUE(parse_integer("-3", v));
  EXPECT_EQ(v, -3);
  EXPECT_TRUE(parse_integer("+4", v));
  EXPECT_EQ(v, 4);
  for (const char* bad : {"", "1.0", "1x", "x1", "--1", "+-1", "++1", "+", "1e3", " 1", "99999999999999999999999"})
    EXPECT_FALSE(parse_integer(bad, v)) << bad;
}

TEST(Numbers, FormatCountGroupsThousands) {
  EXPECT_EQ(format_count(0), "0");
  EXPECT_EQ(format_count(7), "7");
  EXPECT_EQ(format_count(999), "999");
  EXPECT_EQ(format_count(1000), "1,000");
  EXPECT_EQ(format_count(1839), "1,839");
  EXPECT_EQ(format_count(100000), "100,000");
  EXPECT_EQ(format_count(999999), "999,999");
  EXPECT_EQ(format_count(1234567), "1,234,567");
  EXPECT_EQ(format_count(1000000000), "1,000,000,000");
  EXPECT_EQ(format_count(18446744073709551615ull), "18,446,744,073,709,551,615");
}

}  // namespace
}  // namespace ffd
