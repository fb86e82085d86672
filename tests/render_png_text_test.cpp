// The renderer's PNG files and bitmap text: write_png round trips and is deterministic,
// the readers take every PNG colour type and bit depth (built here by a small stored-
// deflate encoder, interlaced too) and refuse truncated, random and mutated bytes with
// InputError; draw_text clips, measures as text.h says, and its glyphs differ.
#include <gtest/gtest.h>

#include <climits>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <set>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include "common/errors.h"
#include "render/image.h"
#include "render/png_io.h"
#include "render/text.h"
#include "test_meshes.h"

namespace ffd {
namespace {

// A deterministic picture with gradients, flat areas and noise.
Image pattern(int width, int height, std::uint32_t seed = 7) {
  std::mt19937 rng(seed);
  Image image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const auto noise = static_cast<std::uint8_t>(rng());
      image.set(x, y, {static_cast<std::uint8_t>(x * 7), static_cast<std::uint8_t>(y < height / 2 ? 40 : y * 5), noise});
    }
  return image;
}

std::string png_bytes(const Image& image) {
  std::ostringstream os;
  write_png(os, image);
  return os.str();
}

Image read_bytes(const std::string& bytes, const std::string& name = "x.png") {
  return read_png_memory(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), name);
}

// The message of the InputError that reading `bytes` throws ("" if it throws none).
std::string read_error(const std::string& bytes) {
  try {
    read_bytes(bytes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// --- A minimal PNG encoder (stored deflate blocks, filter 0), for the reader's tests ---

std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return ~c;
}

void put32(std::string& s, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) s += static_cast<char>(v >> shift & 0xff);
}

std::string chunk(const std::string& type, const std::string& data) {
  std::string out;
  put32(out, static_cast<std::uint32_t>(data.size()));
  out += type + data;
  put32(out, crc32(type + data));
  return out;
}

std::string zlib_stored(const std::string& raw) {
  std::string out = "\x78\x01";
  std::size_t pos = 0;
  do {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - pos);
    out += static_cast<char>(pos + n == raw.size() ? 1 : 0);
    out += static_cast<char>(n & 0xff);
    out += static_cast<char>(n >> 8);
    out += static_cast<char>(~n & 0xff);
    out += static_cast<char>((~n >> 8) & 0xff);
    out += raw.substr(pos, n);
    pos += n;
  } while (pos < raw.size());
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  put32(out, b << 16 | a);
  return out;
}

struct TestPng {
  int width = 0, height = 0;
  int color_type = 2;  // 0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA
  int depth = 8;
  bool interlaced = false;
  std::function<std::vector<std::uint32_t>(int x, int y)> samples;  // one per channel
  std::string palette;  // PLTE data, for colour type 3
  std::string trns;     // tRNS data, if any
};

int channels(int color_type) { return color_type == 2 ? 3 : color_type == 4 ? 2 : color_type == 6 ? 4 : 1; }

// The filtered (filter 0) rows of the sub-image at (x0 + i·dx, y0 + j·dy).
std::string pass_rows(const TestPng& p, int x0, int y0, int dx, int dy) {
  std::string raw;
  for (int y = y0; y < p.height; y += dy) {
    if (x0 >= p.width) break;
    raw += '\0';
    std::uint32_t acc = 0;
    int bits = 0;
    for (int x = x0; x < p.width; x += dx)
      for (std::uint32_t v : p.samples(x, y))
        for (int k = p.depth - 1; k >= 0; --k) {
          acc = acc << 1 | (v >> k & 1);
          if (++bits == 8) raw += static_cast<char>(acc), acc = 0, bits = 0;
        }
    if (bits > 0) raw += static_cast<char>(acc << (8 - bits));
  }
  return raw;
}

