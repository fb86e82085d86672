#include "mesh/foam_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "common/errors.h"
#include "mesh/text_lines.h"
#include "mesh/volume_patch.h"

namespace ffd {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kMaxLabel = std::numeric_limits<std::uint32_t>::max();
constexpr const char* kFileNames[5] = {"points", "faces", "owner", "neighbour", "boundary"};

// ---------------------------------------------------------------------------------------
// Scanning OpenFOAM's token syntax: white space and C/C++ comments between tokens, words,
// quoted strings, and the punctuation ; ( ) { }.

bool is_space(char ch) { return ch == ' ' || ch == '\n' || ch == '\t' || ch == '\r' || ch == '\f' || ch == '\v'; }
bool is_punct(char ch) { return ch == ';' || ch == '(' || ch == ')' || ch == '{' || ch == '}' || ch == '"'; }
bool ends_token(char ch) { return is_space(ch) || is_punct(ch); }

// A place in one file: its text, the position, and the line there (from 1; lines inside
// binary data are counted too, so a line number is always the file's physical line).
struct Cursor {
  std::string_view text;
  const std::string* file = nullptr;
  std::size_t pos = 0;
  std::size_t line = 1;

  bool at_end() const { return pos >= text.size(); }
  char peek() const { return pos < text.size() ? text[pos] : '\0'; }
  std::string here() const { return place(*file, line); }
  std::string byte(std::uint64_t n) const { return *file + ": byte " + std::to_string(n); }
  [[noreturn]] void fail(const std::string& message) const { throw InputError(At{here()}, message); }
};

// Skips white space and comments (// to the line's end, /* ... */), counting lines.
void skip_space(Cursor& c) {
  const std::string_view t = c.text;
  std::size_t i = c.pos;
  while (i < t.size()) {
    const char ch = t[i];
    if (ch == '\n') {
      ++c.line, ++i;
    } else if (is_space(ch)) {
      ++i;
    } else if (ch == '/' && i + 1 < t.size() && t[i + 1] == '/') {
      i = std::min(t.find('\n', i), t.size());
    } else if (ch == '/' && i + 1 < t.size() && t[i + 1] == '*') {
      const std::size_t end = t.find("*/", i + 2);
      if (end == std::string_view::npos) c.fail("a /* comment is not closed");
      c.line += static_cast<std::size_t>(std::count(t.begin() + i, t.begin() + end, '\n'));
      i = end + 2;
    } else {
      break;
    }
  }
  c.pos = i;
}

// What is at the cursor, for messages: 'the token' (at most 20 characters) or "the end
// of the file".
std::string found(Cursor c) {
  skip_space(c);
  if (c.at_end()) return "the end of the file";
  std::size_t end = c.pos + 1;
  if (!ends_token(c.text[c.pos]))
    while (end < c.text.size() && end - c.pos < 20 && !ends_token(c.text[end])) ++end;
  return "'" + std::string(c.text.substr(c.pos, end - c.pos)) + "'";
}

// The next token: one punctuation character, a quoted string (quotes included) or a
// word; empty at the end of the text.
std::string_view next_token(Cursor& c) {
  skip_space(c);
  if (c.at_end()) return {};
  const std::size_t begin = c.pos;
  if (c.text[begin] == '"') {
    std::size_t i = begin + 1;
    while (i < c.text.size() && c.text[i] != '"') i += c.text[i] == '\\' ? 2 : 1;
    if (i >= c.text.size()) c.fail("a quoted string is not closed");
    c.line += static_cast<std::size_t>(std::count(c.text.begin() + begin, c.text.begin() + i, '\n'));
    c.pos = i + 1;
  } else if (is_punct(c.text[begin])) {
    c.pos = begin + 1;
  } else {
    while (c.pos < c.text.size() && !ends_token(c.text[c.pos])) ++c.pos;
  }
  return c.text.substr(begin, c.pos - begin);
}

// Moves past a parenthesized group from its '(' to the matching ')' (or the end).
void skip_group(Cursor& c) {
  int depth = 0;
  for (; c.pos < c.text.size(); ++c.pos) {
    const char ch = c.text[c.pos];
    if (ch == '\n') ++c.line;
    if (ch == '(') ++depth;
    if (ch == ')' && --depth == 0) {
      ++c.pos;
      return;
    }
  }
}

// An unsigned integer at the cursor that ends at a space, punctuation or the end.
bool take_count(Cursor& c, std::uint64_t& value) {
  const char* p = c.text.data() + c.pos;
  const char* end = c.text.data() + c.text.size();
  const auto [next, ec] = std::from_chars(p, end, value);
  if (ec != std::errc() || next == p || (next < end && !ends_token(*next))) return false;
  c.pos += static_cast<std::size_t>(next - p);
  return true;
}

// A finite number at the cursor that ends at a space, punctuation or the end.
bool take_scalar(Cursor& c, double& value) {
  const char* p = c.text.data() + c.pos;
  const char* end = c.text.data() + c.text.size();
  const auto [next, ec] = std::from_chars(p, end, value, std::chars_format::general);
  if (ec != std::errc() || next == p || (next < end && !ends_token(*next)) || !std::isfinite(value)) return false;
  c.pos += static_cast<std::size_t>(next - p);
  return true;
}

// ---------------------------------------------------------------------------------------
// The FoamFile header.

struct Header {
  bool binary = false, label64 = false, scalar32 = false;
  std::string format = "ascii", version, cls;
};

// The value of a header entry up to its ';' (its first token, unquoted).
std::string_view header_value(Cursor& c, std::string_view key) {
  std::string_view value;
  for (std::string_view t = next_token(c); t != ";"; t = next_token(c)) {
    if (t.empty() || t == "{" || t == "}")
      c.fail("the FoamFile header's entry '" + std::string(key) + "' does not end with ';'");
    if (value.empty()) value = t;
  }
  if (value.size() >= 2 && value.front() == '"') value = value.substr(1, value.size() - 2);
  return value;
}

// `arch "LSB;label=32;scalar=64"`: the sizes of binary labels and scalars.
void read_arch(std::string_view arch, Header& h, const Cursor& c) {
  while (!arch.empty()) {
    const std::size_t cut = arch.find(';');
    const std::string_view part = arch.substr(0, cut);
    arch = cut == std::string_view::npos ? std::string_view() : arch.substr(cut + 1);
    if (part == "MSB") c.fail("big-endian (MSB) files are not supported");
    if (part == "label=32" || part == "label=64") h.label64 = part == "label=64";
    else if (part == "scalar=32" || part == "scalar=64") h.scalar32 = part == "scalar=32";
    else if (part.substr(0, 6) == "label=" || part.substr(0, 7) == "scalar=")
      c.fail("unsupported arch '" + std::string(part) + "' (read: label=32 or 64, scalar=32 or 64)");
  }
}

// `FoamFile { version 2.0; format ascii; class ...; arch "..."; ... }`.
Header read_header(Cursor& c) {
  skip_space(c);
  const Cursor start = c;
  if (next_token(c) != "FoamFile") start.fail("expected the FoamFile header, found " + found(start));
  if (next_token(c) != "{") c.fail("expected '{' after FoamFile");
  Header h;
  for (std::string_view key = next_token(c); key != "}"; key = next_token(c)) {
    if (key.empty()) c.fail("the FoamFile header is not closed with '}'");
    if (is_punct(key[0])) c.fail("expected a keyword in the FoamFile header, found '" + std::string(key) + "'");
    const std::string_view value = header_value(c, key);
    if (key == "format") {
      if (value != "ascii" && value != "binary")
        c.fail("format '" + std::string(value) + "' is neither ascii nor binary");
      h.format = value;
      h.binary = value == "binary";
    } else if (key == "class") {
      h.cls = value;
    } else if (key == "version") {
      h.version = value;
    } else if (key == "arch") {
      read_arch(value, h, c);
    }
  }
  return h;
}

// Nothing but white space and comments after the file's data.
void expect_end(Cursor& c) {
  skip_space(c);
  if (!c.at_end()) c.fail("unexpected " + found(c) + " after the data");
}

// ---------------------------------------------------------------------------------------
// Lists: `N ( items )`, the items as text or, in a binary file, as raw bytes right after
// the '('. A binary empty list may be a bare `0`.

struct ListStart {
  std::uint64_t count = 0;
  std::size_t line = 0;  // of the count
  bool open = false;     // a '(' was read
};

ListStart read_list_start(Cursor& c, const char* what) {
  skip_space(c);
  ListStart s{0, c.line, false};
  if (!take_count(c, s.count)) c.fail(std::string("expected the number of ") + what + ", found " + found(c));
  skip_space(c);
  if (c.peek() == '{') c.fail("uniform lists 'N{value}' are not supported");
  if (c.peek() != '(') {
    if (s.count == 0) return s;
    c.fail(std::string("expected '(' after the number of ") + what + ", found " + found(c));
  }
  ++c.pos;
  s.open = true;
  return s;
}

// Refuses a text list whose count could not fit in the rest of the file (each item takes
// at least `min_bytes`), before anything is allocated for it.
void check_room(const Cursor& c, const ListStart& s, std::size_t min_bytes, const char* what) {
  if (s.count > (c.text.size() - c.pos) / min_bytes)
    throw InputError(At{place(*c.file, s.line)}, "the file ends before the " + std::to_string(s.count) + " " +
                     what + " it announces");
}

// The closing ')' of a text list.
void close_list(Cursor& c, const ListStart& s, const char* what) {
  if (!s.open) return;
  skip_space(c);
  if (c.peek() != ')')
    c.fail("expected ')' after " + std::to_string(s.count) + " " + what + ", found " + found(c));
  ++c.pos;
}

// The raw data of a binary list (count items of `item` bytes) and its ')': checks that
// both are there, moves past them and returns the data's first byte.
std::size_t binary_data(Cursor& c, const ListStart& s, std::size_t item, const char* what) {
  const std::size_t data = c.pos;
  if (!s.open) return data;
  const std::size_t room = c.text.size() - data;
  if (s.count > room / item || s.count * item == room)
    throw InputError(At{c.byte(data)}, "truncated binary list: " + std::to_string(s.count) + " " + what +
                     " need " + std::to_string(s.count) + " x " + std::to_string(item) + " bytes and ')', " +
                     std::to_string(room) + " bytes are left");
  const std::size_t end = data + s.count * item;
  if (c.text[end] != ')')
    throw InputError(At{c.byte(end)}, "expected ')' after the binary data of " + std::to_string(s.count) + " " + what);
  c.line += static_cast<std::size_t>(std::count(c.text.begin() + data, c.text.begin() + end, '\n'));
  c.pos = end + 1;
  return data;
}

// Where a list's items are, to name one in a message after the list is read.
struct ListAt {
  Cursor first;               // text: just after the '('
  std::size_t count_line = 0;
  std::size_t data = 0;       // binary: the first item's byte
  std::size_t item = 0;       // binary: bytes per item; 0 for text
};

// The place of item i: its byte in binary data, else its line, found again by skipping
// i items (a label, `(x y z)` or `n(a b c)`).
std::string item_place(const ListAt& at, std::uint64_t i) {
  if (at.item) return at.first.byte(at.data + i * at.item);
  Cursor c = at.first;
  for (std::uint64_t k = 0; k < i && !c.at_end(); ++k) {
    skip_space(c);
    while (!c.at_end() && !ends_token(c.peek())) ++c.pos;
    skip_space(c);
    if (c.peek() == '(') skip_group(c);
  }
  skip_space(c);
  return c.here();
}

// Appends count raw labels (4 or 8 bytes) from byte `data`, each 0..2^32 - 1.
void append_binary_labels(const Cursor& c, std::size_t data, std::uint64_t count, std::size_t size,
                          std::vector<std::uint32_t>& out) {
  const char* at = c.text.data() + data;
  for (std::uint64_t i = 0; i < count; ++i, at += size) {
    const std::int64_t v = size == 4 ? load_bytes<std::int32_t>(at, swapped_order(false)) : load_bytes<std::int64_t>(at, swapped_order(false));
    if (v < 0 || static_cast<std::uint64_t>(v) > kMaxLabel)
      throw InputError(At{c.byte(data + i * size)}, "label " + std::to_string(v) + " is " +
                       (v < 0 ? "negative" : "too large (at most 4294967295)"));
    out.push_back(static_cast<std::uint32_t>(v));
  }
}

// Reads a list of labels `N ( ... )`, text or binary as the header says, appending them
// to `out` (reserved when it starts empty); returns where its items are.
ListAt read_labels(Cursor& c, const Header& h, const char* what, std::vector<std::uint32_t>& out) {
  const ListStart s = read_list_start(c, what);
  ListAt at{c, s.line, c.pos, 0};
  if (h.binary) {
    at.item = h.label64 ? 8 : 4;
    at.data = binary_data(c, s, at.item, what);
    if (out.empty()) out.reserve(s.count);
    append_binary_labels(c, at.data, s.count, at.item, out);
    return at;
  }
  check_room(c, s, 2, what);  // "0)"
  if (out.empty()) out.reserve(s.count);
  for (std::uint64_t i = 0; i < s.count; ++i) {
    skip_space(c);
    std::uint64_t v = 0;
    if (!take_count(c, v) || v > kMaxLabel)
      c.fail("expected a label (0 to 4294967295) in the " + std::string(what) + ", found " + found(c));
    out.push_back(static_cast<std::uint32_t>(v));
  }
  close_list(c, s, what);
  return at;
}

// Refuses the first of values[from, ...) that is not a point's index.
void check_point_labels(const std::vector<std::uint32_t>& values, std::size_t from, std::uint64_t points,
                        const ListAt& at) {
  for (std::size_t j = from; j < values.size(); ++j)
    if (values[j] >= points)
      throw InputError(At{item_place(at, j - from)}, "label " + std::to_string(values[j]) +
                       " out of range (the mesh has " + std::to_string(points) + " points)");
}

// ---------------------------------------------------------------------------------------
// points

struct PointsRead {
  Header header;
  Eigen::Matrix3Xd xyz;
  std::shared_ptr<const VolumeFile> file;
};

// `N ( (x y z) ... )`: the points and the span of each one's numbers.
void read_ascii_points(Cursor& c, const ListStart& s, const SharedBytes& bytes, PointsRead& r) {
  check_room(c, s, 7, "points");  // "(0 0 0)"
  r.xyz.resize(3, static_cast<Eigen::Index>(s.count));
  std::vector<std::uint64_t> spans;
  spans.reserve(2 * s.count);
  for (std::uint64_t i = 0; i < s.count; ++i) {
    skip_space(c);
    if (c.peek() != '(') c.fail("expected point " + std::to_string(i) + " '(x y z)', found " + found(c));
    ++c.pos;
    for (int k = 0; k < 3; ++k) {
      skip_space(c);
      if (k == 0) spans.push_back(c.pos);
      if (!take_scalar(c, r.xyz(k, static_cast<Eigen::Index>(i))))
        c.fail("expected coordinate " + std::to_string(k) + " of point " + std::to_string(i) +
               " (a finite number), found " + found(c));
    }
    spans.push_back(c.pos);
    skip_space(c);
    if (c.peek() != ')')
      c.fail("expected ')' after the 3 coordinates of point " + std::to_string(i) + ", found " + found(c));
    ++c.pos;
  }
  close_list(c, s, "points");
  r.file = std::make_shared<TextPoints>(bytes, std::move(spans), 3, r.xyz);
}

// `N (` then 3 x N raw doubles (floats for scalar=32) `)`.
void read_binary_points(Cursor& c, const ListStart& s, const SharedBytes& bytes, PointsRead& r) {
  const BinaryScalar scalar{!r.header.scalar32, false};
  const std::size_t size = scalar.is_double ? 8 : 4;
  const std::size_t data = binary_data(c, s, 3 * size, "points");
  r.xyz.resize(3, static_cast<Eigen::Index>(s.count));
  for (std::uint64_t i = 0; i < s.count; ++i)
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = data + (3 * i + static_cast<std::size_t>(k)) * size;
      const double x = read_binary_scalar(c.text.data() + at, scalar);
      if (!std::isfinite(x))
        throw InputError(At{c.byte(at)}, "coordinate " + std::to_string(k) + " of point " + std::to_string(i) +
                         " is not a finite number");
      r.xyz(k, static_cast<Eigen::Index>(i)) = x;
    }
  const std::uint64_t count = s.count;
  r.file = std::make_shared<BinaryPoints>(bytes, std::vector<BinaryBlock>{{0, count, data, 3 * size}}, scalar, 3);
}

