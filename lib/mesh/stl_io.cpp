#include "mesh/stl_io.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/text_lines.h"

namespace ffd {
namespace {

constexpr std::size_t kHeaderBytes = 84;  // 80-byte header and the uint32 triangle count
constexpr std::size_t kTriangleBytes = 50;

// Gives each distinct corner point (== on all three coordinates) one vertex, first seen
// first: an open-addressing table of vertex numbers over the soup's positions (linear
// probing, a power-of-two size kept at most half full). With std::unordered_map's node
// per point, reading a 1M-vertex binary STL took 480 ms instead of 360, and its run
// peaked at 276 MB instead of 180.
class VertexMerger {
public:
  explicit VertexMerger(PolygonSoup& soup) : soup_(soup) { resize(1024); }
  /// Sizes the table for `corners` corners (about corners / 6 distinct points in a
  /// closed triangle mesh; it grows past that).
  void reserve(std::size_t corners) {
    std::size_t size = 1024;
    while (size < corners / 2) size *= 2;
    if (size > slots_.size()) resize(size);
  }
  std::uint32_t add(const Eigen::Vector3d& p) {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t h = hash(p) & mask;; h = (h + 1) & mask) {
      const std::uint32_t v = slots_[h];
      if (v == kEmpty) {
        const auto added = static_cast<std::uint32_t>(soup_.positions.size());
        soup_.positions.push_back(p);
        slots_[h] = added;
        if (2 * soup_.positions.size() > slots_.size()) resize(2 * slots_.size());
        return added;
      }
      if (soup_.positions[v] == p) return v;
    }
  }

private:
  static constexpr std::uint32_t kEmpty = 0xffffffffu;
  static std::size_t hash(const Eigen::Vector3d& p) {
    std::uint64_t h = 1469598103934665603ULL;
    for (int k = 0; k < 3; ++k) {
      const double d = p[k] + 0.0;  // -0 hashes as 0, as they compare equal
      std::uint64_t bits;
      std::memcpy(&bits, &d, 8);
      h = (h ^ bits) * 1099511628211ULL;
      h ^= h >> 29;
    }
    return static_cast<std::size_t>(h);
  }
  // Rebuilds the table with `size` slots (a power of two) from the positions so far.
  void resize(std::size_t size) {
    slots_.assign(size, kEmpty);
    const std::size_t mask = size - 1;
    for (std::size_t v = 0; v < soup_.positions.size(); ++v) {
      std::size_t h = hash(soup_.positions[v]) & mask;
      while (slots_[h] != kEmpty) h = (h + 1) & mask;
      slots_[h] = static_cast<std::uint32_t>(v);
    }
  }
  PolygonSoup& soup_;
  std::vector<std::uint32_t> slots_;
};

std::uint32_t little_uint32(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
}

float little_float(const char* p) {
  const std::uint32_t bits = little_uint32(p);
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

PolygonSoup read_binary(std::string_view bytes, const std::string& file) {
  const std::uint32_t count = little_uint32(bytes.data() + 80);
  PolygonSoup soup;
  soup.binary = true;
  VertexMerger merger(soup);
  merger.reserve(std::size_t(count) * 3);
  soup.elements.reserve(count, 3);
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* tri = bytes.data() + kHeaderBytes + std::size_t(t) * kTriangleBytes + 12;  // after the normal
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d p;
      for (int k = 0; k < 3; ++k) p[k] = little_float(tri + 12 * c + 4 * k);
      if (!p.allFinite())
        throw InputError(At{file}, "triangle " + std::to_string(t) + ": corner " + std::to_string(c) +
                         " has a non-finite coordinate (" + format_number(p[0]) + " " + format_number(p[1]) + " " +
                         format_number(p[2]) + ")");
      soup.elements.add_corner(merger.add(p));
    }
    soup.elements.close(ElementKind::Polygon);
  }
  return soup;
}