std::string encode(const TestPng& p) {
  std::string ihdr;
  put32(ihdr, static_cast<std::uint32_t>(p.width));
  put32(ihdr, static_cast<std::uint32_t>(p.height));
  ihdr += static_cast<char>(p.depth);
  ihdr += static_cast<char>(p.color_type);
  ihdr += std::string("\0\0", 2) + static_cast<char>(p.interlaced ? 1 : 0);
  std::string raw;
  if (!p.interlaced) {
    raw = pass_rows(p, 0, 0, 1, 1);
  } else {
    const int adam7[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4}, {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
    for (const auto& a : adam7) raw += pass_rows(p, a[0], a[1], a[2], a[3]);
  }
  std::string out = "\x89PNG\r\n\x1a\n" + chunk("IHDR", ihdr);
  if (!p.palette.empty()) out += chunk("PLTE", p.palette);
  if (!p.trns.empty()) out += chunk("tRNS", p.trns);
  const std::string z = zlib_stored(raw);
  out += chunk("IDAT", z.substr(0, z.size() / 2)) + chunk("IDAT", z.substr(z.size() / 2));  // two IDATs
  return out + chunk("IEND", "");
}

// The chunk types of a PNG, in order.
std::vector<std::string> chunk_types(const std::string& png) {
  std::vector<std::string> types;
  for (std::size_t pos = 8; pos + 12 <= png.size();) {
    const std::uint32_t length = std::uint32_t(std::uint8_t(png[pos])) << 24 | std::uint32_t(std::uint8_t(png[pos + 1])) << 16 |
                                 std::uint32_t(std::uint8_t(png[pos + 2])) << 8 | std::uint8_t(png[pos + 3]);
    types.push_back(png.substr(pos + 4, 4));
    pos += 12 + length;
  }
  return types;
}

// Re-computes the CRC of every chunk (after a mutation), as far as the lengths allow.
void fix_crcs(std::string& png) {
  for (std::size_t pos = 8; pos + 12 <= png.size();) {
    const std::uint32_t length = std::uint32_t(std::uint8_t(png[pos])) << 24 | std::uint32_t(std::uint8_t(png[pos + 1])) << 16 |
                                 std::uint32_t(std::uint8_t(png[pos + 2])) << 8 | std::uint8_t(png[pos + 3]);
    if (length > png.size() - pos - 12) return;
    std::string crc;
    put32(crc, crc32(png.substr(pos + 4, 4 + length)));
    png.replace(pos + 8 + length, 4, crc);
    pos += 12 + length;
  }
}

// --- write_png and the readers ---

TEST(RenderPng, RoundTripKeepsEveryPixel) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {37, 23}, {300, 2}, {3, 200}}) {
    const Image image = pattern(w, h);
    const Image back = read_bytes(png_bytes(image));
    EXPECT_EQ(back.width, w);
    EXPECT_EQ(back.height, h);
    EXPECT_EQ(back.rgb, image.rgb) << w << " x " << h;
  }
}

TEST(RenderPng, WriteIsDeterministicAndPlain) {
  const Image image = pattern(64, 48);
  const std::string first = png_bytes(image);
  EXPECT_EQ(png_bytes(image), first);
  EXPECT_EQ(png_bytes(pattern(64, 48)), first);
  EXPECT_NE(png_bytes(pattern(64, 48, 8)), first);
  // IHDR: 8-bit RGB, not interlaced; then only image data, no time, text or gamma chunk.
  ASSERT_GT(first.size(), 33u);
  EXPECT_EQ(first.substr(12, 4), "IHDR");
  EXPECT_EQ(first[24], 8);
  EXPECT_EQ(first[25], 2);
  EXPECT_EQ(first[28], 0);
  for (const std::string& type : chunk_types(first)) EXPECT_TRUE(type == "IHDR" || type == "IDAT" || type == "IEND") << type;
  EXPECT_EQ(chunk_types(first).back(), "IEND");
}

TEST(RenderPng, WriteRefusesAnEmptyImageAndPassesOnTheStreamsFailure) {
  std::ostringstream os;
  EXPECT_THROW(write_png(os, Image()), InputError);
  Image bad(4, 4);
  bad.rgb.pop_back();
  EXPECT_THROW(write_png(os, bad), InputError);

  struct FailingBuffer : std::streambuf {
    int_type overflow(int_type) override { return traits_type::eof(); }
    std::streamsize xsputn(const char*, std::streamsize) override { return 0; }
  } buffer;
  std::ostream quiet(&buffer);
  EXPECT_NO_THROW(write_png(quiet, pattern(8, 8)));
  EXPECT_FALSE(quiet.good());
  std::ostream throwing(&buffer);
  throwing.exceptions(std::ios::badbit);
  EXPECT_THROW(write_png(throwing, pattern(8, 8)), std::ios_base::failure);
}

