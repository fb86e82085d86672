// Base64 (RFC 4648's alphabet, padded), as VTK XML files and glTF data URIs hold binary
// data.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace ffd {

/// Decoded bytes. Not zeroed first: a large array is decoded straight into fresh pages.
struct DecodedBytes {
  std::unique_ptr<char[]> data;
  std::size_t size = 0;
  std::string_view view() const { return {data.get(), size}; }
};

/// Decodes up to `groups` groups of four alphabet characters at `in` into 3 bytes each at
/// `out`; returns how many, stopping before the first group with any other character
/// (a space, '=').
std::size_t decode_base64_groups(const char* in, std::size_t groups, char* out);

/// Appends `data`'s base64 encoding, padded, to `out`.
void append_base64(std::string_view data, std::string& out);

/// Decodes text made of one or more padded base64 runs (VTK encodes an array's header and
/// its data apart), with whitespace allowed between characters, into `out`. Returns
/// std::string_view::npos, or the offset in `text` of the first character that is not
/// valid there. Long runs of whole groups are decoded by every thread in fixed blocks:
/// the same bytes for any thread count.
std::size_t decode_base64(std::string_view text, DecodedBytes& out);

}  // namespace ffd
