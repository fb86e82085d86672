// Wavefront OBJ: a strict reader and an exact writer.
//
// The reader is ours rather than tinyobjloader's because tinyobjloader's number parser
// is not correctly rounded (about 2 in 3 values written with 17 digits read back a bit
// off) and it turns malformed values ("nan", "v 1 2", "v a b c") into zeros without a
// word. This one reads numbers with std::from_chars (exact), rejects every malformed line
// with its line number, and keeps per-corner UV and normal indices, vertex colours
// (`v x y z r g b`), groups, materials and mtllib lines, and what it does not interpret.
// tinyobjloader stays as the independent reference our tests compare against.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <string_view>

#include "mesh/file_normals.h"
#include "mesh/mesh.h"
#include "mesh/vertex_colors.h"
#include "mesh/soup.h"

namespace ffd {

/// Parses OBJ text. `file` names the source in error messages. A line ending in `\\`
/// continues on the next. Statements it does not interpret (`vw`, `mg`, `lod`, `cstype`,
/// `curv`, ...) and the w of `v x y z w` are kept in the soup's ObjSource (obj_source.h).
/// \throw InputError "file:line: what was expected" on any malformed line (NaN/inf,
/// indices out of range, a statement keyword that is not a word).
PolygonSoup read_obj(std::string_view text, const std::string& file);
/// The same, calling `release_text` where the reader no longer needs the text, before it
/// builds its arrays from what it parsed (read_mesh gives a mapped file's pages back there).
/// An OBJ of plain geometry from 4 MB on is parsed by the team in chunks (obj_chunks.h).
PolygonSoup read_obj(std::string_view text, const std::string& file, const std::function<void()>& release_text);

/// read_obj without its fast path for `v` and `f` lines: every line through the general
/// tokenizing reader. The same soup, or the same error, as read_obj on any text; kept as
/// the reference the fast path is tested and fuzzed against.
PolygonSoup read_obj_general(std::string_view text, const std::string& file);

/// Writes `mesh` (current positions) as OBJ with shortest round-trip numbers. File normals
/// go through `transform_normal` when given (each distinct (normal, vertex) pair once);
/// a normal shared by corners at several vertices is written once per distinct result.
/// Colours, when given, go on the v lines (v x y z r g b); else a w the file gave does.
/// The statements the reader kept (Mesh::obj_source()) are written back where they were:
/// before the vertices, or before the element that followed them.
void write_obj(std::ostream& os, const Mesh& mesh, const NormalTransform& transform_normal,
               VertexColors colors);

}  // namespace ffd
