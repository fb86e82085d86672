// The text encodings the text readers take: ASCII and UTF-8 (a leading UTF-8 byte-order
// mark is skipped). UTF-16 and UTF-32 are refused by name rather than read as garbage.
#pragma once

#include <string>
#include <string_view>

namespace ffd {

/// The name of the wide encoding `bytes` begins in ("UTF-16LE", "UTF-32BE", ...): by its
/// byte-order mark, else by the NUL bytes that ASCII text interleaves in it (the first
/// four bytes); empty for ASCII or UTF-8.
std::string wide_text_encoding(std::string_view bytes);

/// `bytes` without a leading UTF-8 byte-order mark.
std::string_view without_utf8_bom(std::string_view bytes);

/// Throws InputError naming `path` if `bytes` is UTF-16 or UTF-32 text.
void refuse_wide_text(std::string_view bytes, const std::string& path);

}  // namespace ffd
