// Line and token scanning shared by the text mesh readers.
#pragma once

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "common/errors.h"
#include "common/numbers.h"

namespace ffd {

/// Walks `text` line by line (LF or CRLF), counting lines from 1.
class LineScanner {
public:
  explicit LineScanner(std::string_view text) : text_(text) {}
  /// Moves to the next line; false at the end of the text.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  std::size_t number() const { return number_; }

private:
  std::string_view text_;
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
