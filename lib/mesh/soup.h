// A polygon soup as a file holds it: what the readers produce and build_mesh consumes.
// Plain arrays, no CGAL: every reader fills one, so validation lives in one place.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/zeroed_array.h"
#include "mesh/mesh_elements.h"

namespace ffd {

struct PlySource;
struct ObjSource;

/// What one text line of a vertex and one of a triangle take in a soup: a position, and the
/// triangle's three corners, kind, offset and file line (the readers size their
/// reservations by it).
constexpr std::size_t kSoupLineBytes = sizeof(Eigen::Vector3d) + sizeof(ElementKind) + 5 * sizeof(std::uint32_t);

/// Everything ffdtool keeps of a mesh file.
struct PolygonSoup {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3f> colors;      // empty, or one RGB in [0,1] per vertex
  std::vector<Eigen::Vector2d> uvs;         // OBJ vt / OFF st table
  std::vector<Eigen::Vector3d> normals;     // OBJ vn / NOFF / PLY normal table
  bool normals_per_vertex = false;          // normals[v] is vertex v's (NOFF, PLY), element or not
  MeshElements elements;                    // faces, lines, points in file order
  std::vector<ObjState> groups;             // OBJ o/g/usemtl/s state, one per distinct state
  std::vector<std::string> header;          // OBJ mtllib lines, written back verbatim
  bool binary = false;                      // read from a binary PLY or STL
  std::shared_ptr<const PlySource> ply;     // a PLY file's every element (ply_source.h)
  std::shared_ptr<const ObjSource> obj;     // an OBJ's statements not interpreted (obj_source.h)
};

/// Reserves a reader's arrays for `vertices` vertices and `faces` triangles with their file
/// lines, to be filled front to back, and asks huge pages (common/zeroed_array.h) for the
/// two largest, the positions and the corners.
inline void reserve_for_lines(PolygonSoup& soup, std::size_t vertices, std::size_t faces) {
  soup.positions.reserve(vertices);
  soup.elements.reserve(faces, 3);
  soup.elements.lines.reserve(faces);
  advise_huge_pages_reserved(soup.positions);
  advise_huge_pages_reserved(soup.elements.corners);
}

}  // namespace ffd
