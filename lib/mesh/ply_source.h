// The PLY file a mesh was read from, kept so that writing the mesh as PLY gives the file
// back: its header's lines as they were, and every element and property in the file's
// order and declared types. The writer rewrites only what a run changes:
// - x y z (and nx ny nz) from the mesh's current positions (and normals), in the declared
//   type (an integer-typed coordinate or normal is promoted to double, so a deformed
//   position is not rounded to an integer);
// - red green blue when a save paints the vertices (and adds them when the file had none).
// Everything else (alpha, UVs, per-face colours and normals, custom properties, other
// elements, tristrips, comments) is written back value for value; a binary file whose
// positions did not move comes back byte for byte.
// Valid while the connectivity is the file's (Mesh::ply_source()).
#pragma once

#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ffd {

class Mesh;

enum class PlyType : std::uint8_t { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

std::size_t ply_type_size(PlyType type);
bool ply_integer(PlyType type);
/// The header's word for a type ("uchar", "float", ...): the PLY 1.0 spelling.
const char* ply_type_name(PlyType type);
/// Stores x as `type` at out (ply_type_size(type) bytes, native order), converted as a
/// cast does: exact for a value read from a property of that type.
void ply_store(PlyType type, double x, unsigned char* out);
/// The value of `type` at p (native byte order), as a double: exact for every PLY type.
double ply_load(PlyType type, const unsigned char* p);

/// Copies one value of `size` bytes (1, 2, 4 or 8) from `in` to `out`, its bytes
/// reversed when `swap` (a binary file of the other byte order). Inline, with a
/// fixed-size copy per size: the binary readers and writers call it per value.
inline void ply_copy(unsigned char* out, const unsigned char* in, std::size_t size, bool swap) {
  const auto copy = [&](auto v, auto reversed) {
    std::memcpy(&v, in, sizeof v);
    if (swap) v = reversed(v);
    std::memcpy(out, &v, sizeof v);
  };
  switch (size) {
    case 1: *out = *in; return;
    case 2: return copy(std::uint16_t{}, [](std::uint16_t v) { return __builtin_bswap16(v); });
    case 4: return copy(std::uint32_t{}, [](std::uint32_t v) { return __builtin_bswap32(v); });
    default: return copy(std::uint64_t{}, [](std::uint64_t v) { return __builtin_bswap64(v); });
  }
}

/// One property of an element: its declaration and, unless the writer takes it from the
/// mesh, every item's value in the declared type (native byte order).
struct PlyColumn {
  /// What the writer writes: the values as read, or a component of the mesh's current
  /// positions, normals or (when a save gives them) colours.
  enum class Role : std::uint8_t { Kept, Position, Normal, Color };
  std::string name;
  PlyType type = PlyType::Float32;
  bool list = false;
  PlyType count_type = PlyType::Uint8;
  std::size_t line = 0;  // its line in PlySource::header (0-based)
  Role role = Role::Kept;
  int component = 0;  // x, y, z (nx, ...; red, ...): 0, 1, 2
  /// Kept, but also read into the mesh (UVs, the face and tristrips index lists), so that
  /// other formats carry it too.
  bool in_mesh = false;
  /// Scalars: one value per item. Lists: every item's entries, one after another. Empty
  /// for the Position and Normal roles.
  std::vector<unsigned char> values;
  std::vector<std::uint32_t> lengths;  // lists: each item's entry count
};

struct PlyElementData {
  std::string name;
  std::uint64_t count = 0;
  std::size_t line = 0;  // its `element` line in PlySource::header
  std::vector<PlyColumn> columns;
};

struct PlySource {
  enum class Format : std::uint8_t { Ascii, BinaryLittle, BinaryBig };
  Format format = Format::Ascii;
  /// The header's lines as read, `ply` to `end_header`, without their line ends.
  std::vector<std::string> header;
  std::size_t format_line = 1;
  /// The file's line end: "\n", "\r\n" or "\r" (an ASCII body's items end with it too).
  std::string line_end = "\n";
  std::vector<PlyElementData> elements;
  std::size_t vertex_element = 0;  // index in elements

  /// The values the writer carries and no other writer can: "vertex alpha", "face red",
  /// "element edge", ... (properties in PLY's own words), for the warning when a write
  /// cannot carry them. Positions, normals, RGB colours, UVs and the face index lists
  /// are left out: every mesh format ffdtool writes holds those or says so itself.
  std::vector<std::string> carried_only_here() const;
};

/// Writes `mesh` as the PLY file it was read from (\pre mesh.ply_source()), with its
/// current positions, `normals` (3 × n, when the file has nx ny nz) and, when given,
/// `colors`. `binary`: the file's own binary format (little- or big-endian) if it was
/// binary, else little-endian; otherwise ASCII.
void write_ply_source(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals,
                      const std::vector<Eigen::Vector3f>* colors, bool binary);

}  // namespace ffd