PointsRead read_points(const SharedBytes& bytes, const std::string& file) {
  Cursor c{*bytes, &file};
  PointsRead r;
  r.header = read_header(c);
  const ListStart s = read_list_start(c, "points");
  if (r.header.binary)
    read_binary_points(c, s, bytes, r);
  else
    read_ascii_points(c, s, bytes, r);
  expect_end(c);
  if (s.count > kMaxLabel) c.fail("more than 4294967295 points");
  return r;
}

// ---------------------------------------------------------------------------------------
// faces: a faceList `N ( n(a b c ...) ... )` or a faceCompactList (offsets, then the
// concatenated labels), text or binary.

struct Faces {
  std::vector<std::uint64_t> offset{0};
  std::vector<std::uint32_t> vertex;
  std::uint64_t count() const { return offset.size() - 1; }
  std::uint64_t size(std::uint64_t f) const { return offset[f + 1] - offset[f]; }
};

void read_face_list(Cursor& c, const Header& h, std::uint64_t points, Faces& f) {
  const ListStart s = read_list_start(c, "faces");
  check_room(c, s, 8, "faces");  // "3(0 1 2)"
  f.offset.reserve(s.count + 1);
  for (std::uint64_t i = 0; i < s.count; ++i) {
    const std::size_t first = f.vertex.size();
    const ListAt at = read_labels(c, h, "face's point labels", f.vertex);
    if (f.vertex.size() - first < 3)
      throw InputError(At{place(*c.file, at.count_line)}, "face " + std::to_string(i) + " has " +
                       std::to_string(f.vertex.size() - first) + " points (a face needs 3 or more)");
    check_point_labels(f.vertex, first, points, at);
    f.offset.push_back(f.vertex.size());
  }
  close_list(c, s, "faces");
}

