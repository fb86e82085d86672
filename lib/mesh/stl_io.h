// STL: a strict reader of our own (ASCII and binary); the writer is in ply_stl_io.h.
//
// Binary is the 80-byte header, a little-endian uint32 triangle count and 50 bytes per
// triangle; the count must match the file's size exactly. A file that starts with
// "solid" is read as ASCII, unless it is not valid ASCII STL and its size fits the
// binary count (binary files whose header starts with "solid" are common). Equal corner
// points (all three coordinates ==, so -0 and 0 are one) become one vertex, numbered in
// the order first seen, as CGAL's reader does. Coordinates must be finite.
#pragma once

#include <string>
#include <string_view>

#include "mesh/soup.h"

namespace ffd {

/// Parses the bytes of an STL file. `file` names the source in error messages.
/// \throw InputError "file:line: what" (ASCII) or "file: triangle t: what" (binary), or
/// "file: what" for a size that does not fit the binary count, an empty file or a file
/// without a triangle.
PolygonSoup read_stl(std::string_view bytes, const std::string& file);

/// Whether `bytes` have exactly the size a binary STL's triangle count gives them.
bool stl_is_binary(std::string_view bytes);

}  // namespace ffd
