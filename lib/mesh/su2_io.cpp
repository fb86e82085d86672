#include "mesh/su2_io.h"

#include <charconv>
#include <limits>

#include "common/errors.h"
#include "mesh/text_lines.h"
#include "mesh/volume_patch.h"

namespace ffd {
namespace {

// The SU2 element kinds (VTK's numbers) with their node counts.
int su2_node_count(long long type) {
  switch (type) {
    case cell_type::kLine: return 2;
    case cell_type::kTriangle: return 3;
    case cell_type::kQuad: return 4;
    case cell_type::kTetra: return 4;
    case cell_type::kHexahedron: return 8;
    case cell_type::kWedge: return 6;
    case cell_type::kPyramid: return 5;
    default: return 0;
  }
}

// Walks the file's lines, skipping blank ones and `%` comments, with line numbers.
class Su2Lines {
public:
  Su2Lines(std::string_view text, const std::string& path) : text_(text), lines_(text), path_(path) {}
  /// The next line with content (comment removed); false at the end of the file.
  bool next(std::string_view& line) {
    while (lines_.next(line)) {
      const std::size_t percent = line.find('%');
      if (percent != std::string_view::npos) line = line.substr(0, percent);
      const char* p = skip_blanks(line.data(), line.data() + line.size());
      if (p < line.data() + line.size()) return true;
    }
    return false;
  }
  /// The next line with content, or an error naming what was expected.
  std::string_view expect(const char* what) {
    std::string_view line;
    if (!next(line)) fail_at(lines_.number(), std::string("the file ends before ") + what);
    return line;
  }
  /// The byte offset of `p` (a pointer into the current line) in the file.
  std::uint64_t offset(const char* p) const { return static_cast<std::uint64_t>(p - text_.data()); }
  std::size_t number() const { return lines_.number(); }
  [[noreturn]] void fail(const std::string& message) const { fail_at(lines_.number(), message); }
  [[noreturn]] void fail_at(std::size_t line, const std::string& message) const {
    throw InputError(At{place(path_, line)}, message);
  }

private:
  std::string_view text_;
  LineScanner lines_;
  const std::string& path_;
};

// "KEY= value" (spaces allowed around '='): the value's text, or empty if `line` is not KEY.
bool keyword(std::string_view line, std::string_view key, std::string_view& value) {
  const char* p = skip_blanks(line.data(), line.data() + line.size());
  std::string_view rest(p, static_cast<std::size_t>(line.data() + line.size() - p));
  if (rest.substr(0, key.size()) != key) return false;
  rest.remove_prefix(key.size());
  const char* q = skip_blanks(rest.data(), rest.data() + rest.size());
  if (q == rest.data() + rest.size() || *q != '=') return false;
  ++q;
  q = skip_blanks(q, rest.data() + rest.size());
  value = std::string_view(q, static_cast<std::size_t>(rest.data() + rest.size() - q));
  while (!value.empty() && blank(value.back())) value.remove_suffix(1);
  return true;
}

// The non-negative count after KEY=, within `limit`; the line must be KEY=. NPOIN= may
// give a second count (the nodes a partition owns), which is checked and ignored.
std::size_t read_count(Su2Lines& lines, std::string_view line, std::string_view key, std::size_t limit,
                       bool second = false) {
  std::string_view value;
  if (!keyword(line, key, value))
    lines.fail("expected " + std::string(key) + "= here, found '" + std::string(line.substr(0, 40)) + "'");
  const char* p = value.data();
  const char* end = p + value.size();
  long long count = 0, owned = 0;
  const bool ok = fast_integer(p, end, count) && count >= 0 &&
                  (p == end || (second && fast_integer(p = skip_blanks(p, end), end, owned) && p == end));
  if (!ok) lines.fail(std::string(key) + "= needs a non-negative count, found '" + std::string(value) + "'");
  if (static_cast<unsigned long long>(count) > limit)
    lines.fail(std::string(key) + "= " + std::to_string(count) + " is more than the rest of the file can hold");
  return static_cast<std::size_t>(count);
}

// One element line: its type and `count` node indices below `nodes` (the file's optional
// trailing element index is allowed and ignored). Appends it to `cells`.
void read_element(Su2Lines& lines, std::string_view line, std::size_t nodes, VolumeCells& cells,
                  bool check_nodes) {
  const char* p = line.data();
  const char* end = p + line.size();
  long long type = 0;
  p = skip_blanks(p, end);
  if (!fast_integer(p, end, type)) lines.fail("an element line starts with its type, found '" + std::string(line) + "'");
  const int count = su2_node_count(type);
  if (count == 0) lines.fail("element type " + std::to_string(type) + " is not an SU2 element (3, 5, 9, 10, 12, 13, 14)");
  std::uint32_t ids[8];
  for (int k = 0; k < count; ++k) {
    long long id = -1;
    p = skip_blanks(p, end);
    if (!fast_integer(p, end, id)) lines.fail(cell_type_name(static_cast<std::uint8_t>(type)) + " needs " + std::to_string(count) + " node indices");
    if (id < 0 || (check_nodes && static_cast<unsigned long long>(id) >= nodes))
      lines.fail("node index " + std::to_string(id) + " out of range (the file has " + std::to_string(nodes) + " nodes)");
    ids[k] = static_cast<std::uint32_t>(id);
  }
  long long index = 0;
  p = skip_blanks(p, end);
  if (p < end && !fast_integer(p, end, index)) lines.fail("unexpected text after the element's nodes");
  if (skip_blanks(p, end) != end) lines.fail("unexpected text after the element's index");
  cells.add(static_cast<std::uint8_t>(type), ids, static_cast<std::size_t>(count));
}

}  // namespace

namespace {

// What the reader has seen so far.
struct Su2State {
  int dimension = 0;
  std::size_t points_line = 0;   // where NPOIN= is (0: not yet)
  std::size_t elements_line = 0; // where NELEM= is
  std::size_t volume_cells = 0;  // NELEM
  bool markers = false;
  VolumeRead read;
  std::vector<std::uint64_t> spans;
  std::vector<std::size_t> marker_lines;  // where each marker's MARKER_TAG= is
  std::vector<std::size_t> marker_first;  // the cell each marker's elements start at
};

// NPOIN's nodes: `dimension` numbers each, then an optional index. Records each node's
// span for the writer.
void read_points(Su2Lines& lines, std::size_t count, Su2State& state) {
  Eigen::Matrix3Xd& points = state.read.points;
  points.setZero(3, static_cast<Eigen::Index>(count));
  state.spans.resize(2 * count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::string_view line = lines.expect("every node of NPOIN is read");
    const char* p = line.data();
    const char* end = p + line.size();
    double x[3] = {0, 0, 0};
    p = skip_blanks(p, end);
    state.spans[2 * i] = lines.offset(p);
    for (int k = 0; k < state.dimension; ++k) {
      p = skip_blanks(p, end);
      if (!fast_number(p, end, x[k]))
        lines.fail("a node needs " + std::to_string(state.dimension) + " finite coordinates, found '" + std::string(line) + "'");
    }
    state.spans[2 * i + 1] = lines.offset(p);
    long long index = 0;
    p = skip_blanks(p, end);
    if (p < end && (!fast_integer(p, end, index) || skip_blanks(p, end) != end))
      lines.fail("unexpected text after the node's coordinates");
    points.col(static_cast<Eigen::Index>(i)) = Eigen::Vector3d(x[0], x[1], x[2]);
  }
}

// NMARK's markers: MARKER_TAG= name, MARKER_ELEMS= n, then n boundary elements.
void read_markers(Su2Lines& lines, std::size_t count, std::size_t limit, Su2State& state) {
  VolumeSource& source = state.read.source;
  for (std::size_t m = 0; m < count; ++m) {
    std::string_view line = lines.expect("every marker of NMARK is read");
    std::string_view name;
    if (!keyword(line, "MARKER_TAG", name)) lines.fail("expected MARKER_TAG= here");
    if (name.empty()) lines.fail("MARKER_TAG= needs a name");
    state.marker_lines.push_back(lines.number());
    state.marker_first.push_back(source.cells.size());
    const std::size_t elements = read_count(lines, lines.expect("MARKER_ELEMS="), "MARKER_ELEMS", limit);
    VolumeMarker marker{std::string(name), state.dimension - 1, {}};
    marker.cells.reserve(elements);
    for (std::size_t e = 0; e < elements; ++e) {
      marker.cells.push_back(source.cells.size());
      read_element(lines, lines.expect("every element of the marker is read"), 0, source.cells, false);
    }
    source.markers.push_back(std::move(marker));
  }
}

// Reads one top-level section starting at `line`; false when `line` is none of them.
bool read_section(Su2Lines& lines, std::string_view line, std::size_t limit, Su2State& state) {
  std::string_view value;
  if (keyword(line, "NZONE", value) || keyword(line, "IZONE", value))
    lines.fail("multi-zone SU2 files (NZONE) are not supported; split the zones into files of their own");
  if (keyword(line, "NDIME", value)) {
    const std::size_t d = read_count(lines, line, "NDIME", 3);
    if (d != 2 && d != 3) lines.fail("NDIME= must be 2 or 3");
    state.dimension = static_cast<int>(d);
    return true;
  }
  if (state.dimension == 0) lines.fail("an SU2 mesh starts with NDIME=");
  if (keyword(line, "NELEM", value)) {
    if (state.elements_line) lines.fail("a second NELEM=");
    state.volume_cells = read_count(lines, line, "NELEM", limit);
    state.elements_line = lines.number();
    if (!state.read.source.cells.type.empty()) lines.fail("NELEM= must come before NMARK=");
    state.read.source.cells.type.reserve(state.volume_cells);
    state.read.source.cells.node.reserve(4 * state.volume_cells);
    for (std::size_t e = 0; e < state.volume_cells; ++e)
      read_element(lines, lines.expect("every element of NELEM is read"), 0, state.read.source.cells, false);
    return true;
  }
  if (keyword(line, "NPOIN", value)) {
    if (state.points_line) lines.fail("a second NPOIN=");
    state.points_line = lines.number();
    read_points(lines, read_count(lines, line, "NPOIN", limit, true), state);
    return true;
  }
  if (keyword(line, "NMARK", value)) {
    if (!state.elements_line) lines.fail("NMARK= must come after NELEM=");
    state.markers = true;
    read_markers(lines, read_count(lines, line, "NMARK", limit), limit, state);
    return true;
  }
  return false;
}

}  // namespace

namespace {

// The line of volume element `k` (counted from NELEM=), found again for a message.
std::size_t element_line(std::string_view text, const std::string& path, std::size_t elements_line, std::size_t k) {
  Su2Lines lines(text, path);
  std::string_view line;
  while (lines.number() < elements_line && lines.next(line)) {
  }
  for (std::size_t i = 0; i <= k && lines.next(line);) ++i;
  return lines.number();
}

// Every node index of every element below the node count; markers' elements included.
void check_node_indices(std::string_view text, const std::string& path, const Su2State& state) {
  const VolumeCells& cells = state.read.source.cells;
  const std::size_t nodes = static_cast<std::size_t>(state.read.points.cols());
  for (std::size_t c = 0; c < cells.size(); ++c)
    for (std::size_t k = 0; k < cells.degree(c); ++k) {
      const std::uint32_t id = cells.nodes(c)[k];
      if (id < nodes) continue;
      std::size_t line = 0;
      if (c < state.volume_cells) {
        line = element_line(text, path, state.elements_line, c);
      } else {
        std::size_t m = 0;  // the marker holding cell c (markers may be empty): its elements follow its header
        while (m + 1 < state.marker_first.size() && state.marker_first[m + 1] <= c) ++m;
        line = element_line(text, path, state.marker_lines[m] + 1, c - state.marker_first[m]);
      }
      throw InputError(At{place(path, line)}, "node index " + std::to_string(id) + " out of range (the file has " +
                                                  std::to_string(nodes) + " nodes)");
    }
}

}  // namespace

VolumeRead read_su2(SharedBytes bytes, const std::string& path) {
  const std::string_view text = *bytes;
  Su2Lines lines(text, path);
  Su2State state;
  const std::size_t limit = text.size() / 2 + 1;  // each element, node or marker takes two bytes at least
  std::string_view line;
  while (!(state.points_line && state.markers) && lines.next(line))
    if (!read_section(lines, line, limit, state)) {
      if (state.points_line && state.elements_line) break;  // what follows is kept as it is
      lines.fail("expected NDIME=, NELEM=, NPOIN= or NMARK= here, found '" + std::string(line.substr(0, 40)) + "'");
    }
  if (state.dimension == 0) throw InputError(At{path}, "not an SU2 mesh: no NDIME=");
  if (!state.elements_line) throw InputError(At{path}, "the SU2 mesh has no NELEM= section");
  if (!state.points_line) throw InputError(At{path}, "the SU2 mesh has no NPOIN= section");
  check_node_indices(text, path, state);
  VolumeSource& source = state.read.source;
  source.format = VolumeFormat::Su2;
  source.encoding = "ascii";
  source.dimension = state.dimension;
  source.file = std::make_shared<TextPoints>(std::move(bytes), std::move(state.spans), state.dimension, state.read.points);
  return std::move(state.read);
}

}  // namespace ffd