// Every colour type and bit depth, plain and interlaced, to the expected 8-bit RGB.
TEST(RenderPng, ReadsEveryColourTypeAndDepth) {
  std::string palette;
  for (int i = 0; i < 256; ++i) palette += std::string{char(i), char(255 - i), char(i * 3)};
  int cases = 0;
  for (bool interlaced : {false, true}) {
    for (const auto& [color_type, depth] : std::vector<std::pair<int, int>>{
             {0, 1}, {0, 2}, {0, 4}, {0, 8}, {0, 16}, {2, 8}, {2, 16}, {3, 1}, {3, 2}, {3, 4}, {3, 8}, {4, 8}, {4, 16}, {6, 8}, {6, 16}}) {
      TestPng p;
      p.width = 13;
      p.height = 11;
      p.color_type = color_type;
      p.depth = depth;
      p.interlaced = interlaced;
      const std::uint32_t max = (1u << depth) - 1;
      p.samples = [&](int x, int y) {
        std::vector<std::uint32_t> s;
        for (int c = 0; c < channels(p.color_type); ++c) s.push_back(std::uint32_t(x * 37 + y * 101 + c * 53) * 2654435761u % (max + 1));
        return s;
      };
      if (color_type == 3) p.palette = palette.substr(0, 3 * (max + 1));
      if (color_type == 3) p.trns = std::string("\x10\x80", 2);  // alpha for entries 0 and 1, dropped
      if (color_type == 0) p.trns = std::string("\0\1", 2);       // grey 1 transparent, dropped
      const Image image = read_bytes(encode(p));
      ASSERT_EQ(image.width, 13);
      ASSERT_EQ(image.height, 11);
      for (int y = 0; y < p.height; ++y)
        for (int x = 0; x < p.width; ++x) {
          const std::vector<std::uint32_t> s = p.samples(x, y);
          auto to8 = [&](std::uint32_t v) { return static_cast<std::uint8_t>(p.depth == 16 ? v >> 8 : v * 255 / max); };
          Rgb expected;
          if (color_type == 3) {
            expected = {std::uint8_t(palette[3 * s[0]]), std::uint8_t(palette[3 * s[0] + 1]), std::uint8_t(palette[3 * s[0] + 2])};
          } else if (color_type == 0 || color_type == 4) {
            expected = {to8(s[0]), to8(s[0]), to8(s[0])};
          } else {
            expected = {to8(s[0]), to8(s[1]), to8(s[2])};
          }
          ASSERT_EQ(image.at(x, y), expected) << "type " << color_type << " depth " << depth << " interlaced "
                                              << interlaced << " at " << x << ", " << y;
        }
      ++cases;
    }
  }
  EXPECT_EQ(cases, 30);
}