void read_compact_faces(Cursor& c, const Header& h, std::uint64_t points, Faces& f) {
  std::vector<std::uint32_t> offsets;
  const ListAt oat = read_labels(c, h, "face offsets", offsets);
  const ListAt vat = read_labels(c, h, "face point labels", f.vertex);
  if (offsets.empty())
    throw InputError(At{place(*c.file, oat.count_line)}, "a faceCompactList's offsets list has at least its 0");
  if (offsets[0] != 0)
    throw InputError(At{item_place(oat, 0)}, "the first face offset is " + std::to_string(offsets[0]) + ", not 0");
  for (std::size_t i = 1; i < offsets.size(); ++i)
    if (offsets[i] < std::uint64_t{offsets[i - 1]} + 3)
      throw InputError(At{item_place(oat, i)}, offsets[i] < offsets[i - 1]
          ? "face offset " + std::to_string(offsets[i]) + " is below the one before it"
          : "face " + std::to_string(i - 1) + " has " + std::to_string(offsets[i] - offsets[i - 1]) +
            " points (a face needs 3 or more)");
  if (offsets.back() != f.vertex.size())
    throw InputError(At{item_place(oat, offsets.size() - 1)}, "the last face offset is " +
                     std::to_string(offsets.back()) + ", but the faces list " + std::to_string(f.vertex.size()) +
                     " point labels");
  check_point_labels(f.vertex, 0, points, vat);
  f.offset.assign(offsets.begin(), offsets.end());
}

