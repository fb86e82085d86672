// Wavefront OBJ: a strict reader and an exact writer.
//
// The reader is ours rather than tinyobjloader's because tinyobjloader's number parser
// is not correctly rounded (about 2 in 3 values written with 17 digits read back a bit
// off) and it turns malformed values ("nan", "v 1 2", "v a b c") into zeros without a
// word. This one reads numbers with std::from_chars (exact), rejects every malformed line
// with its line number, and keeps per-corner UV and normal indices, vertex colours
// (`v x y z r g b`), groups, materials and mtllib lines. tinyobjloader stays as the
// independent reference our tests compare against.
#pragma once

#include <ostream>
#include <string>
#include <string_view>

#include "mesh/file_normals.h"
#include "mesh/mesh.h"
#include "mesh/vertex_colors.h"
#include "mesh/soup.h"

namespace ffd {

/// Parses OBJ text. `file` names the source in error messages.
/// \throw InputError "file:line: what was expected" on any malformed or unsupported line
/// (lines, points, curves, NaN/inf, indices out of range).
PolygonSoup read_obj(std::string_view text, const std::string& file);

/// read_obj without its fast path for `v` and `f` lines: every line through the general
/// tokenizing reader. The same soup, or the same error, as read_obj on any text; kept as
/// the reference the fast path is tested and fuzzed against.
PolygonSoup read_obj_general(std::string_view text, const std::string& file);

/// Writes `mesh` (current positions) as OBJ with shortest round-trip numbers. File normals
/// go through `transform_normal` when given (each distinct (normal, vertex) pair once);
/// a normal shared by corners at several vertices is written once per distinct result.
/// Colours, when given, go on the v lines (v x y z r g b).
void write_obj(std::ostream& os, const Mesh& mesh, const NormalTransform& transform_normal,
               VertexColors colors);

}  // namespace ffd
