// Digits a word at a time (word_digits.h) against the library's own conversion: an index
// ffdtool reads is what std::from_chars reads.
#include <gtest/gtest.h>

#include <charconv>
#include <cstdint>
#include <random>
#include <string>
#include <system_error>

#include "common/word_digits.h"
#include "mesh/text_lines.h"

namespace ffd {
namespace {

// decimal() at the start of `text` (with the line ending at its end) against from_chars:
// alone, and with digits readable past the line's end, which must not be taken in.
void expect_decimal_agrees(const std::string& text) {
  const std::string file = text + "98765432";
  const char* first = file.data();
  const char* last = file.data() + text.size();
  long long theirs = -7;
  const auto b = std::from_chars(first, last, theirs);
  for (const char* readable : {static_cast<const char*>(nullptr), last, file.data() + file.size()}) {
    long long mine = -7;
    const auto a = decimal(first, last, mine, readable);
    ASSERT_EQ(a.ec, b.ec) << '"' << text << '"';
    if (b.ec == std::errc()) {
      ASSERT_EQ(a.ptr, b.ptr) << '"' << text << '"';
      ASSERT_EQ(mine, theirs) << '"' << text << '"';
    }
  }
}

TEST(WordDigits, DecimalReadsWhatFromCharsReadsWhateverFollowsTheDigits) {
  // Every byte after the digits, including those next to '0'..'9' and those with the high
  // bit set whose low half is a digit, at every length up to 20 and either sign.
  for (int length = 0; length <= 20; ++length)
    for (int sign = 0; sign < 2; ++sign)
      for (int after = 0; after < 256; ++after) {
        std::string text = sign ? "-" : "";
        for (int k = 0; k < length; ++k) text += static_cast<char>('1' + (k * 7 + length) % 9);
        if (after >= '0' && after <= '9') continue;  // that is a longer number
        text += static_cast<char>(after);
        expect_decimal_agrees(text);
        expect_decimal_agrees(text + "1234567 8");  // 8 bytes of line past the digits
      }
}

TEST(WordDigits, DecimalReadsRandomIndicesAsFromChars) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> digits(1, 19), digit(0, 9), ending(0, 5), tail(0, 12);
  const char endings[] = {' ', '/', '\n', '\r', '\t', ':'};
  for (int i = 0; i < 300000; ++i) {
    std::string text = rng() % 5 == 0 ? "-" : "";
    for (int k = digits(rng); k > 0; --k) text += static_cast<char>('0' + digit(rng));
    text += endings[ending(rng)];
    text.append(static_cast<std::size_t>(tail(rng)), '5');
    expect_decimal_agrees(text);
    expect_decimal_agrees(text.substr(0, text.size() - static_cast<std::size_t>(tail(rng) % 3)));
  }
}

TEST(WordDigits, LeadingDigitsStopsAtTheFirstByteThatIsNotADigit) {
  for (int at = 0; at < 8; ++at)
    for (int byte = 0; byte < 256; ++byte) {
      char text[8] = {'9', '0', '5', '1', '2', '3', '4', '8'};
      text[at] = static_cast<char>(byte);
      const bool digit = byte >= '0' && byte <= '9';
      EXPECT_EQ(leading_digits(load_word(text)), digit ? 8 : at) << at << ' ' << byte;
    }
}

}  // namespace
}  // namespace ffd