Faces read_faces(std::string_view bytes, const std::string& file, std::uint64_t points) {
  Cursor c{bytes, &file};
  const Header h = read_header(c);
  Faces f;
  if (h.cls == "faceCompactList")
    read_compact_faces(c, h, points, f);
  else
    read_face_list(c, h, points, f);
  expect_end(c);
  if (f.count() > kMaxLabel) c.fail("more than 4294967295 faces");
  return f;
}

// ---------------------------------------------------------------------------------------
// owner and neighbour: each face's cells.

struct Sides {
  std::vector<std::uint32_t> owner, neighbour;
  std::uint64_t cells = 0;  // max(owner, neighbour) + 1
};

ListAt read_label_file(std::string_view bytes, const std::string& file, const char* what,
                       std::vector<std::uint32_t>& out) {
  Cursor c{bytes, &file};
  const Header h = read_header(c);
  const ListAt at = read_labels(c, h, what, out);
  expect_end(c);
  return at;
}

// Refuses a cell label past `bound`: no mesh has more cells than face sides.
void check_cell_labels(const std::vector<std::uint32_t>& cells, const ListAt& at, std::uint64_t bound) {
  for (std::size_t j = 0; j < cells.size(); ++j)
    if (cells[j] >= bound)
      throw InputError(At{item_place(at, j)}, "cell " + std::to_string(cells[j]) +
                       " out of range (owner and neighbour name " + std::to_string(bound) +
                       " face sides, so at most " + std::to_string(bound) + " cells)");
}

