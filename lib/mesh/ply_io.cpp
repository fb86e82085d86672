#include "mesh/ply_io.h"

#include <algorithm>
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

enum class Format { Ascii, BinaryLittle, BinaryBig };

enum class Type { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

struct TypeName {
  std::string_view name;
  Type type;
};
constexpr TypeName kTypeNames[] = {
    {"char", Type::Int8},     {"int8", Type::Int8},       {"uchar", Type::Uint8},   {"uint8", Type::Uint8},
    {"short", Type::Int16},   {"int16", Type::Int16},     {"ushort", Type::Uint16}, {"uint16", Type::Uint16},
    {"int", Type::Int32},     {"int32", Type::Int32},     {"uint", Type::Uint32},   {"uint32", Type::Uint32},
    {"float", Type::Float32}, {"float32", Type::Float32}, {"double", Type::Float64}, {"float64", Type::Float64}};

bool parse_type(std::string_view word, Type& type) {
  for (const TypeName& t : kTypeNames)
    if (t.name == word) {
      type = t.type;
      return true;
    }
  return false;
}

std::size_t type_size(Type t) {
  switch (t) {
    case Type::Int8: case Type::Uint8: return 1;
    case Type::Int16: case Type::Uint16: return 2;
    case Type::Int32: case Type::Uint32: case Type::Float32: return 4;
    case Type::Float64: return 8;
  }
  return 8;
}

bool is_integer(Type t) { return t != Type::Float32 && t != Type::Float64; }

// The range of an integer type, for ASCII values.
void integer_range(Type t, long long& lo, long long& hi) {
  switch (t) {
    case Type::Int8: lo = -128; hi = 127; return;
    case Type::Uint8: lo = 0; hi = 255; return;
    case Type::Int16: lo = -32768; hi = 32767; return;
    case Type::Uint16: lo = 0; hi = 65535; return;
    case Type::Int32: lo = -2147483648LL; hi = 2147483647LL; return;
    default: lo = 0; hi = 4294967295LL; return;
  }
}

// What a kept vertex property feeds.
enum Slot : int { kNone = -1, kX, kY, kZ, kNx, kNy, kNz, kRed, kGreen, kBlue, kU, kV, kSlots };

int vertex_slot(std::string_view name) {
  static constexpr std::pair<std::string_view, int> kNames[] = {
      {"x", kX},         {"y", kY},         {"z", kZ},         {"nx", kNx},       {"ny", kNy},
      {"nz", kNz},       {"red", kRed},     {"green", kGreen}, {"blue", kBlue},   {"u", kU},
      {"v", kV},         {"s", kU},         {"t", kV},         {"texture_u", kU}, {"texture_v", kV},
      {"texture_s", kU}, {"texture_t", kV}};
  for (const auto& [n, slot] : kNames)
    if (n == name) return slot;
  return kNone;
}

struct Property {
  std::string name;
  Type type = Type::Float32;
  bool list = false;
  Type count_type = Type::Uint8;
  std::size_t line = 0;
  int slot = kNone;      // vertex: what it feeds
  bool indices = false;  // face: the vertex index list
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::size_t line = 0;  // the header line declaring it
  std::vector<Property> properties;
  /// The fewest bytes one item can take: its scalars and list counts (binary), or two
  /// per value (ASCII: a digit and a separator).
  std::size_t min_bytes(Format format) const {
    std::size_t n = 0;
    for (const Property& p : properties)
      n += format != Format::Ascii ? type_size(p.list ? p.count_type : p.type) : 2;
    return n;
  }
};

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t data_start = 0;  // the first byte after end_header's line
  std::size_t lines = 0;       // the header's lines
};