TEST(RenderPng, ReadPngNamesTheFile) {
  const std::string dir = test::temp_folder("render_png");
  const std::string path = dir + "/picture.png";
  {
    std::ofstream os(path, std::ios::binary);
    write_png(os, pattern(20, 10));
  }
  EXPECT_EQ(read_png(path).rgb, pattern(20, 10).rgb);
  auto message = [](const std::string& p) -> std::string {
    try {
      read_png(p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(message(dir + "/missing.png"), dir + "/missing.png: no such file");
  EXPECT_EQ(message(dir), dir + ": is a folder, not a PNG file");
  std::ofstream(dir + "/text.png") << "P3\n1 1\n255\n0 0 0\n";
  EXPECT_EQ(message(dir + "/text.png"), dir + "/text.png: not a PNG file");
  const std::string bytes = png_bytes(pattern(20, 10));
  std::ofstream(dir + "/cut.png", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_EQ(message(dir + "/cut.png").rfind(dir + "/cut.png: corrupt PNG: ", 0), 0u) << message(dir + "/cut.png");
}

TEST(RenderPng, RefusesAbsurdSizes) {
  TestPng p;
  p.width = 1 << 15;
  p.height = (1 << 13) + 1;  // 2^28 + 2^15 pixels
  p.color_type = 0;
  p.samples = [](int, int) { return std::vector<std::uint32_t>{0}; };
  std::string header = "\x89PNG\r\n\x1a\n";
  std::string ihdr;
  put32(ihdr, static_cast<std::uint32_t>(p.width));
  put32(ihdr, static_cast<std::uint32_t>(p.height));
  ihdr += std::string("\x08\0\0\0\0", 5);
  const std::string png = header + chunk("IHDR", ihdr) + chunk("IDAT", zlib_stored("")) + chunk("IEND", "");
  EXPECT_EQ(read_error(png), "x.png: the image is 32768 x 8193 pixels; at most 2^28 pixels and 2^24 a side are read");
  // A size within the limits but with no data behind it fails on the data, cheaply.
  std::string small = ihdr;
  small[7] = 0, small[6] = 0x10;  // height 4096: 2^27 pixels
  EXPECT_EQ(read_error(header + chunk("IHDR", small) + chunk("IDAT", zlib_stored("")) + chunk("IEND", "")).rfind("x.png: corrupt PNG: ", 0), 0u);
}

TEST(RenderPng, EveryPrefixOfAValidFileIsRefused) {
  for (bool interlaced : {false, true}) {
    TestPng p;
    p.width = 9;
    p.height = 7;
    p.interlaced = interlaced;
    p.samples = [](int x, int y) { return std::vector<std::uint32_t>{std::uint32_t(x * 20), std::uint32_t(y * 30), 7}; };
    for (const std::string& png : {png_bytes(pattern(16, 16)), encode(p)}) {
      ASSERT_NO_THROW(read_bytes(png));
      for (std::size_t n = 0; n < png.size(); ++n) {
        const std::string cut = png.substr(0, n);
        const std::string message = read_error(cut);
        EXPECT_TRUE(message.rfind(n < 8 ? "x.png: not a PNG file" : "x.png: corrupt PNG: ", 0) == 0)
            << "prefix of " << n << " of " << png.size() << " bytes: \"" << message << "\"";
      }
    }
  }
}

TEST(RenderPng, RandomBytesAreRefused) {
  std::mt19937_64 rng(20240611);
  const std::string signature = "\x89PNG\r\n\x1a\n";
  for (int i = 0; i < 2000; ++i) {
    std::string bytes(rng() % 300, '\0');
    for (char& c : bytes) c = static_cast<char>(rng());
    if (i % 2 == 1) bytes = signature + bytes;  // past the signature check
    if (i % 4 == 3) bytes = signature + chunk("IHDR", bytes.substr(8, 13)) + bytes.substr(8);
    EXPECT_NE(read_error(bytes), "") << "buffer " << i;
  }
}

// Mutated valid files, their CRCs made right again so the mutation reaches the chunk's
// reader and the decompressor: an image or an InputError, never anything else.
TEST(RenderPng, MutatedFilesGiveAnImageOrInputError) {
  TestPng p;
  p.width = 12;
  p.height = 9;
  p.color_type = 3;
  p.depth = 4;
  p.interlaced = true;
  p.palette = std::string(48, '\x55');
  p.samples = [](int x, int y) { return std::vector<std::uint32_t>{std::uint32_t(x + y) % 16}; };
  const std::vector<std::string> seeds = {png_bytes(pattern(24, 16)), encode(p)};
  std::mt19937_64 rng(99);
  int accepted = 0, refused = 0;
  for (int i = 0; i < 3000; ++i) {
    std::string bytes = seeds[i % seeds.size()];
    for (int k = 1 + int(rng() % 4); k > 0; --k) {
      const std::size_t at = 8 + rng() % (bytes.size() - 8);
      switch (rng() % 3) {
        case 0: bytes[at] = static_cast<char>(rng()); break;
        case 1: bytes[at] ^= static_cast<char>(1 << (rng() % 8)); break;
        default: bytes.erase(at, 1 + rng() % 8); break;
      }
    }
    fix_crcs(bytes);
    try {
      const Image image = read_bytes(bytes);
      EXPECT_EQ(image.rgb.size(), 3u * image.width * image.height);
      ++accepted;
    } catch (const InputError&) {
      ++refused;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "mutation " << i << ": not an InputError: " << e.what();
    }
  }
  EXPECT_GT(refused, 0);
  EXPECT_GT(accepted, 0);  // some mutations only change pixels
}

// --- Text ---

const Rgb kBlack{0, 0, 0}, kWhite{255, 255, 255}, kRed{255, 0, 0};

int count(const Image& image, Rgb color) {
  int n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) n += image.at(x, y) == color;
  return n;
}

TEST(RenderText, Metrics) {
  EXPECT_EQ(text_width("MAX 0.013", 2), (6 * 9 - 1) * 2);
  EXPECT_EQ(text_width("MAX 0.013", 2), 106);
  EXPECT_EQ(text_width("", 3), 0);
  EXPECT_EQ(text_width("a", 1), 5);
  EXPECT_EQ(text_width("a", 0), 5);  // a scale below 1 counts as 1
  EXPECT_EQ(text_width("x\xC3\x97y", 1), 17);  // "×" is one (unknown) character
  EXPECT_EQ(text_height(1), 9);
  EXPECT_EQ(text_height(2), 18);
  EXPECT_EQ(text_width(std::string(100, 'W'), INT_MAX), INT_MAX);
}

TEST(RenderText, DrawsWithinTheMeasuredBox) {
  Image image(60, 30, kWhite);
  draw_text(image, 5, 4, "Ag8y", kBlack, 2);
  int min_x = INT_MAX, min_y = INT_MAX, max_x = -1, max_y = -1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (image.at(x, y) == kBlack) {
        min_x = std::min(min_x, x), min_y = std::min(min_y, y), max_x = std::max(max_x, x), max_y = std::max(max_y, y);
      }
  EXPECT_EQ(min_x, 5);
  EXPECT_EQ(min_y, 4);
  EXPECT_EQ(max_x, 5 + text_width("Ag8y", 2) - 1);
  EXPECT_EQ(max_y, 4 + text_height(2) - 1);  // the descenders of g and y reach the bottom
}

// Drawing into a small image is a window onto drawing into a large one: the same pixels
// where the small one has them, nothing else changed, nothing written outside.
TEST(RenderText, ClipsToTheImage) {
  const int w = 23, h = 17, margin = 40;
  for (const auto& [x, y] : std::vector<std::pair<int, int>>{{-3, -3}, {w - 4, h - 4}, {-20, 5}, {10, -12}, {w - 1, h - 1}}) {
    for (int scale : {1, 2, 3}) {
      Image small(w, h, kWhite), large(w + 2 * margin, h + 2 * margin, kWhite);
      draw_text_box(small, x, y, "8gA%", kBlack, kRed, scale);
      draw_text_box(large, x + margin, y + margin, "8gA%", kBlack, kRed, scale);
      for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px)
          ASSERT_EQ(small.at(px, py), large.at(px + margin, py + margin)) << x << ", " << y << " scale " << scale;
    }
  }
  Image image(w, h, kWhite);
  const Image untouched = image;
  for (int x : {INT_MIN, -1000000, w + 14, 1000000, INT_MAX})  // 14: the box's margin at scale 7
    for (int y : {INT_MIN, -1000000, h + 14, INT_MAX}) {
      draw_text(image, x, y, "8 W\xC3\x97", kBlack, 5);
      draw_text_box(image, x, y, "8 W", kBlack, kRed, 7);
    }
  EXPECT_EQ(image.rgb, untouched.rgb);
  draw_text(image, INT_MIN / 2, INT_MIN / 2, "88888888", kBlack, INT_MAX);  // huge, over everything
  draw_text_box(image, INT_MAX - 5, INT_MAX - 5, "8", kBlack, kRed, INT_MAX);
  Image empty;
  draw_text_box(empty, 0, 0, "8", kBlack, kRed, 1);
}

TEST(RenderText, GlyphsDifferAndUnknownCharactersAreBoxes) {
  auto lit = [](std::string_view text) {
    Image image(12, 12, kWhite);
    draw_text(image, 1, 1, text, kBlack, 1);
    return image;
  };
  EXPECT_GT(count(lit("8"), kBlack), count(lit("1"), kBlack));
  EXPECT_EQ(count(lit(" "), kBlack), 0);
  const Image box = lit("\t");
  EXPECT_GT(count(box, kBlack), 0);
  EXPECT_EQ(lit("\xC3\x97").rgb, box.rgb);  // a UTF-8 sequence: one box
  EXPECT_EQ(lit("~").rgb, box.rgb);
  const std::string font = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz.,:;-+=%()/_<>#!?'*[]|";
  std::set<std::vector<std::uint8_t>> seen{box.rgb};
  for (char c : font) EXPECT_TRUE(seen.insert(lit(std::string(1, c)).rgb).second) << "'" << c << "' is not its own glyph";
}

TEST(RenderText, BoxFillsTheMarginAroundTheText) {
  Image image(40, 30, kWhite);
  draw_text_box(image, 10, 8, "Hi", kBlack, kRed, 1);
  const int bw = text_width("Hi", 1) + 4, bh = text_height(1) + 4;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const bool inside = x >= 8 && x < 8 + bw && y >= 6 && y < 6 + bh;
      const Rgb c = image.at(x, y);
      if (inside) {
        EXPECT_TRUE(c == kBlack || c == kRed) << x << ", " << y;
      } else {
        EXPECT_EQ(c, kWhite) << x << ", " << y;
      }
    }
  EXPECT_GT(count(image, kBlack), 10);
  Image untouched(10, 10, kWhite);
  Image image2 = untouched;
  draw_text_box(image2, 3, 3, "", kBlack, kRed, 1);
  EXPECT_EQ(image2.rgb, untouched.rgb);
}

}  // namespace
}  // namespace ffd
