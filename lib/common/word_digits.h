// Decimal digits eight at a time in one 64-bit word, the text's first byte lowest (x86-64
// is little-endian): an index is read with a few multiplications instead of a loop of one
// digit per step that waits on the last. word_digits_test checks it against
// std::from_chars.
#pragma once

#include <cstdint>
#include <cstring>

namespace ffd {

/// The 8 bytes at p as one word. p must have 8 readable bytes.
inline std::uint64_t load_word(const char* p) {
  std::uint64_t word;
  std::memcpy(&word, p, 8);
  return word;
}

/// How many of word's bytes, from its first, are '0'..'9' before any other byte (0 to 8).
/// A byte b is a digit when b ^ '0' is at most 9; adding 0x76 sets the high bit of every
/// larger value below 0x8a, and the larger ones have it set already. A carry out of such a
/// byte only reaches bytes after it, so the first flagged byte is the first non-digit.
inline int leading_digits(std::uint64_t word) {
  const std::uint64_t x = word ^ 0x3030303030303030ULL;
  const std::uint64_t flagged = ((x + 0x7676767676767676ULL) | x) & 0x8080808080808080ULL;
  return flagged ? __builtin_ctzll(flagged) >> 3 : 8;
}

/// The number that word's first n digits spell (1 <= n <= 8; leading_digits(word) >= n):
/// the digits are moved to the top of the word behind 8 - n zeros, then pairs, quads and
/// the two halves are combined, each step in every lane at once.
inline std::uint32_t digits_value(std::uint64_t word, int n) {
  std::uint64_t d = (word & 0x0F0F0F0F0F0F0F0FULL) << (8 * (8 - n));
  d = (d * 10 + (d >> 8)) & 0x00FF00FF00FF00FFULL;
  d = (d * 100 + (d >> 16)) & 0x0000FFFF0000FFFFULL;
  return static_cast<std::uint32_t>((d * 10000 + (d >> 32)) & 0xFFFFFFFFULL);
}

}  // namespace ffd
