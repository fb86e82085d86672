#include "render/png_io.h"

#include <png.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "common/errors.h"

// libpng reports an error by calling our error function, which must not return: it
// longjmps to the setjmp of the function that called libpng. The longjmp skips every
// frame in between without running destructors, so the functions that hold a setjmp
// (encode, read_header, decode) and the callbacks keep no C++ object with a destructor;
// everything that has one (the Image, an exception from the stream) lives in their
// callers, which turn a failed call into a C++ exception.

namespace ffd {
namespace {

// What the callbacks share with the code that called libpng.
struct PngState {
  const std::uint8_t* data = nullptr;  // reading: the bytes and how far libpng has read
  std::size_t size = 0;
  std::size_t pos = 0;
  std::ostream* os = nullptr;          // writing
  std::exception_ptr stream_error;     // what the stream threw, passed on after the longjmp
  char message[256] = {};              // libpng's error message
};

PngState& state_of_error(png_structp png) { return *static_cast<PngState*>(png_get_error_ptr(png)); }
PngState& state_of_io(png_structp png) { return *static_cast<PngState*>(png_get_io_ptr(png)); }

[[noreturn]] void on_error(png_structp png, png_const_charp message) {
  PngState& state = state_of_error(png);
  std::snprintf(state.message, sizeof state.message, "%s", message ? message : "unknown error");
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}  // benign: a bad ancillary chunk is skipped

void read_bytes(png_structp png, png_bytep out, std::size_t count) {
  PngState& state = state_of_io(png);
  if (count > state.size - state.pos) png_error(png, "the data ends early");
  std::memcpy(out, state.data + state.pos, count);
  state.pos += count;
}

void write_bytes(png_structp png, png_bytep data, std::size_t count) {
  PngState& state = state_of_io(png);
  bool threw = false;
  try {
    state.os->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(count));
  } catch (...) {
    state.stream_error = std::current_exception();
    threw = true;
  }
  if (threw) png_error(png, "the stream failed");  // outside the handler: longjmp leaves no catch
}

void flush_nothing(png_structp) {}  // the caller flushes its stream

// libpng's structs, destroyed whichever way the caller leaves.
struct ReadStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~ReadStructs() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};
struct WriteStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~WriteStructs() { png_destroy_write_struct(&png, info ? &info : nullptr); }
};

// Writes the whole PNG; false on a libpng error (its message in the state).
bool encode(png_structp png, png_infop info, const Image& image) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 6);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_ALL_FILTERS);
  png_write_info(png, info);
  const std::size_t row_bytes = std::size_t(3) * static_cast<std::size_t>(image.width);
  for (int y = 0; y < image.height; ++y) png_write_row(png, image.rgb.data() + row_bytes * static_cast<std::size_t>(y));
  png_write_end(png, nullptr);
  return true;
}

// A PNG's size, from its header.
struct PngHeader {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t bits_per_pixel = 0;  // in the file, before any conversion
};

// Reads the signature's rest and the chunks up to the first IDAT; false on a libpng error.
bool read_header(png_structp png, png_infop info, PngHeader* header) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  header->width = png_get_image_width(png, info);
  header->height = png_get_image_height(png, info);
  header->bits_per_pixel = std::uint32_t(png_get_bit_depth(png, info)) * png_get_channels(png, info);
  return true;
}

// Decodes the image data to 8-bit RGB into rgb (3 · width · height bytes) and reads the
// chunks after it, to IEND; false on a libpng error.
bool decode(png_structp png, png_infop info, const PngHeader* header, std::uint8_t* rgb) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_expand(png);  // palette to RGB, grey below 8 bits to 8, tRNS to alpha
  png_set_strip_16(png);
  png_set_gray_to_rgb(png);
  png_set_strip_alpha(png);
  const int passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const std::size_t row_bytes = std::size_t(3) * header->width;
  if (png_get_rowbytes(png, info) != row_bytes || png_get_channels(png, info) != 3 ||
      png_get_bit_depth(png, info) != 8)
    png_error(png, "cannot convert the pixels to 8-bit RGB");
  for (int pass = 0; pass < passes; ++pass)
    for (std::uint32_t y = 0; y < header->height; ++y) png_read_row(png, rgb + row_bytes * y, nullptr);
  png_read_end(png, nullptr);
  return true;
}