Sides read_sides(std::string_view owner, std::string_view neighbour, const std::string names[5],
                 std::uint64_t faces) {
  Sides s;
  const ListAt oat = read_label_file(owner, names[2], "owner labels", s.owner);
  if (s.owner.size() != faces)
    throw InputError(At{place(names[2], oat.count_line)}, "owner has " + std::to_string(s.owner.size()) +
                     " labels, but faces has " + std::to_string(faces) + " faces (one label per face)");
  const ListAt nat = read_label_file(neighbour, names[3], "neighbour labels", s.neighbour);
  if (s.neighbour.size() > faces)
    throw InputError(At{place(names[3], nat.count_line)}, "neighbour has " + std::to_string(s.neighbour.size()) +
                     " labels, more than the " + std::to_string(faces) + " faces (one per internal face)");
  const std::uint64_t bound = s.owner.size() + s.neighbour.size();
  check_cell_labels(s.owner, oat, bound);
  check_cell_labels(s.neighbour, nat, bound);
  for (std::size_t f = 0; f < s.neighbour.size(); ++f)
    if (s.neighbour[f] == s.owner[f])
      throw InputError(At{item_place(nat, f)}, "face " + std::to_string(f) + " has cell " +
                       std::to_string(s.owner[f]) + " on both sides");
  for (const auto* list : {&s.owner, &s.neighbour})
    for (std::uint32_t cell : *list) s.cells = std::max<std::uint64_t>(s.cells, std::uint64_t{cell} + 1);
  return s;
}

