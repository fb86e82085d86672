#include "mesh/ply_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/ply_source.h"
#include "mesh/text_lines.h"

namespace ffd {
namespace {

using Format = PlySource::Format;
using Type = PlyType;

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

std::size_t type_size(Type t) { return ply_type_size(t); }

bool is_integer(Type t) { return ply_integer(t); }

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
      {"texture_s", kU}, {"texture_t", kV}, {"diffuse_red", kRed}, {"diffuse_green", kGreen},
      {"diffuse_blue", kBlue}};
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
  bool indices = false;  // face, tristrips: the vertex index list
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
  std::vector<std::string> text;  // each line as read, without its line end
  std::size_t format_line = 0;    // 0-based
  std::string line_end;           // the first line's: "\n", "\r\n" or "\r"
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
  // A repeated name is allowed: the first one has the name's meaning, and all are kept.
  h.elements.back().properties.push_back(std::move(p));
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
    // A line ends at LF, CRLF or a lone CR (old Mac and some Rhino exports).
    const std::size_t end = std::min(bytes.find_first_of("\r\n", pos), bytes.size());
    const std::string_view line = bytes.substr(pos, end - pos);
    const std::size_t ending = end + 1 < bytes.size() && bytes[end] == '\r' && bytes[end + 1] == '\n' ? 2 : 1;
    if (h.line_end.empty()) h.line_end = std::string(bytes.substr(std::min(end, bytes.size()), ending));
    pos = end + ending;
    h.text.emplace_back(line);
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
      h.format_line = h.lines - 1;
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
  if (h.line_end.empty()) h.line_end = "\n";
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

