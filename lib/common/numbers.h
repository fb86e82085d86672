// Exact text forms of numbers: shortest round-trip formatting and strict parsing.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace ffd {

/// Appends the shortest decimal form of x that reads back to the same double, as
/// std::to_chars does (at most 17 significant digits, except that a whole number below
/// 1e23 may be written out as its exact integer). Non-finite values are
/// written as "nan"/"inf" so that a bug never hides as a plausible number.
void append_number(std::string& out, double x);

/// Writes append_number's text of x at `first` and returns the end; for writers that format
/// into their own buffer. It may write anywhere in kNumberChars characters from `first`
/// (past the end it returns), so the buffer needs that room.
constexpr std::size_t kNumberChars = 48;
char* format_number_to(char* first, double x);

/// The shortest round-trip text of x.
std::string format_number(double x);

/// A duration for people: "0.153 ms" below a millisecond, "12.5 ms" above.
std::string format_ms(double ms);

/// n with thousands separators: 1234567 -> "1,234,567", for human-readable summaries.
std::string format_count(std::size_t n);

/// Parses all of `text` as a finite double, correctly rounded (std::from_chars).
/// Returns false for empty text, trailing characters, nan, inf or overflow.
bool parse_finite(std::string_view text, double& value);

/// Parses all of `text` as a (possibly negative) integer. False on any other text.
bool parse_integer(std::string_view text, long long& value);

}  // namespace ffd