// ---------------------------------------------------------------------------------------
// boundary: `N ( name { type wall; nFaces 20; startFace 760; ... } ... )`.

struct Patch {
  std::string name;
  std::uint64_t start = 0, size = 0;
  std::size_t start_line = 0, size_line = 0;
};

// Moves past a sub-dictionary `{ ... }` from its '{'.
void skip_dictionary(Cursor& c) {
  int depth = 0;
  do {
    const std::string_view t = next_token(c);
    if (t.empty()) c.fail("a '{' is not closed before the end of the file");
    depth += t == "{" ? 1 : t == "}" ? -1 : 0;
  } while (depth > 0);
}

// The value of a dictionary entry up to its ';' (a sub-dictionary `{ ... }` has none):
// its token when it is one word, else empty.
std::string_view entry_value(Cursor& c, std::string_view key) {
  skip_space(c);
  if (c.peek() == '{') {
    skip_dictionary(c);
    return {};
  }
  std::string_view value;
  std::size_t tokens = 0;
  int depth = 0;
  for (std::string_view t = next_token(c); t != ";" || depth > 0; t = next_token(c)) {
    if (t.empty()) c.fail("the entry '" + std::string(key) + "' does not end with ';'");
    if (t == "(" || t == "{") ++depth;
    if ((t == ")" || t == "}") && --depth < 0)
      c.fail("unexpected '" + std::string(t) + "' in the entry '" + std::string(key) + "'");
    ++tokens;
    value = t;
  }
  return tokens == 1 ? value : std::string_view();
}

std::uint64_t patch_number(std::string_view value, const Patch& p, std::string_view key, const Cursor& c) {
  long long n = -1;
  if (!parse_integer(value, n) || n < 0)
    c.fail("patch '" + p.name + "': " + std::string(key) + " '" + std::string(value) + "' is not a count");
  return static_cast<std::uint64_t>(n);
}

// One patch: its name and dictionary, of which nFaces and startFace are needed.
Patch read_patch(Cursor& c, std::uint64_t index) {
  const std::string_view name = next_token(c);
  if (name.empty() || is_punct(name[0]))
    c.fail("expected the name of patch " + std::to_string(index) + ", found '" + std::string(name) + "'");
  Patch p{std::string(name)};
  const std::size_t name_line = c.line;
  if (next_token(c) != "{") c.fail("expected '{' after the patch name '" + p.name + "'");
  for (std::string_view key = next_token(c); key != "}"; key = next_token(c)) {
    if (key.empty() || is_punct(key[0]))
      c.fail("expected a keyword or '}' in patch '" + p.name + "', found '" + std::string(key) + "'");
    const std::size_t line = c.line;
    const std::string_view value = entry_value(c, key);
    if (key == "nFaces") p.size = patch_number(value, p, key, c), p.size_line = line;
    if (key == "startFace") p.start = patch_number(value, p, key, c), p.start_line = line;
  }
  if (!p.size_line || !p.start_line)
    throw InputError(At{place(*c.file, name_line)}, "patch '" + p.name + "' has no " +
                     (p.size_line ? "startFace" : "nFaces") + " entry");
  return p;
}

// The patches, which cover the boundary faces (internal..faces) in order, one after another.
std::vector<Patch> read_boundary(std::string_view bytes, const std::string& file, std::uint64_t faces,
                                 std::uint64_t internal) {
  Cursor c{bytes, &file};
  read_header(c);
  const ListStart s = read_list_start(c, "patches");
  check_room(c, s, 3, "patches");  // "a{}"
  std::vector<Patch> patches;
  patches.reserve(s.count);
  std::uint64_t next = internal;  // where the next patch starts
  for (std::uint64_t i = 0; i < s.count; ++i) {
    Patch p = read_patch(c, i);
    if (p.start != next)
      throw InputError(At{place(file, p.start_line)}, "patch '" + p.name + "' starts at face " +
                       std::to_string(p.start) + ", not at face " + std::to_string(next) + " where the " +
                       (i ? "patch before it ends" : "internal faces end"));
    if (p.size > faces - p.start)
      throw InputError(At{place(file, p.size_line)}, "patch '" + p.name + "' has " + std::to_string(p.size) +
                       " faces from face " + std::to_string(p.start) + ", past the mesh's " + std::to_string(faces) +
                       " faces");
    next = p.start + p.size;
    patches.push_back(std::move(p));
  }
  close_list(c, s, "patches");
  if (next != faces)
    throw InputError(At{place(file, s.line)}, "the patches end at face " + std::to_string(next) +
                     ", but the mesh has " + std::to_string(faces) + " faces (each boundary face is in a patch)");
  expect_end(c);
  return patches;
}

