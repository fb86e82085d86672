// The legacy VTK reader (read_vtk_legacy): DATASET UNSTRUCTURED_GRID, ASCII or BINARY.
//
// The file is a stream of whitespace-separated tokens (keywords, counts, ASCII values);
// BINARY data starts after its keyword line's newline and is big-endian. Reading stops
// once POINTS, CELLS and CELL_TYPES are read: the point, cell and field data after them
// are carried as they are.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <functional>
#include <optional>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/volume_patch.h"
#include "mesh/vtk_volume_io.h"

namespace ffd {
namespace {

constexpr std::size_t kNone = std::string_view::npos;

struct Legacy {
  Legacy(std::string_view b, const std::string& p) : bytes(b), path(p) {}
  std::string_view bytes;
  const std::string& path;
  bool binary = false;
  std::size_t pos = 0;
  std::size_t first_binary = kNone;  // where binary data first starts: later places are bytes
};

std::string place_at(const Legacy& f, std::size_t offset) {
  offset = std::min(offset, f.bytes.size());
  if (f.first_binary != kNone && offset >= f.first_binary) return f.path + ": byte " + std::to_string(offset);
  const auto lines = std::count(f.bytes.begin(), f.bytes.begin() + static_cast<std::ptrdiff_t>(offset), '\n');
  return f.path + ":" + std::to_string(lines + 1);
}

[[noreturn]] void fail(const Legacy& f, std::size_t offset, const std::string& message) {
  throw InputError(At{place_at(f, offset)}, message);
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

// The next whitespace-separated token (empty at the end); `at` is where it starts.
std::string_view next_token(Legacy& f, std::size_t& at) {
  while (f.pos < f.bytes.size() && is_space(f.bytes[f.pos])) ++f.pos;
  at = f.pos;
  while (f.pos < f.bytes.size() && !is_space(f.bytes[f.pos])) ++f.pos;
  return f.bytes.substr(at, f.pos - at);
}

std::string_view token_or_fail(Legacy& f, const char* what) {
  std::size_t at;
  const std::string_view t = next_token(f, at);
  if (t.empty()) fail(f, at, std::string("the file ends where ") + what + " is expected");
  return t;
}

std::uint64_t count_token(Legacy& f, const char* what, std::uint64_t max) {
  std::size_t at;
  const std::string_view t = next_token(f, at);
  long long n;
  if (!parse_integer(t, n) || n < 0 || static_cast<unsigned long long>(n) > max)
    fail(f, at, std::string("expected ") + what + " (a count from 0 to " + std::to_string(max) + "), not '" + std::string(t) + "'");
  return static_cast<std::uint64_t>(n);
}

// A whole line from pos (without its line end); pos moves past it.
std::string_view next_line(Legacy& f) {
  const std::size_t end = std::min(f.bytes.find('\n', f.pos), f.bytes.size());
  std::string_view line = f.bytes.substr(f.pos, end - f.pos);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  f.pos = std::min(end + 1, f.bytes.size());
  return line;
}

// The rest of a keyword line must be blank; binary data starts after its newline.
void end_line(Legacy& f) {
  while (f.pos < f.bytes.size() && (f.bytes[f.pos] == ' ' || f.bytes[f.pos] == '\t' || f.bytes[f.pos] == '\r')) ++f.pos;
  if (f.pos < f.bytes.size() && f.bytes[f.pos] != '\n') fail(f, f.pos, "unexpected words at the end of the line");
  f.pos = std::min(f.pos + 1, f.bytes.size());
  if (f.first_binary == kNone) f.first_binary = f.pos;
}

// "# vtk DataFile Version X.Y", the title, ASCII|BINARY, DATASET UNSTRUCTURED_GRID.
std::string read_header(Legacy& f) {
  constexpr std::string_view kMagic = "# vtk DataFile Version ";
  const std::string_view first = next_line(f);
  if (first.substr(0, kMagic.size()) != kMagic) fail(f, 0, "not a legacy VTK file (the first line must be '# vtk DataFile Version X.Y')");
  std::string_view version = first.substr(kMagic.size());
  while (!version.empty() && is_space(version.back())) version.remove_suffix(1);
  const std::size_t dot = version.find('.');
  long long major = 0, minor = 0;
  if (dot == kNone || !parse_integer(version.substr(0, dot), major) || !parse_integer(version.substr(dot + 1), minor) ||
      major < 1 || major > 5 || minor < 0 || minor > 99 || major * 100 + minor > 501)
    fail(f, 0, "legacy VTK version '" + std::string(version) + "' is not supported (ffdtool reads 1.0 to 5.1)");
  next_line(f);  // the title
  const std::size_t format_at = f.pos;
  std::string_view format = next_line(f);
  while (!format.empty() && is_space(format.back())) format.remove_suffix(1);
  const std::string kind = upper(format);
  if (kind != "ASCII" && kind != "BINARY") fail(f, format_at, "the third line must be ASCII or BINARY, not '" + std::string(format) + "'");
  f.binary = kind == "BINARY";
  std::size_t at;
  if (upper(next_token(f, at)) != "DATASET") fail(f, at, "expected DATASET after the ASCII/BINARY line");
  const std::string dataset = upper(token_or_fail(f, "the DATASET's kind"));
  if (dataset != "UNSTRUCTURED_GRID")
    fail(f, at, "DATASET " + dataset + " is not supported; ffdtool reads legacy VTK files whose DATASET is UNSTRUCTURED_GRID");
  return std::string(version);
}

// A binary type's size and signedness (VTK's legacy type names), 0 for one ffdtool skips not.
struct LegacyType {
  std::size_t size = 0;
  bool is_signed = true, is_float = false;
};

LegacyType legacy_type(std::string_view name) {
  const std::string n = upper(name);
  if (n == "BIT") return {};
  if (n == "CHAR" || n == "VTKTYPEINT8") return {1, true, false};
  if (n == "UNSIGNED_CHAR" || n == "VTKTYPEUINT8") return {1, false, false};
  if (n == "SHORT" || n == "VTKTYPEINT16") return {2, true, false};
  if (n == "UNSIGNED_SHORT" || n == "VTKTYPEUINT16") return {2, false, false};
  if (n == "INT" || n == "VTKTYPEINT32" || n == "VTKIDTYPE") return {4, true, false};
  if (n == "UNSIGNED_INT" || n == "VTKTYPEUINT32") return {4, false, false};
  if (n == "LONG" || n == "VTKTYPEINT64") return {8, true, false};
  if (n == "UNSIGNED_LONG" || n == "VTKTYPEUINT64") return {8, false, false};
  if (n == "FLOAT") return {4, true, true};
  if (n == "DOUBLE") return {8, true, true};
  return {};
}

std::int64_t load_big_integer(const char* at, LegacyType t) {
  std::uint64_t u = 0;
  for (std::size_t k = 0; k < t.size; ++k) u = (u << 8) | static_cast<std::uint8_t>(at[k]);
  if (t.is_signed && t.size < 8 && (u >> (8 * t.size - 1)))
    return static_cast<std::int64_t>(u) - (std::int64_t{1} << (8 * t.size));
  if (t.is_signed && t.size == 8) return static_cast<std::int64_t>(u);  // two's complement (C++20)
  return u > static_cast<std::uint64_t>(INT64_MAX) ? INT64_MAX : static_cast<std::int64_t>(u);
}

using RangeMessage = std::function<std::string(std::uint64_t index, long long value)>;

// `count` integers of type t from pos, each in [lo, hi] (else the message `range` makes).
template <class T>
void read_integers(Legacy& f, std::uint64_t count, LegacyType t, long long lo, long long hi, std::vector<T>& out,
                   const RangeMessage& range) {
  const std::size_t left = f.bytes.size() - f.pos;
  if (f.binary ? count > left / t.size : count > left / 2 + 1)
    fail(f, f.pos, "the file is too short to hold " + std::to_string(count) + " values");
  out.resize(count);
  if (f.binary) {
    for (std::uint64_t i = 0; i < count; ++i) {
      const std::int64_t v = load_big_integer(f.bytes.data() + f.pos, t);
      if (v < lo || v > hi) fail(f, f.pos, range(i, v));
      out[i] = static_cast<T>(v);
      f.pos += t.size;
    }
    return;
  }
  for (std::uint64_t i = 0; i < count; ++i) {
    std::size_t at;
    const std::string_view token = next_token(f, at);
    long long v;
    const auto [next, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (token.empty()) fail(f, at, "the file ends after " + std::to_string(i) + " of " + std::to_string(count) + " values");
    if (ec != std::errc() || next != token.data() + token.size()) fail(f, at, "'" + std::string(token) + "' is not an integer");
    if (v < lo || v > hi) fail(f, at, range(i, v));
    out[i] = static_cast<T>(v);
  }
}

struct PointsRead {
  Eigen::Matrix3Xd points;
  std::vector<std::uint64_t> spans;  // ASCII: each node's text
  BinaryBlock block;                 // BINARY
  bool is_double = true;
};

void read_ascii_points(Legacy& f, std::uint64_t n, bool is_double, PointsRead& r) {
  if (3 * n > (f.bytes.size() - f.pos) / 2 + 1) fail(f, f.pos, "the file is too short to hold " + std::to_string(n) + " points");
  r.points.resize(3, static_cast<Eigen::Index>(n));
  r.spans.resize(2 * n);
  for (std::uint64_t i = 0; i < 3 * n; ++i) {
    std::size_t at;
    const std::string_view token = next_token(f, at);
    if (token.empty()) fail(f, at, "the file ends after " + std::to_string(i) + " of " + std::to_string(3 * n) + " point coordinates");
    double x;
    const auto [next, ec] = std::from_chars(token.data(), token.data() + token.size(), x);
    if (ec != std::errc() || next != token.data() + token.size() || !std::isfinite(x))
      fail(f, at, "node " + std::to_string(i / 3) + ": '" + std::string(token) + "' is not a finite number");
    r.points(static_cast<Eigen::Index>(i % 3), static_cast<Eigen::Index>(i / 3)) = is_double ? x : static_cast<float>(x);
    if (i % 3 == 0) r.spans[2 * (i / 3)] = at;
    if (i % 3 == 2) r.spans[2 * (i / 3) + 1] = f.pos;
  }
}

PointsRead read_points(Legacy& f) {
  PointsRead r;
  const std::uint64_t n = count_token(f, "the number of points", UINT32_MAX);
  std::size_t at;
  const std::string type = upper(next_token(f, at));
  if (type != "FLOAT" && type != "DOUBLE")
    fail(f, at, "POINTS of type '" + type + "' are not supported; ffdtool reads float and double points");
  r.is_double = type == "DOUBLE";
  if (!f.binary) {
    read_ascii_points(f, n, r.is_double, r);
    return r;
  }
  end_line(f);
  const BinaryScalar scalar{r.is_double, true};
  const std::size_t size = r.is_double ? 8 : 4;
  if (3 * n > (f.bytes.size() - f.pos) / size) fail(f, f.pos, "the file is too short to hold " + std::to_string(n) + " points");
  r.block = {0, n, f.pos, 3 * size};
  r.points.resize(3, static_cast<Eigen::Index>(n));
  for (std::uint64_t i = 0; i < 3 * n; ++i) {
    const double x = read_binary_scalar(f.bytes.data() + f.pos + i * size, scalar);
    if (!std::isfinite(x)) fail(f, f.pos + i * size, "node " + std::to_string(i / 3) + " has a coordinate that is not finite");
    r.points(static_cast<Eigen::Index>(i % 3), static_cast<Eigen::Index>(i / 3)) = x;
  }
  f.pos += 3 * n * size;
  return r;
}

RangeMessage node_range(std::uint64_t nodes) {
  return [nodes](std::uint64_t, long long v) {
    return "node index " + std::to_string(v) + " out of range (the file has " + std::to_string(nodes) + " nodes)";
  };
}

// 5.1's form: OFFSETS type (ncells + 1 begin offsets), CONNECTIVITY type.
void read_offset_cells(Legacy& f, std::uint64_t n_offsets, std::uint64_t size, std::uint64_t nodes, VolumeCells& cells) {
  std::size_t at;
  for (const char* keyword : {"OFFSETS", "CONNECTIVITY"}) {
    const bool offsets = keyword[0] == 'O';
    if (upper(next_token(f, at)) != keyword) fail(f, at, std::string("expected ") + keyword);
    const std::string_view type_name = token_or_fail(f, "the type");
    const LegacyType t = legacy_type(type_name);
    if (t.size == 0 || t.is_float) fail(f, at, std::string(keyword) + " of type '" + std::string(type_name) + "' are not integers");
    if (f.binary) end_line(f);
    if (offsets) {
      read_integers(f, n_offsets, t, 0, static_cast<long long>(size), cells.offset,
                    [size](std::uint64_t i, long long v) { return "offset " + std::to_string(i) + " (" + std::to_string(v) + ") is outside 0.." + std::to_string(size); });
      if (n_offsets == 0) cells.offset.assign(1, 0);
      for (std::size_t c = 1; c < cells.offset.size(); ++c)
        if (cells.offset[c] < cells.offset[c - 1]) fail(f, at, "OFFSETS decrease at cell " + std::to_string(c));
      if (cells.offset.front() != 0 || cells.offset.back() != size)
        fail(f, at, "OFFSETS must run from 0 to the connectivity's size " + std::to_string(size));
    } else {
      read_integers(f, size, t, 0, static_cast<long long>(nodes) - 1, cells.node, node_range(nodes));
    }
  }
}

// The old form: per cell its node count, then its nodes (int).
void read_counted_cells(Legacy& f, std::uint64_t ncells, std::uint64_t size, std::uint64_t nodes, VolumeCells& cells) {
  std::vector<std::uint32_t> stream;
  read_integers(f, size, LegacyType{4, true, false}, 0, UINT32_MAX, stream,
                [](std::uint64_t i, long long v) { return "CELLS value " + std::to_string(i) + " (" + std::to_string(v) + ") is negative"; });
  cells.offset.reserve(ncells + 1);
  cells.node.reserve(size - std::min(size, ncells));
  std::uint64_t j = 0;
  for (std::uint64_t c = 0; c < ncells; ++c) {
    if (j >= size || stream[j] > size - j - 1)
      fail(f, f.pos, "CELLS' size " + std::to_string(size) + " does not match the node counts of its " + std::to_string(ncells) + " cells");
    for (std::uint64_t k = j + 1; k <= j + stream[j]; ++k) {
      if (stream[k] >= nodes) fail(f, f.pos, "cell " + std::to_string(c) + ": " + node_range(nodes)(k, stream[k]));
      cells.node.push_back(stream[k]);
    }
    j += 1 + stream[j];
    cells.offset.push_back(cells.node.size());
  }
  if (j != size) fail(f, f.pos, "CELLS' size " + std::to_string(size) + " does not match the node counts of its " + std::to_string(ncells) + " cells");
}

void read_cells(Legacy& f, std::uint64_t nodes, VolumeCells& cells) {
  const std::uint64_t n = count_token(f, "the number of cells", std::uint64_t{1} << 40);
  const std::uint64_t size = count_token(f, "the size of the cell list", std::uint64_t{1} << 42);
  if (f.binary) end_line(f);
  const std::size_t mark = f.pos;
  std::size_t at;
  const bool offset_form = upper(next_token(f, at)) == "OFFSETS";
  f.pos = mark;
  if (offset_form)
    read_offset_cells(f, n, size, nodes, cells);
  else
    read_counted_cells(f, n, size, nodes, cells);
}

void read_cell_types(Legacy& f, VolumeCells& cells) {
  const std::size_t at = f.pos;
  const std::uint64_t n = count_token(f, "the number of cell types", std::uint64_t{1} << 40);
  if (n != cells.offset.size() - 1)
    fail(f, at, "CELL_TYPES has " + std::to_string(n) + " cells where CELLS has " + std::to_string(cells.offset.size() - 1));
  if (f.binary) end_line(f);
  while (!f.binary && f.pos < f.bytes.size() && is_space(f.bytes[f.pos])) ++f.pos;
  const std::size_t first = f.pos;  // the first type, where a bad cell is reported
  read_integers(f, n, LegacyType{4, true, false}, 0, 255, cells.type,
                [](std::uint64_t i, long long v) { return "cell " + std::to_string(i) + ": unknown cell type " + std::to_string(v); });
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (cells.type[c] == cell_type::kPolyhedron)
      fail(f, first, "cell " + std::to_string(c) + " is a polyhedron; ffdtool reads polyhedra from VTU files, not legacy VTK");
    if (!vtk_cell_fits(cells.type[c], cells.degree(c)))
      fail(f, first, "cell " + std::to_string(c) + ": " + vtk_cell_problem(cells.type[c], cells.degree(c)));
  }
}

// Skips a METADATA block: its lines up to a blank one.
void skip_metadata(Legacy& f) {
  next_line(f);
  while (f.pos < f.bytes.size()) {
    const std::string_view line = next_line(f);
    if (std::all_of(line.begin(), line.end(), is_space)) return;
  }
}

// Skips a FIELD before the cells: its arrays, "NAME COMPONENTS TUPLES TYPE" and values.
void skip_field(Legacy& f) {
  token_or_fail(f, "the FIELD's name");
  const std::uint64_t arrays = count_token(f, "the FIELD's number of arrays", 1u << 20);
  for (std::uint64_t k = 0; k < arrays; ++k) {
    std::size_t at;
    std::string_view name = next_token(f, at);
    if (name == "METADATA") {
      skip_metadata(f);
      name = next_token(f, at);
    }
    if (name.empty()) fail(f, at, "the file ends inside a FIELD");
    if (name == "NULL_ARRAY") continue;
    const std::uint64_t components = count_token(f, "the array's components", 1u << 20);
    const std::uint64_t tuples = count_token(f, "the array's tuples", std::uint64_t{1} << 40);
    const std::string_view type_name = token_or_fail(f, "the array's type");
    const LegacyType t = legacy_type(type_name);
    if (t.size == 0) fail(f, at, "FIELD array of type '" + std::string(type_name) + "' before the cells is not supported");
    const std::uint64_t count = components * tuples;
    if (f.binary) {
      end_line(f);
      if (count > (f.bytes.size() - f.pos) / t.size) fail(f, f.pos, "the file ends inside FIELD array " + std::string(name));
      f.pos += count * t.size;
    } else {
      for (std::uint64_t i = 0; i < count; ++i)
        if (next_token(f, at).empty()) fail(f, at, "the file ends inside FIELD array " + std::string(name));
    }
  }
}

}  // namespace

VolumeRead read_vtk_legacy(SharedBytes bytes, const std::string& path) {
  Legacy f(*bytes, path);
  VolumeRead out;
  out.source.format = VolumeFormat::Vtk;
  out.source.version = read_header(f);
  out.source.encoding = f.binary ? "binary" : "ascii";
  VolumeCells& cells = out.source.cells;
  std::optional<PointsRead> points;
  bool have_cells = false, have_types = false;
  while (!(points && have_cells && have_types)) {
    std::size_t at;
    const std::string keyword = upper(next_token(f, at));
    if (keyword.empty() || keyword == "POINT_DATA" || keyword == "CELL_DATA") break;
    if (keyword == "POINTS" && !points) points = read_points(f);
    else if (keyword == "CELLS" && points && !have_cells) read_cells(f, static_cast<std::uint64_t>(points->points.cols()), cells), have_cells = true;
    else if (keyword == "CELL_TYPES" && have_cells && !have_types) read_cell_types(f, cells), have_types = true;
    else if (keyword == "FIELD") skip_field(f);
    else if (keyword == "METADATA") skip_metadata(f);
    else fail(f, at, "unexpected '" + keyword + "' (expected POINTS, then CELLS, then CELL_TYPES)");
  }
  if (!points) fail(f, f.pos, "the file has no POINTS");
  if (have_cells != have_types) fail(f, f.pos, "the file has CELLS but no CELL_TYPES");
  out.points = points->points;
  if (f.binary)
    out.source.file = std::make_shared<BinaryPoints>(bytes, std::vector<BinaryBlock>{points->block}, BinaryScalar{points->is_double, true}, 3);
  else
    out.source.file = std::make_shared<TextPoints>(bytes, std::move(points->spans), 3, out.points);
  return out;
}

}  // namespace ffd
