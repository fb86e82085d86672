// Line and token scanning shared by the text mesh readers.
#pragma once

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#ifdef __SSE2__
#include <emmintrin.h>
#endif
#ifdef __AVX2__
#include <immintrin.h>
#endif

#include "common/errors.h"
#include "common/numbers.h"
#include "common/word_digits.h"

namespace ffd {

/// The '\n' of a text one after another, for positions that never go back. With SSE2
/// (every x86-64) it tests sixteen bytes at once into a bit mask and keeps the mask, so a
/// short line costs a few instructions: a mesh file's lines are 20-50 bytes, where a
/// memchr call per line cost more (a 1M-vertex OBJ's 4M lines: 26 ms against 44 for a
/// pass over them). Elsewhere, and for the last 15 bytes, memchr.
class NewlineFinder {
public:
  explicit NewlineFinder(std::string_view text) : text_(text) {}
  /// The position of the first '\n' at or after `from` (not less than any earlier call's
  /// `from`), or the text's size when there is none.
  std::size_t next(std::size_t from) {
    const std::size_t size = text_.size();
#ifdef __SSE2__
    for (;;) {
      if (scanned_ && from >= block_ && from < block_ + 16) {  // in the block in hand
        const unsigned left = mask_ & (~0u << (from - block_));
        if (left != 0) return block_ + static_cast<std::size_t>(__builtin_ctz(left));
        from = block_ + 16;
      }
      if (from + 16 > size) break;
      const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(text_.data() + from));
      mask_ = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(bytes, _mm_set1_epi8('\n'))));
      block_ = from;
      scanned_ = true;
    }
#endif
    if (from >= size) return size;
    const void* hit = std::memchr(text_.data() + from, '\n', size - from);
    return hit ? static_cast<std::size_t>(static_cast<const char*>(hit) - text_.data()) : size;
  }

private:
  std::string_view text_;
  std::size_t block_ = 0;  // once scanned_: bytes [block_, block_ + 16) gave mask_
  unsigned mask_ = 0;
  bool scanned_ = false;
};

/// Walks `text` line by line (LF or CRLF), counting lines from 1.
class LineScanner {
public:
  explicit LineScanner(std::string_view text) : text_(text), newlines_(text) {}
  /// Moves to the next line; false at the end of the text.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = newlines_.next(pos_);
    line = text_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  std::size_t number() const { return number_; }

private:
  std::string_view text_;
  NewlineFinder newlines_;
  std::size_t pos_ = 0;
  std::size_t number_ = 0;
};

/// Splits `line` at spaces and tabs into `tokens` (views into line), dropping a '#'
/// comment when `comments` is set.
inline void split_tokens(std::string_view line, std::vector<std::string_view>& tokens,
                         bool comments = true) {
  tokens.clear();
  if (comments) {
    std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
  }
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

// In-place parsing for the readers' fast paths (OBJ `v`/`f`, OFF vertex and face lines):
// no token vector, and false, having changed nothing, at anything not taken in full, so
// that the reader hands the line to its general path, which gives the error.

inline bool blank(char c) { return c == ' ' || c == '\t'; }

/// How many lines of `text` start with `a` and then a blank, and how many with `b` (OBJ's
/// "v " and "f "): a line starts at the text's start and after each '\n'. With AVX2 it
/// tests 32 positions at once for a '\n' followed by the letter and a blank, without a
/// branch per line: on a 1M-vertex OBJ (107 MB, 3M lines) 17 ms against 31 for the walk
/// from newline to newline that counts the rest (and all of it elsewhere). Sixteen
/// positions at once (SSE2) were no faster than that walk.
inline std::array<std::size_t, 2> count_keyed_lines(std::string_view text, char a, char b) {
  std::array<std::size_t, 2> counts{0, 0};
  const char* d = text.data();
  const std::size_t n = text.size();
  const auto line_at = [&](std::size_t p) {  // the line starting at p
    if (p + 1 < n && blank(d[p + 1])) counts[0] += d[p] == a, counts[1] += d[p] == b;
  };
  line_at(0);
  std::size_t i = 0;  // positions below i are tested for a '\n'
#ifdef __AVX2__
  const __m256i newline = _mm256_set1_epi8('\n'), ka = _mm256_set1_epi8(a), kb = _mm256_set1_epi8(b);
  const __m256i space = _mm256_set1_epi8(' '), tab = _mm256_set1_epi8('\t');
  for (; i + 34 <= n; i += 32) {
    const auto at = [d, i](std::size_t k) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(d + i + k)); };
    const __m256i line = at(0), key = at(1), gap = at(2);
    const __m256i starts = _mm256_and_si256(_mm256_cmpeq_epi8(line, newline),
                                            _mm256_or_si256(_mm256_cmpeq_epi8(gap, space), _mm256_cmpeq_epi8(gap, tab)));
    counts[0] += static_cast<std::size_t>(__builtin_popcount(
        static_cast<unsigned>(_mm256_movemask_epi8(_mm256_and_si256(starts, _mm256_cmpeq_epi8(key, ka))))));
    counts[1] += static_cast<std::size_t>(__builtin_popcount(
        static_cast<unsigned>(_mm256_movemask_epi8(_mm256_and_si256(starts, _mm256_cmpeq_epi8(key, kb))))));
  }
