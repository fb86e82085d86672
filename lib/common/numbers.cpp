#include "common/numbers.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>

namespace ffd {

char* format_number_to(char* first, double x) {
  if (x == 0.0) x = 0.0;  // -0 prints as 0: the sign of zero carries no geometry
  auto [end, ec] = std::to_chars(first, first + kNumberChars, x);
  (void)ec;  // 32 bytes always suffice for a double
  return end;
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