void parse_format(const std::vector<std::string_view>& t, const std::string& at, Header& h) {
  if (t.size() != 3 || t[2] != "1.0" ||
      (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian"))
    throw InputError(at + ": expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
  h.format = t[1] == "ascii" ? Format::Ascii : t[1] == "binary_little_endian" ? Format::BinaryLittle : Format::BinaryBig;
}

void parse_element(const std::vector<std::string_view>& t, const std::string& at, std::size_t line, Header& h) {
  long long count;
  if (t.size() != 3 || !parse_integer(t[2], count) || count < 0)
    throw InputError(at + ": expected 'element NAME COUNT' with a count of 0 or more");
  for (const Element& e : h.elements)
    if (e.name == t[1]) throw InputError(at + ": a second element '" + std::string(t[1]) + "'");
  Element e;
  e.name = std::string(t[1]);
  e.count = static_cast<std::uint64_t>(count);
  e.line = line;
  h.elements.push_back(std::move(e));
}

void parse_property(const std::vector<std::string_view>& t, const std::string& at, std::size_t line, Header& h) {
  if (h.elements.empty()) throw InputError(at + ": a property before any element");
  Property p;
  p.line = line;
  if (t.size() == 5 && t[1] == "list") {
    p.list = true;
    if (!parse_type(t[2], p.count_type) || !is_integer(p.count_type))
      throw InputError(at + ": the list's count type '" + std::string(t[2]) + "' is not an integer type");
    if (!parse_type(t[3], p.type))
      throw InputError(at + ": unknown property type '" + std::string(t[3]) + "'");
    p.name = std::string(t[4]);
  } else if (t.size() == 3) {
    if (!parse_type(t[1], p.type)) throw InputError(at + ": unknown property type '" + std::string(t[1]) + "'");
    p.name = std::string(t[2]);
  } else {
    throw InputError(at + ": expected 'property TYPE NAME' or 'property list COUNTTYPE ITEMTYPE NAME'");
  }
  Element& e = h.elements.back();
  for (const Property& q : e.properties)
    if (q.name == p.name) throw InputError(at + ": a second property '" + p.name + "' in element " + e.name);
  e.properties.push_back(std::move(p));
}

// The header up to end_header's line; elements and properties as declared.
Header read_header(std::string_view bytes, const std::string& file) {
  if (bytes.empty()) throw InputError(At{file}, "the file is empty (a PLY file starts with 'ply')");
  Header h;
  bool have_format = false;
  std::size_t pos = 0;
  std::vector<std::string_view> t;
  for (;;) {
    if (pos >= bytes.size())
      throw InputError(At{file}, "the header ends without 'end_header' (after line " + std::to_string(h.lines) + ")");
    std::size_t end = std::min(bytes.find('\n', pos), bytes.size());
    std::string_view line = bytes.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = end + 1;
    const std::string at = place(file, ++h.lines);
    split_tokens(line, t, false);
    if (h.lines == 1) {
      if (t.size() != 1 || t[0] != "ply") throw InputError(at + ": not a PLY file (the first line must be 'ply')");
      continue;
    }
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format") {
      if (have_format) throw InputError(at + ": a second format line");
      parse_format(t, at, h);
      have_format = true;
    } else if (t[0] == "element") {
      parse_element(t, at, h.lines, h);
    } else if (t[0] == "property") {
      parse_property(t, at, h.lines, h);
    } else if (t[0] == "end_header") {
      if (t.size() != 1) throw InputError(at + ": unexpected words after end_header");
      if (!have_format) throw InputError(at + ": the header has no format line");
      break;
    } else {
      throw InputError(at + ": unknown header keyword '" + std::string(t[0]) + "'");
    }
  }
  h.data_start = std::min(pos, bytes.size());
  return h;
}

// Reads values one by one from the data after the header, and words errors with the
// element, item and (ASCII) line they concern.
class Cursor {
public:
  Cursor(std::string_view bytes, const Header& h, const std::string& file)
      : bytes_(bytes), pos_(h.data_start), line_(h.lines + 1), format_(h.format), file_(file) {
    const std::uint16_t one = 1;
    unsigned char low;
    std::memcpy(&low, &one, 1);
    const bool host_little = low == 1;
    swap_ = format_ != Format::Ascii && (format_ == Format::BinaryLittle) != host_little;
  }
  bool ascii() const { return format_ == Format::Ascii; }
  std::size_t left() const { return bytes_.size() - pos_; }
  /// The line of the next value (ASCII: after skipping blanks).
  std::size_t line() {
    skip_blanks();
    return line_;
  }
  void at(const Element* element, std::uint64_t item) {
    element_ = element;
    item_ = item;
  }
  void at(const Property* property) { property_ = property; }

  /// "file:line: vertex 3: what" (ASCII) or "file: vertex 3: what" (binary).
  [[noreturn]] void fail(const std::string& what) const {
    std::string where = ascii() ? place(file_, line_) : file_;
    if (element_) where += ": " + element_->name + " " + std::to_string(item_);
    throw InputError(where + ": " + what);
  }

  /// One value of type t (integers exactly, float32 as a float).
  double scalar(Type t) { return ascii() ? ascii_scalar(t) : binary_scalar(t); }

  /// The length of list p, checked against the bytes left.
  std::uint64_t list_length(const Property& p) {
    const double n = scalar(p.count_type);
    if (n < 0) fail("the list " + p.name + " has a negative length");
    const std::uint64_t count = static_cast<std::uint64_t>(n);
    const std::uint64_t per_item = ascii() ? 2 : type_size(p.type);
    if (count > (left() + (ascii() ? 1 : 0)) / per_item)
      fail("the list " + p.name + " promises " + std::to_string(count) + " items, more than the " +
           std::to_string(left()) + " bytes left can hold");
    return count;
  }

  /// Throws unless only blanks are left in an ASCII file (more values there mean the
  /// header's counts are wrong). A binary file may go on: exporters pad theirs, and the
  /// header's counts already fixed every byte that is read.
  void expect_end() {
    if (!ascii()) return;
    skip_blanks();
    if (pos_ == bytes_.size()) return;
    element_ = nullptr;
    fail("unexpected data after the last element");
  }

private:
  void skip_blanks() {
    if (!ascii()) return;
    while (pos_ < bytes_.size()) {
      const char c = bytes_[pos_];
      if (c == '\n') ++line_;
      else if (c != ' ' && c != '\t' && c != '\r' && c != '\f' && c != '\v') break;
      ++pos_;
    }
  }

  std::string expected() const {
    return property_ ? " (expected " + property_->name + ")" : std::string();
  }

  double binary_scalar(Type t) {
    const std::size_t n = type_size(t);
    if (left() < n) fail("the file ends inside it" + expected());
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + pos_, n);
    pos_ += n;
    if (swap_) std::reverse(b, b + n);
    switch (t) {
      case Type::Int8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case Type::Uint8: return b[0];
      case Type::Int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::Uint16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::Int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::Uint32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::Float32: { float v; std::memcpy(&v, b, 4); return v; }
      case Type::Float64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0;
  }

  double ascii_scalar(Type t) {
    skip_blanks();
    if (pos_ == bytes_.size()) {
      if (bytes_.back() == '\n') --line_;  // name the last line, not the one after it
      fail("the file ends inside it" + expected());
    }
    const std::size_t start = pos_;
    while (pos_ < bytes_.size()) {
      const char c = bytes_[pos_];
      if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v') break;
      ++pos_;
    }
    const std::string_view token = bytes_.substr(start, pos_ - start);
    const auto name = [this] { return property_ ? property_->name + " " : std::string(); };
    if (is_integer(t)) {
      long long v, lo, hi;
      integer_range(t, lo, hi);
      if (!parse_integer(token, v) || v < lo || v > hi)
        fail(name() + "'" + std::string(token) + "' is not an integer in " + std::to_string(lo) + ".." +
             std::to_string(hi));
      return static_cast<double>(v);
    }
    const char* first = token.data();
    const char* last = first + token.size();
    if (*first == '+' && last - first > 1 && first[1] != '-') ++first;
    std::from_chars_result r;
    double value;
    if (t == Type::Float32) {
      float f;
      r = std::from_chars(first, last, f);
      value = f;
    } else {
      r = std::from_chars(first, last, value);
    }
    if (r.ec == std::errc::result_out_of_range) fail(name() + "'" + std::string(token) + "' is not a finite number");
    if (r.ec != std::errc() || r.ptr != last) fail(name() + "'" + std::string(token) + "' is not a number");
    return value;
  }

  std::string_view bytes_;
  std::size_t pos_;
  std::size_t line_;
  Format format_;
  bool swap_ = false;
  const std::string& file_;
  const Element* element_ = nullptr;
  std::uint64_t item_ = 0;
  const Property* property_ = nullptr;
};

// What the vertex element gives: which slots it has, and whether its colour is integral.
struct VertexLayout {
  bool has[kSlots] = {};
  bool integer_color = false;
  bool normals() const { return has[kNx] && has[kNy] && has[kNz]; }
  bool colors() const { return has[kRed] && has[kGreen] && has[kBlue]; }
  bool uvs() const { return has[kU] && has[kV]; }
};

VertexLayout vertex_layout(Element& e, const std::string& file) {
  VertexLayout layout;
  for (Property& p : e.properties) {
    const int slot = vertex_slot(p.name);
    if (slot == kNone || layout.has[slot]) continue;  // a second uv name is skipped
    if (p.list) {
      if (slot <= kZ)
        throw InputError(At{place(file, p.line)}, "the vertex property " + p.name + " must be a scalar, not a list");
      continue;
    }
    p.slot = slot;
    layout.has[slot] = true;
    if (slot == kRed) layout.integer_color = is_integer(p.type);
  }
  for (int s = kX; s <= kZ; ++s)
    if (!layout.has[s])
      throw InputError(At{place(file, e.line)}, "the vertex element has no property " +
                       std::string(s == kX ? "x" : s == kY ? "y" : "z"));
  // A partial normal, colour or texture coordinate is skipped as unknown.
  for (Property& p : e.properties) {
    const int s = p.slot;
    if ((s >= kNx && s <= kNz && !layout.normals()) || (s >= kRed && s <= kBlue && !layout.colors()) ||
        (s >= kU && s <= kV && !layout.uvs()))
      p.slot = kNone;
  }
  return layout;
}

void face_layout(Element& e, const std::string& file) {
  for (Property& p : e.properties)
    if (p.name == "vertex_indices" || p.name == "vertex_index") {
      if (!p.list || !is_integer(p.type))
        throw InputError(At{place(file, p.line)}, p.name + " must be a list of integers");
      p.indices = true;
      return;
    }
  throw InputError(At{place(file, e.line)}, "the face element has no list vertex_indices");
}

const char* const kSlotNames[] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "u", "v"};

void read_vertices(Cursor& cur, const Element& e, const VertexLayout& layout, PolygonSoup& soup) {
  soup.positions.reserve(e.count);
  if (layout.normals()) soup.normals.reserve(e.count);
  if (layout.colors()) soup.colors.reserve(e.count);
  if (layout.uvs()) soup.uvs.reserve(e.count);
  double v[kSlots] = {};
  for (std::uint64_t i = 0; i < e.count; ++i) {
    cur.at(&e, i);
    for (const Property& p : e.properties) {
      cur.at(&p);
      if (p.list) {
        for (std::uint64_t k = 0, n = cur.list_length(p); k < n; ++k) cur.scalar(p.type);
        continue;
      }
      const double x = cur.scalar(p.type);
      if (p.slot == kNone) continue;
      if (!std::isfinite(x)) cur.fail(std::string(kSlotNames[p.slot]) + " is not finite (" + format_number(x) + ")");
      v[p.slot] = x;
    }
    soup.positions.emplace_back(v[kX], v[kY], v[kZ]);
    if (layout.normals()) soup.normals.emplace_back(v[kNx], v[kNy], v[kNz]);
    if (layout.colors()) {
      const double scale = layout.integer_color ? 1.0 / 255.0 : 1.0;
      soup.colors.emplace_back(static_cast<float>(v[kRed] * scale), static_cast<float>(v[kGreen] * scale),
                               static_cast<float>(v[kBlue] * scale));
    }
    if (layout.uvs()) soup.uvs.emplace_back(v[kU], v[kV]);
  }
}

void read_faces(Cursor& cur, const Element& e, std::uint64_t vertices, const VertexLayout& layout, PolygonSoup& soup) {
  // A face takes at least three indices, so no more faces than this fit in the bytes left.
  std::uint64_t per_face = e.min_bytes(cur.ascii() ? Format::Ascii : Format::BinaryLittle);
  for (const Property& p : e.properties)
    if (p.indices) per_face += cur.ascii() ? 6 : 3 * type_size(p.type);
  soup.elements.reserve(std::min<std::uint64_t>(e.count, cur.left() / per_face + 1), 3);
  for (std::uint64_t i = 0; i < e.count; ++i) {
    cur.at(&e, i);
    const std::size_t line = cur.ascii() ? cur.line() : 0;
    for (const Property& p : e.properties) {
      cur.at(&p);
      if (!p.list) {
        cur.scalar(p.type);
        continue;
      }
      const std::uint64_t n = cur.list_length(p);
      for (std::uint64_t k = 0; k < n; ++k) {
        const double x = cur.scalar(p.type);
        if (!p.indices) continue;
        if (x < 0 || x >= static_cast<double>(vertices))
          cur.fail("vertex index " + std::to_string(static_cast<long long>(x)) + " is out of range (the file has " +
                   std::to_string(vertices) + " vertices)");
        const auto v = static_cast<std::uint32_t>(x);
        soup.elements.add_corner(v, layout.uvs() ? static_cast<std::int32_t>(v) : -1,
                                 layout.normals() ? static_cast<std::int32_t>(v) : -1);
      }
      // Checked here, not only in build_mesh: it bounds the memory a face takes per byte.
      if (p.indices && n < 3) cur.fail("a face needs at least 3 vertices, found " + std::to_string(n));
    }
    soup.elements.close(ElementKind::Polygon, -1, line);
  }
}

}  // namespace