// ---------------------------------------------------------------------------------------
// The cells.

// Each cell's faces (ascending), by a counting sort of the face sides: O(faces).
void cell_faces(const Sides& s, std::vector<std::uint64_t>& first, std::vector<std::uint32_t>& faces,
                const std::string& owner_file) {
  first.assign(s.cells + 1, 0);
  for (std::uint32_t c : s.owner) ++first[std::uint64_t{c} + 1];
  for (std::uint32_t c : s.neighbour) ++first[std::uint64_t{c} + 1];
  for (std::uint64_t c = 0; c < s.cells; ++c) {
    if (first[c + 1] == 0)
      throw InputError(At{owner_file}, "cell " + std::to_string(c) + " is on no face (neither owner nor neighbour "
                       "names it, but a higher cell is named)");
    first[c + 1] += first[c];
  }
  faces.resize(first.back());
  std::vector<std::uint64_t> next(first.begin(), first.end() - 1);
  for (std::size_t f = 0; f < s.owner.size(); ++f) {
    faces[next[s.owner[f]]++] = static_cast<std::uint32_t>(f);
    if (f < s.neighbour.size()) faces[next[s.neighbour[f]]++] = static_cast<std::uint32_t>(f);
  }
}

// One polyhedron per cell: its faces in VTK's stream form, as stored where the cell owns
// the face and reversed (first point kept) where it is the neighbour, so that every face
// points out of the cell; its nodes in order of first appearance.
void add_polyhedra(const Faces& faces, const Sides& s, std::uint64_t points, const std::string& owner_file,
                   VolumeCells& cells) {
  std::vector<std::uint64_t> first;
  std::vector<std::uint32_t> by_cell;
  cell_faces(s, first, by_cell, owner_file);
  std::vector<std::uint64_t> seen(points, std::numeric_limits<std::uint64_t>::max());  // the last cell using a point
  std::vector<std::uint32_t> nodes, stream;
  for (std::uint64_t c = 0; c < s.cells; ++c) {
    nodes.clear();
    stream.assign(1, static_cast<std::uint32_t>(first[c + 1] - first[c]));
    for (std::uint64_t k = first[c]; k < first[c + 1]; ++k) {
      const std::uint32_t f = by_cell[k];
      const std::uint32_t* v = faces.vertex.data() + faces.offset[f];
      const std::uint64_t n = faces.size(f);
      stream.push_back(static_cast<std::uint32_t>(n));
      stream.push_back(v[0]);
      if (s.owner[f] == c)
        stream.insert(stream.end(), v + 1, v + n);
      else
        for (std::uint64_t j = n - 1; j >= 1; --j) stream.push_back(v[j]);
      for (std::uint64_t j = 0; j < n; ++j)
        if (seen[v[j]] != c) seen[v[j]] = c, nodes.push_back(v[j]);
    }
    cells.add_polyhedron(nodes, stream);
  }
}

// The cells: polyhedra, then one triangle, quad or polygon per boundary face; and one
// marker per patch listing its faces' cells.
void build_cells(const Faces& faces, const Sides& s, const std::vector<Patch>& patches, std::uint64_t points,
                 const std::string& owner_file, VolumeSource& source) {
  VolumeCells& cells = source.cells;
  const std::uint64_t internal = s.neighbour.size(), boundary = faces.count() - internal;
  const std::uint64_t sides = faces.offset.back() + faces.offset[internal];  // face points counted per side
  cells.type.reserve(s.cells + boundary);
  cells.offset.reserve(s.cells + boundary + 1);
  cells.face_offset.reserve(s.cells + boundary);
  cells.face.reserve(s.cells + faces.count() + internal + sides);
  cells.node.reserve(sides / 3 + faces.offset.back() - faces.offset[internal]);
  add_polyhedra(faces, s, points, owner_file, cells);
  for (std::uint64_t f = internal; f < faces.count(); ++f) {
    const std::uint64_t n = faces.size(f);
    const std::uint8_t type = n == 3 ? cell_type::kTriangle : n == 4 ? cell_type::kQuad : cell_type::kPolygon;
    cells.add(type, faces.vertex.data() + faces.offset[f], n);
  }
  for (const Patch& p : patches) {
    VolumeMarker& m = source.markers.emplace_back();
    m.name = p.name;
    m.dimension = 2;
    m.cells.resize(p.size);
    for (std::uint64_t j = 0; j < p.size; ++j) m.cells[j] = s.cells + (p.start - internal) + j;
  }
}