// The words of ASCII STL with their lines.
class Words {
public:
  Words(std::string_view text, const std::string& file) : text_(text), file_(file) {}
  std::size_t line() const { return line_; }
  /// The next word; empty at the end of the text.
  std::string_view next() {
    while (pos_ < text_.size() && is_blank(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_blank(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  /// Skips the rest of the current line (a solid's name).
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(At{place(file_, line_)}, what); }
  void expect(std::string_view word) {
    const std::string_view w = next();
    if (w.empty()) fail("the file ends where '" + std::string(word) + "' was expected");
    if (w != word) fail("expected '" + std::string(word) + "', found '" + std::string(w) + "'");
  }
  /// The next word as a number; `finite` also refuses nan and inf.
  double number(const char* what, bool finite) {
    const std::string_view w = next();
    if (w.empty()) fail(std::string("the file ends where a ") + what + " was expected");
    const char* first = w.data();
    const char* last = first + w.size();
    if (*first == '+' && last - first > 1 && first[1] != '-') ++first;
    double v;
    const auto r = std::from_chars(first, last, v);
    const bool number = (r.ec == std::errc() || r.ec == std::errc::result_out_of_range) && r.ptr == last;
    if (!number || (finite && (r.ec != std::errc() || !std::isfinite(v))))
      fail(std::string(what) + " '" + std::string(w) + "' is not a " + (finite ? "finite number" : "number"));
    return v;
  }

private:
  static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
  std::string_view text_;
  const std::string& file_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

// One `facet normal n n n outer loop vertex x y z (3x) endloop endfacet` after its
// "facet" word, into `soup`.
void read_facet(Words& w, std::size_t index, VertexMerger& merger, PolygonSoup& soup) {
  const std::size_t facet_line = w.line();
  w.expect("normal");
  for (int k = 0; k < 3; ++k) w.number("normal component", false);
  w.expect("outer");
  w.expect("loop");
  for (int c = 0; c < 3; ++c) {
    w.expect("vertex");
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k)
      p[k] = w.number(("triangle " + std::to_string(index) + ": coordinate").c_str(), true);
    soup.elements.add_corner(merger.add(p));
  }
  w.expect("endloop");
  w.expect("endfacet");
  soup.elements.close(ElementKind::Polygon, -1, facet_line);
}

PolygonSoup read_ascii(std::string_view text, const std::string& file) {
  PolygonSoup soup;
  VertexMerger merger(soup);
  Words w(text, file);
  w.expect("solid");
  w.skip_line();
  for (;;) {
    const std::string_view word = w.next();
    if (word.empty()) w.fail("the file ends before 'endsolid'");
    if (word == "facet") {
      read_facet(w, soup.elements.size(), merger, soup);
      continue;
    }
    if (word != "endsolid") w.fail("expected 'facet' or 'endsolid', found '" + std::string(word) + "'");
    w.skip_line();
    const std::string_view after = w.next();
    if (after.empty()) break;
    if (after != "solid") w.fail("unexpected data after 'endsolid'");  // or another solid
    w.skip_line();
  }
  return soup;
}

bool looks_binary(std::string_view bytes) {
  for (char ch : bytes) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c < 9 || (c > 13 && c < 32)) return true;
  }
  return false;
}

}  // namespace

bool stl_is_binary(std::string_view bytes) {
  return bytes.size() >= kHeaderBytes &&
         kHeaderBytes + std::uint64_t(little_uint32(bytes.data() + 80)) * kTriangleBytes == bytes.size();
}

PolygonSoup read_stl(std::string_view bytes, const std::string& file) {
  if (bytes.empty()) throw InputError(At{file}, "the file is empty");
  const bool fits_binary = stl_is_binary(bytes);
  const auto size_error = [&] {
    if (bytes.size() < kHeaderBytes)
      return InputError(At{file}, std::to_string(bytes.size()) +
                        " bytes, too short for a binary STL (84 bytes of header and triangle count) and not "
                        "ASCII STL ('solid' ...)");
    const std::uint64_t count = little_uint32(bytes.data() + 80);
    return InputError(At{file}, "binary STL: the header's count of " + std::to_string(count) + " triangles needs " +
                      std::to_string(kHeaderBytes + count * kTriangleBytes) +
                      " bytes (84 + 50 per triangle), the file has " + std::to_string(bytes.size()));
  };
  PolygonSoup soup;
  const bool solid = bytes.substr(0, 5) == "solid" &&
                     (bytes.size() == 5 || std::string_view(" \t\r\n").find(bytes[5]) != std::string_view::npos);
  if (solid) {
    try {
      soup = read_ascii(bytes, file);
    } catch (const InputError&) {
      if (!fits_binary && looks_binary(bytes)) throw size_error();
      if (!fits_binary) throw;
      soup = read_binary(bytes, file);
    }
  } else {
    if (!fits_binary) throw size_error();
    soup = read_binary(bytes, file);
  }
  if (soup.positions.empty()) throw InputError(At{file}, "the file has no vertex (no triangle)");
  return soup;
}

}  // namespace ffd
