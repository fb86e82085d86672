// What an OBJ file holds that ffdtool does not interpret, kept so that writing the mesh
// as OBJ gives it back in place: statements such as `vw`, `mg`, `lod`, `usemap`,
// `bevel`, `cstype` or `curv`, and the w components of `v` lines. Valid while the
// connectivity is the file's (Mesh::obj_source()).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace ffd {

struct ObjSource {
  /// A statement as read (a line continued with `\` joined into one, its comment kept).
  struct Statement {
    std::size_t before_element = 0;  // elements (f, l, p) read before it
    bool before_vertices = false;    // read before the first `v`: written before them too
    std::string text;
  };
  std::vector<Statement> statements;
  /// Each statement keyword with its count, in the order of first appearance.
  std::vector<std::pair<std::string, std::size_t>> keywords;
  /// The w component of each vertex's `v x y z w` line; NaN where the line has none.
  /// Empty when no vertex has one.
  std::vector<double> w;

  bool empty() const { return statements.empty() && w.empty(); }
};

}  // namespace ffd