  /// Whether a binary file's values are in the other byte order.
  bool swapped() const { return swap_; }
  /// The bytes from the cursor on (binary files), without moving it.
  const unsigned char* peek() const { return reinterpret_cast<const unsigned char*>(bytes_.data()) + pos_; }
  /// The next n bytes of a binary file, which has them (left() >= n).
  const unsigned char* take(std::size_t n) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes_.data()) + pos_;
    pos_ += n;
    return p;
  }

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
      const bool lone_cr = c == '\r' && (pos_ + 1 == bytes_.size() || bytes_[pos_ + 1] != '\n');
      if (c == '\n' || lone_cr) ++line_;
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
    ply_copy(b, reinterpret_cast<const unsigned char*>(bytes_.data()) + pos_, n, swap_);
    pos_ += n;
    return ply_load(t, b);
  }

  double ascii_scalar(Type t) {
    skip_blanks();
    if (pos_ == bytes_.size()) {
      if (bytes_.back() == '\n' || bytes_.back() == '\r') --line_;  // name the last line, not the one after it
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

// Marks the vertex index list of a face or tristrips element.
void index_layout(Element& e, const std::string& file) {
  for (Property& p : e.properties)
    if (p.name == "vertex_indices" || p.name == "vertex_index") {
      if (!p.list || !is_integer(p.type))
        throw InputError(At{place(file, p.line)}, p.name + " must be a list of integers");
      p.indices = true;
      return;
    }
  throw InputError(At{place(file, e.line)}, "the " + e.name + " element has no list vertex_indices");
}

// The columns a PlySource keeps of element e, one per property, with the role the
// writer gives each (ply_source.h); the values come as the items are read.
PlyElementData element_data(const Element& e, bool vertex) {
  PlyElementData d;
  d.name = e.name;
  d.count = e.count;
  d.line = e.line - 1;
  for (const Property& p : e.properties) {
    PlyColumn c;
    c.name = p.name;
    c.type = p.type;
    c.list = p.list;
    c.count_type = p.count_type;
    c.line = p.line - 1;
    c.in_mesh = p.indices;
    if (vertex && p.slot != kNone) {
      c.role = p.slot <= kZ ? PlyColumn::Role::Position : p.slot <= kNz ? PlyColumn::Role::Normal
               : p.slot <= kBlue ? PlyColumn::Role::Color : PlyColumn::Role::Kept;
      c.component = p.slot <= kZ ? p.slot : p.slot <= kNz ? p.slot - kNx : p.slot <= kBlue ? p.slot - kRed : 0;
      c.in_mesh = c.role == PlyColumn::Role::Kept;  // u v
    }
    d.columns.push_back(std::move(c));
  }
  return d;
}

const char* const kSlotNames[] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "u", "v"};

// Appends x to column c's values (unless the writer takes that column from the mesh).
void keep(PlyColumn& c, double x) {
  if (c.role == PlyColumn::Role::Position || c.role == PlyColumn::Role::Normal) return;
  const std::size_t size = ply_type_size(c.type);
  c.values.resize(c.values.size() + size);
  ply_store(c.type, x, c.values.data() + c.values.size() - size);
}

// Reads one item of element e into d's columns: scalars of a vertex slot into `slots`
// (checked finite), the entries of the index list into `indices`.
void read_item(Cursor& cur, const Element& e, PlyElementData& d, double* slots, std::vector<double>& indices) {
  indices.clear();
  for (std::size_t k = 0; k < e.properties.size(); ++k) {
    const Property& p = e.properties[k];
    PlyColumn& c = d.columns[k];
    cur.at(&p);
    if (!p.list) {
      const double x = cur.scalar(p.type);
      if (p.slot != kNone) {
        if (!std::isfinite(x)) cur.fail(std::string(kSlotNames[p.slot]) + " is not finite (" + format_number(x) + ")");
        slots[p.slot] = x;
      }
      keep(c, x);
      continue;
    }
    const std::uint64_t n = cur.list_length(p);
    if (n > 0xffffffffu) cur.fail("the list " + p.name + " has more than 2^32 - 1 entries");
    c.lengths.push_back(static_cast<std::uint32_t>(n));
    for (std::uint64_t i = 0; i < n; ++i) {
      const double x = cur.scalar(p.type);
      keep(c, x);
      if (p.indices) indices.push_back(x);
    }
  }
}

// One scalar property of a binary element read as a row of fixed size.
struct RowField {
  std::size_t offset = 0, size = 0;
  Type type = Type::Uint8;
  int slot = kNone;
  unsigned char* kept = nullptr;  // its column's values, or null (x y z, nx ny nz)
  const Property* property = nullptr;
};

// The fields of e's rows (every property a scalar), each kept column sized for e's items.
std::vector<RowField> row_fields(const Element& e, PlyElementData& d, std::size_t& row) {
  std::vector<RowField> fields;
  row = 0;
  for (std::size_t k = 0; k < e.properties.size(); ++k) {
    const Property& p = e.properties[k];
    PlyColumn& c = d.columns[k];
    RowField f{row, type_size(p.type), p.type, p.slot, nullptr, &p};
    if (c.role != PlyColumn::Role::Position && c.role != PlyColumn::Role::Normal) {
      c.values.resize(e.count * f.size);
      f.kept = c.values.data();
    }
    row += f.size;
    fields.push_back(f);
  }
  return fields;
}

// A binary element whose properties are all scalars, read as rows of fixed size: each
// kept value's bytes go to its column as they are (in native order), and only the vertex
// slots become doubles (checked finite), which `item(i, slots)` takes. Returns false,
// having read nothing, for an ASCII file or an element with a list. (read_ply has checked
// that the element's items fit in the bytes left.)
template <class Item>
bool read_scalar_rows(Cursor& cur, const Element& e, PlyElementData& d, Item&& item) {
  if (cur.ascii() || e.properties.empty()) return false;
  std::size_t row = 0;
  for (const Property& p : e.properties) {
    if (p.list) return false;
    row += type_size(p.type);
  }
  if (e.count > cur.left() / row) cur.fail("the file ends inside element " + e.name);  // not reached: see above
  const std::vector<RowField> fields = row_fields(e, d, row);
  const unsigned char* base = cur.take(e.count * row);
  const bool swap = cur.swapped();
  double slots[kSlots] = {};
  for (std::uint64_t i = 0; i < e.count; ++i, base += row) {
    for (const RowField& f : fields) {
      unsigned char b[8];
      ply_copy(b, base + f.offset, f.size, swap);
      if (f.kept) ply_copy(f.kept + i * f.size, b, f.size, false);
      if (f.slot == kNone) continue;
      slots[f.slot] = ply_load(f.type, b);
      if (!std::isfinite(slots[f.slot])) {
        cur.at(&e, i);
        cur.at(f.property);
        cur.fail(std::string(kSlotNames[f.slot]) + " is not finite (" + format_number(slots[f.slot]) + ")");
      }
    }
    item(i, slots);
  }
  return true;
}

// Reserves d's columns for e's items (e.count is checked against the bytes left).
void reserve_columns(const Element& e, PlyElementData& d) {
  for (PlyColumn& c : d.columns)
    if (!c.list && c.role != PlyColumn::Role::Position && c.role != PlyColumn::Role::Normal)
      c.values.reserve(e.count * ply_type_size(c.type));
    else if (c.list)
      c.lengths.reserve(e.count);
}

void read_vertices(Cursor& cur, const Element& e, const VertexLayout& layout, PlyElementData& d, PolygonSoup& soup) {
  soup.positions.reserve(e.count);
  if (layout.normals()) soup.normals.reserve(e.count);
  soup.normals_per_vertex = layout.normals();
  if (layout.colors()) soup.colors.reserve(e.count);
  if (layout.uvs()) soup.uvs.reserve(e.count);
  const auto add = [&](std::uint64_t, const double* v) {
    soup.positions.emplace_back(v[kX], v[kY], v[kZ]);
    if (layout.normals()) soup.normals.emplace_back(v[kNx], v[kNy], v[kNz]);
    if (layout.colors()) {
      const double scale = layout.integer_color ? 1.0 / 255.0 : 1.0;
      soup.colors.emplace_back(static_cast<float>(v[kRed] * scale), static_cast<float>(v[kGreen] * scale),
                               static_cast<float>(v[kBlue] * scale));
    }
    if (layout.uvs()) soup.uvs.emplace_back(v[kU], v[kV]);
  };
  if (read_scalar_rows(cur, e, d, add)) return;
  reserve_columns(e, d);
  double v[kSlots] = {};
  std::vector<double> unused;
  for (std::uint64_t i = 0; i < e.count; ++i) {
    cur.at(&e, i);
    read_item(cur, e, d, v, unused);
    add(i, v);
  }
}

// Appends the polygon on `corners` (vertex indices) to the soup, with the vertex's UV and
// normal when the file has them.
void add_polygon(const std::uint32_t* corners, std::size_t n, std::size_t line, const VertexLayout& layout,
                 PolygonSoup& soup) {
  for (std::size_t k = 0; k < n; ++k)
    soup.elements.add_corner(corners[k], layout.uvs() ? static_cast<std::int32_t>(corners[k]) : -1,
                             layout.normals() ? static_cast<std::int32_t>(corners[k]) : -1);
  soup.elements.close(ElementKind::Polygon, -1, line);
}

// The vertex index x of an index list, checked against the vertex count.
std::uint32_t vertex_index(Cursor& cur, double x, std::uint64_t vertices) {
  if (x < 0 || x >= static_cast<double>(vertices))
    cur.fail("vertex index " + std::to_string(static_cast<long long>(x)) + " is out of range (the file has " +
             std::to_string(vertices) + " vertices)");
  return static_cast<std::uint32_t>(x);
}

// One face of a binary file whose only property is its index list of 4-byte integers
// (`list uchar int vertex_indices`, what most exporters write), straight from the bytes:
// what read_item and vertex_index do with it, without their per-value dispatch (with
// add_polygon, 76% of reading a 1M-vertex binary PLY), then add_polygon. False, with nothing read,
// for a face that needs their checks (fewer than 3 or more than 16 entries, an index out
// of range, the file's end): the caller reads that one the general way, which words the
// error.
bool read_binary_face(Cursor& cur, const Property& p, PlyColumn& c, std::uint64_t vertices, const VertexLayout& layout,
                      PolygonSoup& soup) {
  constexpr std::uint32_t kMost = 16;
  const std::size_t count_size = type_size(p.count_type);
  if (cur.left() < count_size) return false;
  const unsigned char* at = cur.peek();
  unsigned char b[8];
  ply_copy(b, at, count_size, cur.swapped());
  const double count = ply_load(p.count_type, b);
  if (!(count >= 3 && count <= kMost) || count * 4 > static_cast<double>(cur.left() - count_size)) return false;
  const std::uint32_t n = std::min(static_cast<std::uint32_t>(count), kMost);  // (min: the bound, for the compiler)
  std::uint32_t index[kMost];
  unsigned char value[4 * kMost];  // native byte order, as keep() stores them
  for (std::uint32_t k = 0; k < n; ++k) {
    std::uint32_t bits;
    std::memcpy(&bits, at + count_size + 4 * k, 4);
    if (cur.swapped()) bits = __builtin_bswap32(bits);
    std::memcpy(value + 4 * k, &bits, 4);
    // The value ply_load gives, without its dispatch on the type.
    const std::int64_t x = p.type == Type::Int32 ? static_cast<std::int64_t>(static_cast<std::int32_t>(bits)) : bits;
    if (x < 0 || static_cast<std::uint64_t>(x) >= vertices) return false;
    index[k] = static_cast<std::uint32_t>(x);
  }
  cur.take(count_size + 4 * n);
  c.lengths.push_back(n);
  c.values.insert(c.values.end(), value, value + 4 * n);
  add_polygon(index, n, 0, layout, soup);
  return true;
}

// A face element's polygons, or a tristrips element's triangles: in each strip (runs
// between -1 entries), the triangles of consecutive triples, every second one flipped to
// keep the strip's orientation. A triangle that repeats a vertex is the zero-area joint a
// stripifier puts between strips, not a face, and is not made one.
void read_polygons(Cursor& cur, const Element& e, std::uint64_t vertices, const VertexLayout& layout,
                   PlyElementData& d, PolygonSoup& soup) {
  const bool strips = e.name == "tristrips";
  // A face takes at least three indices, so no more faces than this fit in the bytes left.
  std::uint64_t per_face = e.min_bytes(cur.ascii() ? Format::Ascii : Format::BinaryLittle);
  for (const Property& p : e.properties)
    if (p.indices) per_face += cur.ascii() ? 6 : 3 * type_size(p.type);
  const auto faces = static_cast<std::size_t>(std::min<std::uint64_t>(e.count, cur.left() / per_face + 1));
  reserve_columns(e, d);
  double unused[kSlots];
  std::vector<double> indices;
  std::vector<std::uint32_t> corners;
  const bool fast = !strips && !cur.ascii() && e.properties.size() == 1 && e.properties[0].indices &&
                    type_size(e.properties[0].type) == 4;
  if (!strips) {  // triangles' worth: their corners, with a UV and normal index when the vertices have them
    soup.elements.reserve(faces, 3);
    if (layout.uvs()) soup.elements.corner_uvs.reserve(3 * faces);
    if (layout.normals()) soup.elements.corner_normals.reserve(3 * faces);
    if (fast) d.columns[0].values.reserve(3 * 4 * faces);
  }
  for (std::uint64_t i = 0; i < e.count; ++i) {
    cur.at(&e, i);
    if (fast && read_binary_face(cur, e.properties[0], d.columns[0], vertices, layout, soup)) continue;
    const std::size_t line = cur.ascii() ? cur.line() : 0;
    read_item(cur, e, d, unused, indices);
    corners.clear();
    if (!strips) {
      for (const double x : indices) corners.push_back(vertex_index(cur, x, vertices));
      // Checked here, not only in build_mesh: it bounds the memory a face takes per byte.
      if (corners.size() < 3) cur.fail("a face needs at least 3 vertices, found " + std::to_string(corners.size()));
      add_polygon(corners.data(), corners.size(), line, layout, soup);
      continue;
    }
    std::vector<std::uint32_t> strip;
    for (std::size_t k = 0; k <= indices.size(); ++k) {
      if (k == indices.size() || indices[k] == -1) {
        strip.clear();
        continue;
      }
      strip.push_back(vertex_index(cur, indices[k], vertices));
      const std::size_t n = strip.size();
      if (n < 3) continue;
      const std::uint32_t a = strip[n - 3], b = strip[n - 2], c = strip[n - 1];
      if (a == b || b == c || a == c) continue;
      corners.assign({n % 2 ? a : b, n % 2 ? b : a, c});
      add_polygon(corners.data(), corners.size(), line, layout, soup);
    }
  }
}

}  // namespace

