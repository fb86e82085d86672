// Object File Format (OFF): a strict ASCII reader and an exact writer.
//
// Read: OFF, COFF, NOFF, CNOFF, STOFF and their combinations ([ST][C][N]OFF), comments,
// counts on the header line or the next. Every malformed line is an error with its line
// number (CGAL's reader only says that it failed). Binary OFF and the 4/n dimensions
// are refused. Per-face colours are read and ignored.
// Write: OFF, or COFF when the mesh carries vertex colours, or NOFF with deformed normals.
#pragma once

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>

#include "mesh/mesh.h"
#include "mesh/off_chunks.h"
#include "mesh/vertex_colors.h"
#include "mesh/soup.h"

namespace ffd {

/// Parses OFF text. \throw InputError "file:line: ..." on malformed or unsupported input.
PolygonSoup read_off(std::string_view text, const std::string& file);
/// The same, calling `release_text` where the reader no longer needs the text, before it
/// builds its arrays from what it parsed (read_mesh gives a mapped file's pages back there).
/// A plain OFF from 4 MB on is parsed by the team in chunks (off_chunks.h).
PolygonSoup read_off(std::string_view text, const std::string& file, const std::function<void()>& release_text);

/// read_off without its fast path for plain vertex and face lines: every line through the
/// general tokenizing reader. The same soup, or the same error, as read_off on any text;
/// the reference the fast path is tested against.
PolygonSoup read_off_general(std::string_view text, const std::string& file);

/// The lines after a plain OFF's counts (`OFF` or no keyword), with the counts, as read_off
/// reads its header: what its parallel path (off_chunks.h) parses. std::nullopt when the
/// header is another variant's or read_off refuses it, or nothing follows the counts.
std::optional<OffBody> plain_off_body(std::string_view text);

/// Writes `mesh`'s current positions (and `colors`, COFF) as OFF with shortest round-trip
/// numbers; `normals` (3 × n, may be null) adds per-vertex normals (NOFF).
void write_off(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals, VertexColors colors);

}  // namespace ffd
