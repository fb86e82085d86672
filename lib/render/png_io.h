// PNG files through libpng: a deterministic 8-bit RGB writer and a reader that takes any
// PNG (palette, grey, 16-bit, alpha, interlaced) to 8-bit RGB and turns every malformed
// byte sequence into an InputError.
#pragma once

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>

#include "render/image.h"

namespace ffd {

/// The most pixels, and the most pixels a side, that write_png and the readers accept.
inline constexpr std::uint64_t kMaxPngPixels = std::uint64_t(1) << 28;
inline constexpr std::uint32_t kMaxPngSide = std::uint32_t(1) << 24;

/// Writes `image` as an 8-bit RGB PNG, not interlaced, with no ancillary chunk (no time,
/// text or gamma): zlib level 6 and libpng's adaptive filter choice per row, both set
/// explicitly, so the same image always gives the same bytes (with one libpng and zlib).
/// Write failures are the stream's: a stream that throws has its exception passed on,
/// one that does not is left in a failed state for the caller to check.
/// \throw InputError if the image has no pixel, more than kMaxPngPixels or more than
/// kMaxPngSide a side, or rgb is not 3 · width · height bytes.
/// \throw IoError if libpng fails otherwise (out of memory).
void write_png(std::ostream& os, const Image& image);

/// Whether `path` ends in .png (any case): what the picture outputs are checked for.
bool has_png_extension(const std::string& path);

/// Reads the PNG file at `path` (see read_png_memory).
/// \throw InputError "path: no such file" if there is no file, "path: cannot open for
/// reading: reason" if it cannot be opened, and read_png_memory's errors.
/// \throw IoError "path: cannot read" if reading fails after the open.
Image read_png(const std::string& path);

/// Decodes the PNG in data[0, size) to 8-bit RGB: palettes expanded, grey copied to the
/// three channels, 16-bit samples cut to their high byte, alpha dropped (not composited).
/// `name` is the place the errors name. Any byte sequence gives an image or an error.
/// \throw InputError "name: not a PNG file" (no PNG signature), "name: corrupt PNG:
/// libpng's message" (a truncated or malformed file, a CRC error in a critical chunk) or
/// "name: the image is W x H pixels; ..." past kMaxPngPixels or kMaxPngSide.
Image read_png_memory(const std::uint8_t* data, std::size_t size, const std::string& name);

}  // namespace ffd
