// The elements of a mesh file in their order, as flat arrays: polygons of any size,
// orientation or multiplicity, OBJ lines and points. No topology, no per-element heap
// allocation; what a reader fills and a writer walks.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ffd {

/// What an element is: a polygon (OBJ f, OFF/PLY/STL faces), a polyline (OBJ l) or a
/// set of points (OBJ p).
enum class ElementKind : std::uint8_t { Polygon, Line, Point };

/// Throws InputError: more than 2^32 - 1 corners do not fit the offsets.
[[noreturn]] void throw_too_many_corners();

/// The OBJ grouping statements in force for an element (empty: never set).
struct ObjState {
  std::string object;    // o
  std::string group;     // g (the names after 'g', as written)
  std::string material;  // usemtl
  std::string smoothing; // s
  bool operator==(const ObjState& o) const {
    return object == o.object && group == o.group && material == o.material &&
           smoothing == o.smoothing;
  }
};

/// Element e has the corners offsets[e] .. offsets[e+1]-1; corner c is at vertex
/// corners[c]. The optional arrays are empty when no element has the attribute, else
/// one entry per corner (UVs, normals: -1 for none) or per element (groups: -1 for
/// none; lines: 0 when unknown).
struct MeshElements {
  std::vector<std::uint32_t> offsets = {0};
  std::vector<std::uint32_t> corners;
  std::vector<ElementKind> kinds;
  std::vector<std::int32_t> corner_uvs;      // index into Mesh::uvs
  std::vector<std::int32_t> corner_normals;  // index into Mesh::file_normals
  std::vector<std::int32_t> groups;          // index into Mesh::groups
  std::vector<std::uint32_t> lines;          // the file line that defined the element

  std::size_t size() const { return kinds.size(); }
  std::uint32_t begin(std::size_t e) const { return offsets[e]; }
  std::uint32_t end(std::size_t e) const { return offsets[e + 1]; }
  std::uint32_t degree(std::size_t e) const { return offsets[e + 1] - offsets[e]; }
  /// The first vertex of element e (its corners follow in corners[]).
  const std::uint32_t* vertices(std::size_t e) const { return corners.data() + offsets[e]; }
  std::int32_t uv(std::uint32_t corner) const { return corner_uvs.empty() ? -1 : corner_uvs[corner]; }
  std::int32_t normal(std::uint32_t corner) const { return corner_normals.empty() ? -1 : corner_normals[corner]; }
  std::int32_t group(std::size_t e) const { return groups.empty() ? -1 : groups[e]; }
  std::uint32_t line(std::size_t e) const { return lines.empty() ? 0 : lines[e]; }

  /// Appends a corner to the element being built (closed by close()).
  void add_corner(std::uint32_t vertex, std::int32_t uv = -1, std::int32_t normal = -1) {
    if (uv >= 0 || !corner_uvs.empty()) {
      corner_uvs.resize(corners.size(), -1);  // -1 for the corners before the first UV
      corner_uvs.push_back(uv);
    }
    if (normal >= 0 || !corner_normals.empty()) {
      corner_normals.resize(corners.size(), -1);
      corner_normals.push_back(normal);
    }
    corners.push_back(vertex);
  }
  /// Ends the element whose corners were added since the last close(); `line` is the
  /// file line that defined it (0: unknown; lines past 2^32 - 1 are kept as that).
  void close(ElementKind kind, std::int32_t group = -1, std::size_t file_line = 0) {
    const auto line = static_cast<std::uint32_t>(std::min<std::size_t>(file_line, 0xffffffffu));
    if (corners.size() > 0xffffffffu) throw_too_many_corners();
    if (group >= 0 || !groups.empty()) {
      groups.resize(kinds.size(), -1);  // -1 for the elements before the first group
      groups.push_back(group);
    }
    if (line > 0 || !lines.empty()) {
      lines.resize(kinds.size(), 0);
      lines.push_back(line);
    }
    kinds.push_back(kind);
    offsets.push_back(static_cast<std::uint32_t>(corners.size()));
  }
  /// Appends a polygon with the vertices of `vertices` (any range of indices).
  template <class Range>
  void add_polygon(const Range& vertices, std::int32_t group = -1) {
    for (auto v : vertices) add_corner(static_cast<std::uint32_t>(v));
    close(ElementKind::Polygon, group);
  }
  void add_polygon(std::initializer_list<std::uint32_t> vertices, std::int32_t group = -1) {
    for (std::uint32_t v : vertices) add_corner(v);
    close(ElementKind::Polygon, group);
  }
  /// Reserves room for `elements` elements of `corners_each` corners.
  void reserve(std::size_t elements, std::size_t corners_each) {
    kinds.reserve(elements);
    offsets.reserve(elements + 1);
    corners.reserve(elements * corners_each);
  }
  /// How many elements are of `kind`.
  std::size_t count(ElementKind kind) const {
    std::size_t n = 0;
    for (ElementKind k : kinds) n += k == kind;
    return n;
  }
};

/// "file:line" when element e's line is known, else "file: face N" (N counts polygons
/// only when every element is one; else "element N"), for messages.
std::string element_place(const std::string& file, const MeshElements& elements, std::size_t e);

/// The polygons as triangles, each fanned from its first corner, in element order (what
/// the glTF writer and the renderer take); lines and points are left out.
inline std::vector<std::array<std::uint32_t, 3>> fan_triangles(const MeshElements& el) {
  std::vector<std::array<std::uint32_t, 3>> out;
  out.reserve(el.corners.size() / 3);
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    const std::uint32_t* c = el.vertices(e);
    for (std::uint32_t k = 1; k + 1 < el.degree(e); ++k) out.push_back({c[0], c[k], c[k + 1]});
  }
  return out;
}

}  // namespace ffd
