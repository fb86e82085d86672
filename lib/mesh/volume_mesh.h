// Volume meshes (VTK XML .vtu, legacy .vtk, Gmsh .msh, SU2 .su2, OpenFOAM polyMesh): the
// cells, the markers and the file itself, kept beside a Mesh whose vertices are the
// file's nodes in order (Mesh::volume_source).
//
// A warp moves nodes only, so a volume file is written back by patching its own bytes:
// every cell, zone, marker, physical group, field and comment stays the file's, and only
// the node coordinates are rewritten (a VolumeFile). A node whose position is the one
// read keeps its bytes, text included.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "common/file_bytes.h"

namespace ffd {

/// VTK's cell type numbers (vtkCellType.h), which SU2 uses too; readers of other formats
/// map their kinds to these, with VTK's corner order. A kind ffdtool only carries (a
/// Gmsh element with no VTK number) is kOtherCell.
namespace cell_type {
inline constexpr std::uint8_t kOtherCell = 0;
inline constexpr std::uint8_t kVertex = 1;
inline constexpr std::uint8_t kLine = 3;
inline constexpr std::uint8_t kTriangle = 5;
inline constexpr std::uint8_t kPolygon = 7;
inline constexpr std::uint8_t kQuad = 9;
inline constexpr std::uint8_t kTetra = 10;
inline constexpr std::uint8_t kHexahedron = 12;
inline constexpr std::uint8_t kWedge = 13;
inline constexpr std::uint8_t kPyramid = 14;
inline constexpr std::uint8_t kQuadraticEdge = 21;
inline constexpr std::uint8_t kQuadraticTriangle = 22;
inline constexpr std::uint8_t kQuadraticQuad = 23;
inline constexpr std::uint8_t kQuadraticTetra = 24;
inline constexpr std::uint8_t kQuadraticHexahedron = 25;
inline constexpr std::uint8_t kQuadraticWedge = 26;
inline constexpr std::uint8_t kQuadraticPyramid = 27;
inline constexpr std::uint8_t kBiquadraticQuad = 28;
inline constexpr std::uint8_t kTriquadraticHexahedron = 29;
inline constexpr std::uint8_t kPolyhedron = 42;
}  // namespace cell_type

/// A cell kind's name for info and messages ("tetra", "hexahedron", "polyhedron",
/// "VTK type 71" for a number without one).
std::string cell_type_name(std::uint8_t type);
/// The dimension of a cell kind: 0 vertex, 1 line, 2 triangle/quad/polygon, 3 volume
/// cells; -1 for kOtherCell.
int cell_type_dimension(std::uint8_t type);

/// Every element of the file, volume cells and boundary elements alike, in the file's
/// order: cell c has type[c] and nodes node[offset[c], offset[c + 1]) (0-based indices of
/// the mesh's vertices, VTK's corner order).
/// A polyhedron (kPolyhedron) also has faces: from face[face_offset[c]], VTK's stream
/// form: the face count, then for each face its node count and nodes, each face wound so
/// its normal (right-hand rule) points out of the cell. face_offset is empty when the
/// file has no polyhedra, else one entry per cell (ignored for other kinds).
struct VolumeCells {
  std::vector<std::uint8_t> type;
  std::vector<std::uint64_t> offset{0};
  std::vector<std::uint32_t> node;
  std::vector<std::uint64_t> face_offset;
  std::vector<std::uint32_t> face;

  std::size_t size() const { return type.size(); }
  std::size_t degree(std::size_t c) const { return offset[c + 1] - offset[c]; }
  const std::uint32_t* nodes(std::size_t c) const { return node.data() + offset[c]; }
  /// Appends a cell of `type` with `nodes` (not a polyhedron: add_polyhedron).
  void add(std::uint8_t cell_type, const std::uint32_t* nodes, std::size_t count);
  /// Appends a polyhedron: its distinct nodes, and its faces in VTK's stream form.
  void add_polyhedron(const std::vector<std::uint32_t>& nodes, const std::vector<std::uint32_t>& faces);
};

/// A named set of elements: an SU2 marker, a Gmsh physical group, an OpenFOAM patch.
struct VolumeMarker {
  std::string name;       // the file's name for it (a Gmsh group without one: its number)
  int dimension = -1;     // of its elements, -1 if the file does not say
  std::vector<std::uint64_t> cells;  // indices into VolumeCells, ascending
};

/// What a volume file is, for info, stats and messages.
enum class VolumeFormat { Vtu, Vtk, Msh, Su2, Foam };

/// The name a user knows a volume format by ("VTK XML unstructured grid", "Gmsh MSH 4.1").
std::string volume_format_name(VolumeFormat format);

/// How a volume file is written back with other node positions. Everything but the
/// coordinates is the file's own bytes; a node whose position equals the one read (as
/// stored: a float32 file compares in float32) is written with its own bytes too.
class VolumeFile {
public:
  virtual ~VolumeFile() = default;
  /// Writes the file (for OpenFOAM: the `points` file) with `positions` (3 × nodes).
  virtual void write(std::ostream& os, const Eigen::Matrix3Xd& positions) const = 0;
};

/// A volume file as read: what Mesh::volume_source holds.
struct VolumeSource {
  VolumeFormat format = VolumeFormat::Vtu;
  std::string encoding;   // "ascii", "binary", "appended raw zlib", ... as the file has it
  std::string version;    // "4.1", "2.2", "1.0", ... or empty
  int dimension = 3;      // 2 for a planar mesh (SU2 NDIME=2): nodes have z = 0
  VolumeCells cells;
  std::vector<VolumeMarker> markers;
  /// OpenFOAM: the polyMesh folder's other files, relative to it, copied as they are.
  std::vector<std::string> companion_files;
  std::shared_ptr<const VolumeFile> file;
};

/// A reader's result: the nodes (3 × n, as stored, float32 widened exactly) and the rest.
struct VolumeRead {
  Eigen::Matrix3Xd points;
  VolumeSource source;
};

/// The file's bytes, shared between a reader's result and its VolumeFile.
using SharedBytes = std::shared_ptr<const FileBytes>;

}  // namespace ffd
