#include "mesh/build_mesh.h"

#include <algorithm>
#include <limits>

#include "common/errors.h"

namespace ffd {
namespace {

// Whether every value is below `limit`: one pass the compiler vectorizes.
template <class T>
bool all_below(const std::vector<T>& values, std::int64_t limit) {
  T most = std::numeric_limits<T>::lowest();
  for (const T v : values) most = std::max(most, v);
  return values.empty() || static_cast<std::int64_t>(most) < limit;
}

// Whether check_elements finds nothing, by whole-array passes instead of its element by
// element walk (on a 2M-triangle OBJ 11 -> 3 ms): offsets rising (no element without a
// corner), and every vertex, UV, normal and group index below its table's size (a -1,
// none, is). An array it cannot pass sends the caller to the walk, which names the first
// bad element.
bool elements_valid(const PolygonSoup& soup) {
  const MeshElements& el = soup.elements;
  if (el.offsets.size() != el.size() + 1 || el.offsets.back() != el.corners.size()) return false;
  bool rising = true;
  for (std::size_t e = 0; e < el.size(); ++e) rising &= el.offsets[e] < el.offsets[e + 1];
  return rising && all_below(el.corners, static_cast<std::int64_t>(soup.positions.size())) &&
         all_below(el.corner_uvs, static_cast<std::int64_t>(soup.uvs.size())) &&
         all_below(el.corner_normals, static_cast<std::int64_t>(soup.normals.size())) &&
         all_below(el.groups, static_cast<std::int64_t>(soup.groups.size()));
}

// Checks that every element has a corner and that every index points into its table.
void check_elements(const PolygonSoup& soup, const std::string& file) {
  if (elements_valid(soup)) return;
  const MeshElements& el = soup.elements;
  const auto n = static_cast<std::uint32_t>(soup.positions.size());
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.degree(e) == 0) throw InputError(element_place(file, el, e) + ": an element needs at least one vertex");
    for (std::uint32_t c = el.begin(e); c < el.end(e); ++c) {
      if (el.corners[c] >= n)
        throw InputError(element_place(file, el, e) + ": vertex index " + std::to_string(el.corners[c]) +
                         " is out of range (the file has " + std::to_string(n) + " vertices)");
      if (el.uv(c) >= static_cast<std::int64_t>(soup.uvs.size()))
        throw InputError(element_place(file, el, e) + ": texture index out of range");
      if (el.normal(c) >= static_cast<std::int64_t>(soup.normals.size()))
        throw InputError(element_place(file, el, e) + ": normal index out of range");
    }
    if (el.group(e) >= static_cast<std::int64_t>(soup.groups.size()))
      throw InputError(element_place(file, el, e) + ": group index out of range");
  }
}

}  // namespace

Mesh build_mesh(PolygonSoup soup, const std::string& file, bool defer_normals) {
  check_elements(soup, file);
  Mesh mesh;
  mesh.set_source(file);
  mesh.set_source_binary(soup.binary);
  mesh.set_ply_source(std::move(soup.ply));
  mesh.set_obj_source(std::move(soup.obj));
  const std::size_t n = soup.positions.size();
  // The soup's points lie one after another, 3 doubles each: a 3 x n matrix as they are.
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "a point is 3 doubles, unpadded");
  const double* points = soup.positions.empty() ? nullptr : soup.positions.front().data();
  Eigen::Matrix3Xd positions = copy_in_team(ConstVec3Array(points, 3, static_cast<Eigen::Index>(n)));
  std::vector<Eigen::Vector3d>().swap(soup.positions);
  if (!soup.colors.empty()) {
    soup.colors.resize(n, Eigen::Vector3f(0.8f, 0.8f, 0.8f));
    mesh.colors() = std::move(soup.colors);
  }
  mesh.uvs() = std::move(soup.uvs);
  mesh.file_normals() = std::move(soup.normals);
  mesh.groups() = std::move(soup.groups);
  mesh.header() = std::move(soup.header);
  mesh.file_uv_count = mesh.uvs().size();
  mesh.file_normal_count = mesh.file_normals().size();
  mesh.file_normals_per_vertex = soup.normals_per_vertex;
  mesh.set_elements(std::move(soup.elements));
  mesh.set_vertices(std::move(positions), !defer_normals);
  return mesh;
}

}  // namespace ffd
