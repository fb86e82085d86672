// PLY: a strict reader of our own (ASCII, binary little and big endian); the writer is
// in ply_stl_io.h.
//
// Read: the header (`ply`, `format`, `comment`, `obj_info`, `element`, `property`,
// `property list`, `end_header`, LF, CRLF or CR), every scalar type and its alias. Element
// `vertex`: x y z, optional nx ny nz, red green blue (or diffuse_red ...: integer types
// / 255, floats as they are) and texture coordinates (u v, s t or texture_u texture_v);
// element `face`: the list vertex_indices or vertex_index; element `tristrips`: strips
// with -1 restarts, as triangles. A repeated property name has its first one's meaning.
// Every element and property, these included, is also kept in the soup's PlySource
// (ply_source.h), so that a PLY write gives the file back. No byte sequence crashes it: every count is checked against the
// bytes left before anything is allocated. CGAL's reader stays as the oracle in tests.
#pragma once

#include <string>
#include <string_view>

#include "mesh/soup.h"

namespace ffd {

/// Parses the bytes of a PLY file. `file` names the source in error messages.
/// \throw InputError "file:line: what" (ASCII, and the header) or "file: element i: what"
/// (binary) on a malformed header, a count larger than the bytes left, a truncated file,
/// a non-finite coordinate, normal, colour or texture coordinate, an index out of range,
/// data after the last element, or a file without a vertex.
PolygonSoup read_ply(std::string_view bytes, const std::string& file);

}  // namespace ffd