// The bytes of all IDAT chunks in data[0, size), as far as the data goes.
std::uint64_t image_data_bytes(const std::uint8_t* data, std::size_t size) {
  std::uint64_t total = 0;
  for (std::size_t pos = 8; size - pos >= 8;) {
    const std::uint32_t length = png_get_uint_32(data + pos);
    if (std::memcmp(data + pos + 4, "IDAT", 4) == 0) total += std::min<std::uint64_t>(length, size - pos - 8);
    if (length > size - pos - 8 || size - pos - 8 - length < 4) break;
    pos += 12 + std::size_t(length);
  }
  return total;
}

// Throws the error for a failed libpng call while reading `name`.
[[noreturn]] void throw_corrupt(const PngState& state, const std::string& name) {
  throw InputError(At{name}, std::string("corrupt PNG: ") + state.message);
}

}  // namespace

void write_png(std::ostream& os, const Image& image) {
  if (image.width <= 0 || image.height <= 0)
    throw InputError("cannot write a PNG of " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                     " pixels");
  const std::uint64_t pixels = std::uint64_t(image.width) * std::uint64_t(image.height);
  if (pixels > kMaxPngPixels || std::uint32_t(image.width) > kMaxPngSide || std::uint32_t(image.height) > kMaxPngSide)
    throw InputError("cannot write a PNG of " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                     " pixels: at most 2^28 pixels and 2^24 a side");
  if (image.rgb.size() != 3 * pixels) throw InputError("the image's pixel array does not match its size");
  PngState state;
  state.os = &os;
  WriteStructs s;
  s.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, on_error, on_warning);
  if (s.png) s.info = png_create_info_struct(s.png);
  if (!s.info) throw IoError("cannot encode a PNG: out of memory");
  png_set_write_fn(s.png, &state, write_bytes, flush_nothing);
  png_set_user_limits(s.png, kMaxPngSide, kMaxPngSide);
  if (encode(s.png, s.info, image)) return;
  if (state.stream_error) std::rethrow_exception(state.stream_error);
  throw IoError(std::string("cannot encode a PNG: ") + state.message);
}

Image read_png(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(At{path}, "no such file");
  if (std::filesystem::is_directory(path, ec)) throw InputError(At{path}, "is a folder, not a PNG file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(At{path}, std::string("cannot open for reading: ") + std::strerror(errno));
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError(At{path}, "cannot read");
  return read_png_memory(bytes.data(), bytes.size(), path);
}

Image read_png_memory(const std::uint8_t* data, std::size_t size, const std::string& name) {
  constexpr std::size_t kSignature = 8;
  if (size < kSignature || png_sig_cmp(data, 0, kSignature) != 0) throw InputError(At{name}, "not a PNG file");
  PngState state;
  state.data = data;
  state.size = size;
  state.pos = kSignature;
  ReadStructs s;
  s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, on_error, on_warning);
  if (s.png) s.info = png_create_info_struct(s.png);
  if (!s.info) throw IoError(At{name}, "cannot decode: out of memory");
  png_set_read_fn(s.png, &state, read_bytes);
  png_set_sig_bytes(s.png, kSignature);
  // libpng's own limit per side (1,000,000) would call a large valid image corrupt; ours
  // comes after the header, with its own message.
  png_set_user_limits(s.png, 0x7fffffff, 0x7fffffff);
  PngHeader header;
  if (!read_header(s.png, s.info, &header)) throw_corrupt(state, name);
  const std::uint64_t pixels = std::uint64_t(header.width) * header.height;
  if (pixels > kMaxPngPixels || header.width > kMaxPngSide || header.height > kMaxPngSide)
    throw InputError(At{name}, "the image is " + std::to_string(header.width) + " x " + std::to_string(header.height) +
                                   " pixels; at most 2^28 pixels and 2^24 a side are read");
  // Deflate makes at most 1032 bytes of one (a 258-byte match costs at least two bits):
  // a header that claims more pixels than its data can hold is refused before the image
  // is allocated, so a small corrupt file never costs much memory.
  const std::uint64_t raw_bytes = (pixels * header.bits_per_pixel + 7) / 8;
  const std::uint64_t data_bytes = image_data_bytes(data, size);
  if (raw_bytes > 1032 * data_bytes + 1032)
    throw InputError(At{name}, "corrupt PNG: " + std::to_string(data_bytes) + " bytes of image data cannot hold " +
                                   std::to_string(header.width) + " x " + std::to_string(header.height) + " pixels");
  Image image(static_cast<int>(header.width), static_cast<int>(header.height));
  if (!decode(s.png, s.info, &header, image.rgb.data())) throw_corrupt(state, name);
  return image;
}

bool has_png_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png";
}

}  // namespace ffd