// ---------------------------------------------------------------------------------------
// The folder.

// The folder's files other than the five, relative to it, '/'-separated, sorted.
std::vector<std::string> companion_files(const fs::path& folder) {
  std::vector<std::string> paths;
  try {
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(folder)) {
      if (!e.is_regular_file()) continue;
      std::string relative = e.path().lexically_relative(folder).generic_string();
      if (std::find(std::begin(kFileNames), std::end(kFileNames), relative) == std::end(kFileNames))
        paths.push_back(std::move(relative));
    }
  } catch (const fs::filesystem_error& e) {
    throw IoError(At{folder.string()}, std::string("cannot list the folder: ") + e.what());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

// One of the five files: refused by name when missing or compressed.
SharedBytes read_mesh_file(const fs::path& folder, const char* name) {
  const fs::path path = folder / name;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return read_shared_file_bytes(path.string());
  fs::path gz = path;
  gz += ".gz";
  if (fs::exists(gz, ec))
    throw InputError(At{gz.string()}, "compressed polyMesh files (" + std::string(name) + ".gz) are not supported; "
                     "gunzip them, or set writeCompression off and run foamFormatConvert");
  throw InputError(At{path.string()},
                   "no such file (a polyMesh folder has points, faces, owner, neighbour and boundary)");
}

}  // namespace

VolumeRead read_foam_files(const FoamFiles& files, const std::string& folder) {
  std::string names[5];
  const SharedBytes* bytes[5] = {&files.points, &files.faces, &files.owner, &files.neighbour, &files.boundary};
  for (int i = 0; i < 5; ++i) {
    names[i] = (fs::path(folder) / kFileNames[i]).string();
    if (!*bytes[i]) throw InputError(At{names[i]}, "no such file");
  }
  PointsRead points = read_points(files.points, names[0]);
  const std::uint64_t n = static_cast<std::uint64_t>(points.xyz.cols());
  const Faces faces = read_faces(*files.faces, names[1], n);
  const Sides sides = read_sides(*files.owner, *files.neighbour, names, faces.count());
  const std::vector<Patch> patches = read_boundary(*files.boundary, names[4], faces.count(), sides.neighbour.size());
  VolumeRead r;
  r.source.format = VolumeFormat::Foam;
  r.source.encoding = points.header.format;
  r.source.version = points.header.version;
  build_cells(faces, sides, patches, n, names[2], r.source);
  r.source.file = std::move(points.file);
  r.points = std::move(points.xyz);
  return r;
}

VolumeRead read_foam(const std::string& folder) {
  const fs::path dir(folder);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(At{folder}, "not a folder (an OpenFOAM polyMesh folder is read)");
  FoamFiles files;
  SharedBytes* slots[5] = {&files.points, &files.faces, &files.owner, &files.neighbour, &files.boundary};
  for (int i = 0; i < 5; ++i) *slots[i] = read_mesh_file(dir, kFileNames[i]);
  VolumeRead r = read_foam_files(files, folder);
  r.source.companion_files = companion_files(dir);
  return r;
}

FoamFiles split_foam_bundle(std::string_view bundle) {
  FoamFiles files;
  SharedBytes* slots[5] = {&files.points, &files.faces, &files.owner, &files.neighbour, &files.boundary};
  std::size_t at = 0;
  for (int i = 0; i < 5; ++i) {
    const std::string where = "foam bundle: byte " + std::to_string(at);
    if (bundle.size() - at < 8)
      throw InputError(At{where}, std::string("the size of ") + kFileNames[i] + " is cut short");
    const std::uint64_t size = load_bytes<std::uint64_t>(bundle.data() + at, swapped_order(false));
    at += 8;
    if (size > bundle.size() - at)
      throw InputError(At{where}, std::string(kFileNames[i]) + " has " + std::to_string(size) + " bytes, but " +
                       std::to_string(bundle.size() - at) + " are left");
    *slots[i] = std::make_shared<const FileBytes>(std::string(bundle.substr(at, size)));
    at += size;
  }
  if (at != bundle.size())
    throw InputError(At{"foam bundle: byte " + std::to_string(at)}, std::to_string(bundle.size() - at) +
                     " bytes after the five files");
  return files;
}

}  // namespace ffd
