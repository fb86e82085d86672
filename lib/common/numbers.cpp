#include "common/numbers.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <system_error>

namespace ffd {

namespace {

// Shortest round-trip text, as std::to_chars(double) writes it, from {fmt}'s Dragonbox
// digits: the same bytes (numbers_test compares them on millions of doubles of every kind)
// in about 33 ns where std::to_chars takes 40 on a 1M-vertex OBJ's coordinates. Most of
// std::to_chars' time is printing the shortest significand two digits after another, each
// step waiting on the last division; here its eight-digit halves are split into pairs that
// do not wait on each other. Where std::to_chars writes a whole number from 2^53 on as its
// exact integer, and for zero and the non-finite, it writes the text itself.

struct DigitPairs {
  char c[200];
  constexpr DigitPairs() : c() {
    for (int i = 0; i < 100; ++i) c[2 * i] = static_cast<char>('0' + i / 10), c[2 * i + 1] = static_cast<char>('0' + i % 10);
  }
};
constexpr DigitPairs kPairs;

constexpr std::uint64_t kPow10[20] = {1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL, 1000000ULL, 10000000ULL,
                                      100000000ULL, 1000000000ULL, 10000000000ULL, 100000000000ULL,
                                      1000000000000ULL, 10000000000000ULL, 100000000000000ULL,
                                      1000000000000000ULL, 10000000000000000ULL, 100000000000000000ULL,
                                      1000000000000000000ULL, 10000000000000000000ULL};

/// The number of decimal digits of s > 0.
int decimal_digits(std::uint64_t s) {
  const int guess = (64 - __builtin_clzll(s)) * 1233 >> 12;  // floor(log10(2) * bits)
  return guess + (s >= kPow10[guess]);
}

/// x < 10^8 as eight digits (leading zeros) at out: four pairs, each its own division.
void eight_digits(std::uint32_t x, char* out) {
  const std::uint32_t pairs[4] = {x / 1000000, x / 10000 % 100, x / 100 % 100, x % 100};
  for (int k = 0; k < 4; ++k) std::memcpy(out + 2 * k, kPairs.c + 2 * pairs[k], 2);
}

/// The digits of s < 10^17 right-aligned in tmp[0, 24): returns where the n digits start.
/// tmp has 48 bytes, so that 24 can be copied from there whatever n is.
const char* significand_digits(std::uint64_t s, int n, char (&tmp)[48]) {
  const std::uint64_t rest = s % 10000000000000000ULL;
  tmp[7] = static_cast<char>('0' + s / 10000000000000000ULL);
  eight_digits(static_cast<std::uint32_t>(rest / 100000000), tmp + 8);
  eight_digits(static_cast<std::uint32_t>(rest % 100000000), tmp + 16);
  return tmp + 24 - n;
}

/// d * 10^e (n digits in `digits`) as %f (fixed) or %e, whichever is shorter, %f on a tie.
/// Copies are of fixed size, writing past the end within the caller's kNumberChars.
char* lay_out(char* p, const char* digits, int n, int e) {
  const int exponent = e + n - 1, magnitude = exponent < 0 ? -exponent : exponent;
  const int scientific = n + (n > 1) + 2 + (magnitude >= 100 ? 3 : 2);
  const int fixed = e >= 0 ? n + e : n + e > 0 ? n + 1 : 2 - e;
  if (fixed <= scientific) {
    if (e >= 0) {  // a whole number: at most 5 zeros after the digits (else %e is shorter)
      std::memcpy(p, digits, 24);
      std::memset(p + n, '0', 8);
      return p + n + e;
    }
    if (n + e > 0) {  // digits, point, digits
      const int whole = n + e;
      std::memcpy(p, digits, 24);
      p[whole] = '.';
      std::memcpy(p + whole + 1, digits + whole, 24);
      return p + n + 1;
    }
    std::memcpy(p, "0.000", 5);  // "0.", at most 3 zeros (else %e is shorter), the digits
    std::memcpy(p + 2 - e - n, digits, 24);
    return p + 2 - e;
  }
  *p++ = digits[0];
  if (n > 1) {
    *p++ = '.';
    std::memcpy(p, digits + 1, 24);
    p += n - 1;
  }
  *p++ = 'e';
  *p++ = exponent < 0 ? '-' : '+';
  if (magnitude >= 100) *p++ = static_cast<char>('0' + magnitude / 100);
  std::memcpy(p, kPairs.c + 2 * (magnitude % 100), 2);
  return p + 2;
}

}  // namespace

char* format_number_to(char* first, double x) {
  if (x == 0.0) x = 0.0;  // -0 prints as 0: the sign of zero carries no geometry
  if (x == 0.0 || !(std::abs(x) < 0x1p53)) return std::to_chars(first, first + kNumberChars, x).ptr;
  const auto shortest = fmt::detail::dragonbox::to_decimal(x);
  const int n = decimal_digits(shortest.significand);
  char tmp[48];
  const char* digits = significand_digits(shortest.significand, n, tmp);
  if (x < 0) *first++ = '-';
  return lay_out(first, digits, n, shortest.exponent);
}

void append_number(std::string& out, double x) {
  char buf[kNumberChars];
  out.append(buf, format_number_to(buf, x));
}

std::string format_number(double x) {
  std::string s;
  append_number(s, x);
  return s;
}

std::string format_ms(double ms) {
  char buf[32];
  std::snprintf(buf, sizeof buf, ms < 1 ? "%.3f ms" : "%.1f ms", ms);
  return buf;
}

std::string format_count(std::size_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

bool parse_finite(std::string_view text, double& value) {
  if (text.empty()) return false;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (*first == '+') {  // from_chars rejects a leading '+', OBJ writers emit it
    ++first;
    if (first != last && *first == '-') return false;  // "+-1": from_chars would take the '-'
  }
  auto [ptr, ec] = std::from_chars(first, last, value, std::chars_format::general);
  return ec == std::errc() && ptr == last && std::isfinite(value);
}

bool parse_integer(std::string_view text, long long& value) {
  if (text.empty()) return false;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (*first == '+') {
    ++first;
    if (first != last && *first == '-') return false;
  }
  auto [ptr, ec] = std::from_chars(first, last, value);
  return ec == std::errc() && ptr == last;
}

}  // namespace ffd