PolygonSoup read_ply(std::string_view bytes, const std::string& file) {
  Header h = read_header(bytes, file);
  auto source = std::make_shared<PlySource>();
  source->format = h.format;
  source->header = std::move(h.text);
  source->format_line = h.format_line;
  source->line_end = h.line_end;
  Element* vertex = nullptr;
  for (Element& e : h.elements) {
    if (e.name == "vertex" && !vertex) vertex = &e;
    if (e.name == "face" || e.name == "tristrips") index_layout(e, file);
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
    if (&e == vertex) source->vertex_element = source->elements.size();
    source->elements.push_back(element_data(e, &e == vertex));
    PlyElementData& d = source->elements.back();
    if (&e == vertex) {
      read_vertices(cur, e, layout, d, soup);
    } else if (e.name == "face" || e.name == "tristrips") {
      read_polygons(cur, e, vertex->count, layout, d, soup);
    } else if (!read_scalar_rows(cur, e, d, [](std::uint64_t, const double*) {})) {
      reserve_columns(e, d);
      double unused[kSlots];
      std::vector<double> indices;
      for (std::uint64_t i = 0; min > 0 && i < e.count; ++i) {
        cur.at(&e, i);
        read_item(cur, e, d, unused, indices);
      }
    }
  }
  cur.expect_end();
  soup.ply = std::move(source);
  return soup;
}

}  // namespace ffd
