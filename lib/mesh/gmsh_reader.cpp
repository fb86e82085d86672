#include "mesh/gmsh_reader.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/volume_patch.h"

namespace ffd::msh {
namespace {

bool space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t' || c == '\v' || c == '\f'; }

}  // namespace

std::string quoted(std::string_view token) {
  if (token.size() > 40) return "'" + std::string(token.substr(0, 40)) + "...'";
  return "'" + std::string(token) + "'";
}

// ---- Cursor: text ----

std::string_view Cursor::token() {
  const char* p = text_.data() + pos;
  const char* end = text_.data() + text_.size();
  while (p < end && space(*p)) ++p;
  const char* start = p;
  while (p < end && !space(*p)) ++p;
  last_ = static_cast<std::size_t>(start - text_.data());
  pos = static_cast<std::size_t>(p - text_.data());
  return {start, static_cast<std::size_t>(p - start)};
}

std::uint64_t Cursor::count(const char* what) {
  const std::string_view t = token();
  std::uint64_t value = 0;
  const auto [next, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (t.empty()) fail(std::string("the file ends where ") + what + " should be");
  if (ec != std::errc() || next != t.data() + t.size())
    fail(std::string("expected ") + what + " (a non-negative integer), found " + quoted(t));
  return value;
}

std::int64_t Cursor::integer(const char* what) {
  const std::string_view t = token();
  std::int64_t value = 0;
  const auto [next, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (t.empty()) fail(std::string("the file ends where ") + what + " should be");
  if (ec != std::errc() || next != t.data() + t.size())
    fail(std::string("expected ") + what + " (an integer), found " + quoted(t));
  return value;
}

double Cursor::number(const char* what) {
  const std::string_view t = token();
  double value = 0;
  if (t.empty()) fail(std::string("the file ends where ") + what + " should be");
  if (!parse_finite(t, value)) fail(std::string(what) + " " + quoted(t) + " is not a finite number");
  return value;
}

void Cursor::expect(std::string_view word) {
  const std::string_view t = token();
  if (t.empty()) fail("the file ends where " + std::string(word) + " should be");
  if (t != word) fail("expected " + std::string(word) + ", found " + quoted(t));
}

void Cursor::end_line() {
  while (pos < text_.size() && (text_[pos] == ' ' || text_[pos] == '\t' || text_[pos] == '\r')) ++pos;
  if (pos >= text_.size() || text_[pos] != '\n') fail(pos, "expected the end of the line before binary data");
  ++pos;
}

// ---- Cursor: binary ----

void Cursor::need(std::uint64_t bytes, const char* what) {
  last_ = pos;
  if (bytes > left())
    fail(pos, std::string("the file ends inside ") + what + " (" + std::to_string(bytes) + " bytes needed, " +
                  std::to_string(left()) + " left)");
}

std::int32_t Cursor::int32(const char* what) {
  need(4, what);
  pos += 4;
  return load_bytes<std::int32_t>(text_.data() + pos - 4, swap);
}

std::uint64_t Cursor::size_value(const char* what) {
  need(static_cast<std::uint64_t>(size_bytes), what);
  pos += static_cast<std::size_t>(size_bytes);
  return load_size(text_.data() + pos - size_bytes);
}

double Cursor::real(const char* what) {
  need(8, what);
  pos += 8;
  const double value = load_real(text_.data() + pos - 8);
  if (!std::isfinite(value)) fail(std::string(what) + " is not a finite number");
  return value;
}

void Cursor::skip_real(const char* what) {
  if (binary) {
    need(8, what);
    pos += 8;
  } else if (token().empty()) {
    fail(std::string("the file ends where ") + what + " should be");
  }
}

std::int32_t Cursor::load_int32(const char* at) const { return load_bytes<std::int32_t>(at, swap); }

std::uint64_t Cursor::load_size(const char* at) const {
  return size_bytes == 8 ? load_bytes<std::uint64_t>(at, swap) : load_bytes<std::uint32_t>(at, swap);
}

double Cursor::load_real(const char* at) const { return load_bytes<double>(at, swap); }

// ---- Cursor: errors ----

void Cursor::fits(std::uint64_t count, std::uint64_t bytes_each, const char* what) {
  if (count > left() / bytes_each)
    fail("the file promises " + std::to_string(count) + " " + what + ", more than its remaining " +
         std::to_string(left()) + " bytes can hold");
}

std::string Cursor::where(std::size_t at) const {
  at = std::min(at, text_.size());
  if (binary) return path_ + ": byte " + std::to_string(at);
  const auto lines = std::count(text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  return path_ + ":" + std::to_string(lines + 1);
}

void Cursor::fail(std::size_t at, const std::string& message) const { throw InputError(At{where(at)}, message); }

// ---- Element kinds ----

namespace {

// VTK's corner order from Gmsh's (meshio's _gmsh_to_meshio_order, checked against both
// manuals): the kinds whose edge and face nodes are numbered differently.
constexpr std::uint8_t kTet10[] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
constexpr std::uint8_t kHex20[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15};
constexpr std::uint8_t kHex27[] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  11, 13, 9,  16, 18,
                                   19, 17, 10, 12, 14, 15, 22, 23, 21, 24, 20, 25, 26};
// A Gmsh prism's first triangle (0, 1, 2) winds with its normal into the prism, a VTK
// wedge's out of it (vtkWedge's documentation; meshio's _vtk_common.py says the same):
// VTK's corners are Gmsh's 0 2 1 3 5 4. The 15-node prism takes the same flip, its edge
// nodes following their edges (meshio keeps Gmsh's corner order there, which the guard
// would count as inverted).
constexpr std::uint8_t kWedge[] = {0, 2, 1, 3, 5, 4};
constexpr std::uint8_t kWedge15[] = {0, 2, 1, 3, 5, 4, 7, 9, 6, 13, 14, 12, 8, 11, 10};
constexpr std::uint8_t kPyramid13[] = {0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12};

// Gmsh's element types with a fixed node count (GmshDefines.h; node counts as Gmsh 4.8's
// getElementProperties gives them, and by their names for the prisms it leaves out).
struct KindRow {
  std::uint8_t type;
  std::uint16_t nodes;
  std::int8_t dimension;
};
constexpr KindRow kRows[] = {
    {1, 2, 1},     {2, 3, 2},     {3, 4, 2},     {4, 4, 3},     {5, 8, 3},     {6, 6, 3},     {7, 5, 3},
    {8, 3, 1},     {9, 6, 2},     {10, 9, 2},    {11, 10, 3},   {12, 27, 3},   {13, 18, 3},   {14, 14, 3},
    {15, 1, 0},    {16, 8, 2},    {17, 20, 3},   {18, 15, 3},   {19, 13, 3},   {20, 9, 2},    {21, 10, 2},
    {22, 12, 2},   {23, 15, 2},   {24, 15, 2},   {25, 21, 2},   {26, 4, 1},    {27, 5, 1},    {28, 6, 1},
    {29, 20, 3},   {30, 35, 3},   {31, 56, 3},   {32, 22, 3},   {33, 28, 3},   {36, 16, 2},   {37, 25, 2},
    {38, 36, 2},   {39, 12, 2},   {40, 16, 2},   {41, 20, 2},   {42, 28, 2},   {43, 36, 2},   {44, 45, 2},
    {45, 55, 2},   {46, 66, 2},   {47, 49, 2},   {48, 64, 2},   {49, 81, 2},   {50, 100, 2},  {51, 121, 2},
    {52, 18, 2},   {53, 21, 2},   {54, 24, 2},   {55, 27, 2},   {56, 30, 2},   {57, 24, 2},   {58, 28, 2},
    {59, 32, 2},   {60, 36, 2},   {61, 40, 2},   {62, 7, 1},    {63, 8, 1},    {64, 9, 1},    {65, 10, 1},
    {66, 11, 1},   {71, 84, 3},   {72, 120, 3},  {73, 165, 3},  {74, 220, 3},  {75, 286, 3},  {79, 34, 3},
    {80, 40, 3},   {81, 46, 3},   {82, 52, 3},   {83, 58, 3},   {84, 1, 1},    {85, 1, 2},    {86, 1, 2},
    {87, 1, 3},    {88, 1, 3},    {89, 1, 3},    {90, 40, 3},   {91, 75, 3},   {92, 64, 3},   {93, 125, 3},
    {94, 216, 3},  {95, 343, 3},  {96, 512, 3},  {97, 729, 3},  {98, 1000, 3}, {99, 32, 3},   {100, 44, 3},
    {101, 56, 3},  {102, 68, 3},  {103, 80, 3},  {104, 92, 3},  {105, 104, 3}, {106, 126, 3}, {107, 196, 3},
    {108, 288, 3}, {109, 405, 3}, {110, 550, 3}, {111, 24, 3},  {112, 33, 3},  {113, 42, 3},  {114, 51, 3},
    {115, 60, 3},  {116, 69, 3},  {117, 78, 3},  {118, 30, 3},  {119, 55, 3},  {120, 91, 3},  {121, 140, 3},
    {122, 204, 3}, {123, 285, 3}, {124, 385, 3}, {125, 21, 3},  {126, 29, 3},  {127, 37, 3},  {128, 45, 3},
    {129, 53, 3},  {130, 61, 3},  {131, 69, 3},  {132, 1, 3},   {137, 16, 3},  {138, 4, 2},   {139, 5, 3},
    {140, 4, 3}};

// Gmsh's types whose node count varies (polygons, polyhedra, boundary and XFEM kinds).
constexpr std::uint8_t kVariable[] = {34, 35, 67, 68, 69, 70, 133, 134, 135, 136};
constexpr std::size_t kMaxType = 140;

// The VTK kind and corner order of a Gmsh type (kOtherCell: none).
void set_vtk(ElementKind& kind, int type) {
  using namespace cell_type;
  struct Vtk {
    int gmsh;
    std::uint8_t vtk;
    const std::uint8_t* order;
  };
  static constexpr Vtk kVtk[] = {{1, kLine, nullptr},         {2, kTriangle, nullptr},
                                 {3, kQuad, nullptr},         {4, kTetra, nullptr},
                                 {5, kHexahedron, nullptr},   {6, cell_type::kWedge, kWedge},
                                 {7, kPyramid, nullptr},      {8, kQuadraticEdge, nullptr},
                                 {9, kQuadraticTriangle, nullptr}, {10, kBiquadraticQuad, nullptr},
                                 {11, kQuadraticTetra, kTet10}, {12, kTriquadraticHexahedron, kHex27},
                                 {15, kVertex, nullptr},      {16, kQuadraticQuad, nullptr},
                                 {17, kQuadraticHexahedron, kHex20}, {18, kQuadraticWedge, kWedge15},
                                 {19, kQuadraticPyramid, kPyramid13}};
  for (const Vtk& v : kVtk)
    if (v.gmsh == type) {
      kind.vtk = v.vtk;
      kind.order = v.order;
    }
}

std::array<ElementKind, kMaxType + 1> make_kinds() {
  std::array<ElementKind, kMaxType + 1> kinds{};
  for (const KindRow& row : kRows) {
    kinds[row.type].nodes = row.nodes;
    kinds[row.type].dimension = row.dimension;
    set_vtk(kinds[row.type], row.type);
  }
  return kinds;
}

}  // namespace

const ElementKind& element_kind(std::int64_t type, const Cursor& cursor) {
  static const std::array<ElementKind, kMaxType + 1> kinds = make_kinds();
  if (type >= 0 && type <= static_cast<std::int64_t>(kMaxType) && kinds[static_cast<std::size_t>(type)].nodes)
    return kinds[static_cast<std::size_t>(type)];
  if (std::find(std::begin(kVariable), std::end(kVariable), type) != std::end(kVariable))
    cursor.fail("element type " + std::to_string(type) + " has no fixed node count (polygons, polyhedra and "
                "XFEM elements are not read)");
  cursor.fail("element type " + std::to_string(type) + " is not a Gmsh element type");
}

// ---- Nodes ----

void NodeMap::build(const std::vector<std::uint64_t>& tags, const Cursor& cursor, std::size_t at) {
  if (tags.empty()) return;
  const auto [lo, hi] = std::minmax_element(tags.begin(), tags.end());
  if (*lo == 0) cursor.fail(at, "node tag 0 in $Nodes (Gmsh's tags start at 1)");
  min_ = *lo;
  const std::uint64_t range = *hi - *lo;  // no overflow: both are uint64
  const bool dense = range < 2 * static_cast<std::uint64_t>(tags.size()) + 1024;
  if (dense) dense_.assign(static_cast<std::size_t>(range) + 1, kMissing);
  if (!dense) sparse_.reserve(tags.size());
  for (std::size_t i = 0; i < tags.size(); ++i) {
    const bool fresh = dense ? dense_[tags[i] - min_] == kMissing
                             : sparse_.emplace(tags[i], static_cast<std::uint32_t>(i)).second;
    if (!fresh) cursor.fail(at, "node tag " + std::to_string(tags[i]) + " appears twice in $Nodes");
    if (dense) dense_[tags[i] - min_] = static_cast<std::uint32_t>(i);
  }
}

void MshMesh::reserve_nodes(std::uint64_t count, bool text) {
  points.resize(3, static_cast<Eigen::Index>(count));
  node_tags.reserve(count);
  if (text) spans.reserve(2 * count);
}

void MshMesh::finish_nodes(const Cursor& cursor, std::size_t at) {
  if (node_tags.size() >= NodeMap::kMissing)
    cursor.fail(at, "the file has " + std::to_string(node_tags.size()) + " nodes, more than 2^32 - 1");
  nodes.build(node_tags, cursor, at);
  node_tags = {};
  has_nodes = true;
}

void MshMesh::unknown_node(const std::string& node_tag, const std::string& element_tag, const Cursor& cursor,
                           std::size_t at) {
  cursor.fail(at, "element " + element_tag + " names node " + node_tag + ", which $Nodes does not list");
}

void MshMesh::add_element(const ElementKind& kind) {
  if (kind.dimension == 3) has_3d = true;
  if (!kind.order) return cells.add(kind.vtk, element, kind.nodes);
  std::uint32_t vtk[kMaxElementNodes];
  for (std::size_t c = 0; c < kind.nodes; ++c) vtk[c] = element[kind.order[c]];
  cells.add(kind.vtk, vtk, kind.nodes);
}

std::uint32_t* MshMesh::append_cells(const ElementKind& kind, std::uint64_t count) {
  if (kind.dimension == 3) has_3d = true;
  const std::size_t first = cells.node.size();
  cells.type.resize(cells.type.size() + count, kind.vtk);
  cells.offset.reserve(cells.offset.size() + count);
  for (std::uint64_t e = 1; e <= count; ++e) cells.offset.push_back(first + e * kind.nodes);
  cells.node.resize(first + count * kind.nodes);
  return cells.node.data() + first;
}

void MshMesh::to_vtk_order(const ElementKind& kind, std::uint32_t* cell_nodes, std::uint64_t count) const {
  if (!kind.order) return;
  std::uint32_t gmsh[kMaxElementNodes];
  for (std::uint64_t e = 0; e < count; ++e, cell_nodes += kind.nodes) {
    std::copy(cell_nodes, cell_nodes + kind.nodes, gmsh);
    for (std::size_t c = 0; c < kind.nodes; ++c) cell_nodes[c] = gmsh[kind.order[c]];
  }
}

}  // namespace ffd::msh
