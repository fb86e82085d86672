// A polygon soup as a file holds it: what the readers produce and build_mesh consumes.
// Plain vectors, no CGAL: every reader fills one, so validation lives in one place.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace ffd {

/// The OBJ grouping statements in force for a face (empty: never set).
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

/// One face of a soup: vertex indices in order plus optional per-corner attribute
/// indices (-1 where a corner has none) and the file line that defined it (0 if the
/// format has no lines), so that errors can name it.
struct SoupFace {
  std::vector<std::uint32_t> vertices;
  std::vector<std::int32_t> uvs;      // empty, or one index into PolygonSoup::uvs per corner
  std::vector<std::int32_t> normals;  // empty, or one index into PolygonSoup::normals per corner
  std::int32_t group = -1;            // index into PolygonSoup::groups, -1 for none
  std::size_t line = 0;
};

/// Everything ffdtool keeps of a mesh file.
struct PolygonSoup {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3f> colors;      // empty, or one RGB in [0,1] per vertex
  std::vector<Eigen::Vector2d> uvs;         // OBJ vt / OFF st table
  std::vector<Eigen::Vector3d> normals;     // OBJ vn / NOFF / PLY normal table
  std::vector<std::size_t> vertex_lines;    // line of each position (0: no lines)
  std::vector<SoupFace> faces;
  std::vector<ObjState> groups;             // OBJ o/g/usemtl/s state, one per distinct state
  std::vector<std::string> header;          // OBJ mtllib lines, written back verbatim
};

}  // namespace ffd
