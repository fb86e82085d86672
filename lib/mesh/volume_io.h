// Reading and writing volume meshes (volume_mesh.h) as Meshes: the nodes are the Mesh's
// vertices, in file order, with no polygons (a point cloud to every warp; a planar 2D mesh
// has its triangles and quads as faces); the cells,
// markers and the file ride along as Mesh::volume_source, and a write patches the file's
// own bytes with the current positions. mesh_io.h dispatches here by format.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "mesh/mesh.h"
#include "mesh/volume_mesh.h"

namespace ffd {

/// The volume format a path names: .vtu, .vtk, .msh, .su2 by extension (any case); an
/// existing folder, or a path whose last part is `polyMesh`, is an OpenFOAM polyMesh
/// folder. Empty for anything else (a path without an extension stays a likely typo).
std::optional<VolumeFormat> volume_format_of(const std::filesystem::path& path);

/// Reads a volume mesh. A planar one (VolumeSource::dimension 2) also gets its 2D cells as
/// the Mesh's faces, with normals unless `defer_normals` (as build_mesh's).
/// \throw InputError naming the file and the place.
Mesh read_volume_mesh(const std::string& path, VolumeFormat format, bool defer_normals = false);

/// Checks that `mesh` can be written as `format` at `path`: a volume format needs a mesh
/// read from that format. \throw InputError naming `path` otherwise.
void check_volume_writable(const Mesh& mesh, VolumeFormat format, const std::string& path);

/// Stages the volume file at `path` with the mesh's current positions; for OpenFOAM the
/// polyMesh folder `path` (created if missing) with `points` rewritten and every other
/// file copied. Returns the bytes staged. \pre check_volume_writable.
std::size_t stage_volume_files(const std::string& path, const Mesh& mesh, std::vector<StagedFile>& files);

/// What a surface output leaves out of a volume mesh ("the SU2 file's 1,234 cells and
/// 3 markers"), or empty for a mesh that is not one.
std::string unwritten_volume_data(const Mesh& mesh);

}  // namespace ffd