#endif
  NewlineFinder newlines(text);  // the rest (all of it without AVX2): newline to newline
  for (std::size_t p = newlines.next(i); p < n; p = newlines.next(p + 1)) line_at(p + 1);
  return counts;
}

inline const char* skip_blanks(const char* p, const char* end) {
  while (p < end && blank(*p)) ++p;
  return p;
}

/// A finite number at p that ends at a blank or the line's end, read as parse_finite
/// would (std::from_chars; a leading '+' is left to the general path).
inline bool fast_number(const char*& p, const char* end, double& value) {
  const auto [next, ec] = std::from_chars(p, end, value, std::chars_format::general);
  if (ec != std::errc() || next == p || (next < end && !blank(*next)) || !std::isfinite(value)) return false;
  p = next;
  return true;
}

/// `count` numbers (fast_number) from p, then nothing but blanks to `end`.
inline bool fast_numbers_to_end(const char* p, const char* end, double* out, int count) {
  for (int k = 0; k < count; ++k) {
    p = skip_blanks(p, end);
    if (!fast_number(p, end, out[k])) return false;
  }
  return skip_blanks(p, end) == end;
}

/// std::from_chars(p, end, value) in base 10, the same result for any text. A number of up
/// to 7 digits is read a word at a time (word_digits.h) where 8 bytes from its start can be
/// loaded: up to `readable` (>= end: the rest of the file past a line, which the number
/// does not take in). Others of up to 18 digits (every index a mesh file holds) go in a
/// plain loop, which costs less than the library's overflow-checked one; longer ones to
/// std::from_chars. On a 1M-vertex OBJ's 6M face indices (with the line search) the word
/// takes 34 ms where the loop took 38.
inline std::from_chars_result decimal(const char* p, const char* end, long long& value,
                                      const char* readable = nullptr) {
  const char* q = p + (p < end && *p == '-');
  const char* const digits = q;
  if ((readable ? readable : end) - q >= 8) {
    const std::uint64_t word = load_word(q);
    const int n = std::min<int>(leading_digits(word), static_cast<int>(std::min<std::ptrdiff_t>(end - q, 8)));
    if (n == 0) return {p, std::errc::invalid_argument};
    if (n < 8) {
      const long long v = digits_value(word, n);
      value = digits != p ? -v : v;
      return {q + n, std::errc()};
    }
  }
  std::uint64_t v = 0;
  while (q < end && q - digits < 18 && static_cast<unsigned char>(*q - '0') < 10)
    v = v * 10 + static_cast<unsigned char>(*q++ - '0');
  if (q == digits) return {p, std::errc::invalid_argument};
  if (q < end && static_cast<unsigned char>(*q - '0') < 10) return std::from_chars(p, end, value);
  value = digits != p ? -static_cast<long long>(v) : static_cast<long long>(v);
  return {q, std::errc()};
}

/// fast_numbers_to_end, or the same up to a `#` comment after the numbers: the parallel
/// readers' vertex lines (the comment is looked for only when the plain form fails).
inline bool numbers_before_comment(const char* p, const char* end, double* out, int count) {
  if (fast_numbers_to_end(p, end, out, count)) return true;
  const auto* hash = static_cast<const char*>(std::memchr(p, '#', static_cast<std::size_t>(end - p)));
  return hash && fast_numbers_to_end(p, hash, out, count);
}

/// An integer at p that ends at a blank or the line's end.
inline bool fast_integer(const char*& p, const char* end, long long& value) {
  const auto [next, ec] = decimal(p, end, value);
  if (ec != std::errc() || next == p || (next < end && !blank(*next))) return false;
  p = next;
  return true;
}

/// Whether the line holds nothing to read: blanks, then its end or a `#` comment.
inline bool nothing_to_read(std::string_view line) {
  const char* p = skip_blanks(line.data(), line.data() + line.size());
  return p == line.data() + line.size() || *p == '#';
}

/// "file:line" for messages.
inline std::string place(const std::string& file, std::size_t line) {
  return file + ":" + std::to_string(line);
}

/// Parses a token as a finite number or throws InputError naming file, line and `what`.
inline double number_or_throw(std::string_view token, const std::string& file, std::size_t line,
                              const char* what) {
  double value;
  if (!parse_finite(token, value))
    throw InputError(At{place(file, line)}, std::string(what) + " '" + std::string(token) +
                     "' is not a finite number");
  return value;
}

}  // namespace ffd
