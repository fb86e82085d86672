// Line and token scanning shared by the text mesh readers.
#pragma once

#include <charconv>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "common/errors.h"
#include "common/numbers.h"

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

/// An integer at p that ends at a blank or the line's end.
inline bool fast_integer(const char*& p, const char* end, long long& value) {
  const auto [next, ec] = std::from_chars(p, end, value);
  if (ec != std::errc() || next == p || (next < end && !blank(*next))) return false;
  p = next;
  return true;
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