PolygonSoup read_ply(std::string_view bytes, const std::string& file) {
  Header h = read_header(bytes, file);
  Element* vertex = nullptr;
  for (Element& e : h.elements) {
    if (e.name == "vertex") vertex = &e;
    if (e.name == "face") face_layout(e, file);
  }
  if (!vertex || vertex->count == 0) throw InputError(At{file}, "the file has no vertex");
  const VertexLayout layout = vertex_layout(*vertex, file);
  PolygonSoup soup;
  soup.binary = h.format != Format::Ascii;
  Cursor cur(bytes, h, file);
  for (const Element& e : h.elements) {
    const std::size_t min = e.min_bytes(h.format);
    if (min > 0 && e.count > (cur.left() + (cur.ascii() ? 1 : 0)) / min)
      throw InputError(At{place(file, e.line)}, "element " + e.name + " promises " + std::to_string(e.count) +
                       " items, but only " + std::to_string(cur.left()) + " bytes are left and each needs at least " +
                       std::to_string(min));
    if (&e == vertex) {
      read_vertices(cur, e, layout, soup);
    } else if (e.name == "face") {
      read_faces(cur, e, vertex->count, layout, soup);
    } else {
      for (std::uint64_t i = 0; min > 0 && i < e.count; ++i) {
        cur.at(&e, i);
        for (const Property& p : e.properties) {
          cur.at(&p);
          if (!p.list) cur.scalar(p.type);
          else for (std::uint64_t k = 0, n = cur.list_length(p); k < n; ++k) cur.scalar(p.type);
        }
      }
    }
  }
  cur.expect_end();
  return soup;
}

}  // namespace ffd
