// Reading and writing meshes by file extension: .obj, .off, .ply, .stl, .gltf, .glb, and
// the volume meshes of volume_io.h: .vtu, .vtk, .msh, .su2 and OpenFOAM polyMesh folders
// (a path without an extension).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "mesh/gltf_io.h"
#include "mesh/mesh.h"
#include "mesh/obj_io.h"
#include "mesh/volume_mesh.h"

namespace ffd {

enum class MeshFormat { Obj, Off, Ply, Stl, Gltf, Glb, Vtu, Vtk, Msh, Su2, Foam };

/// The volume format a MeshFormat is, if it is one.
std::optional<VolumeFormat> volume_format(MeshFormat format);

/// The format named by `path`'s extension (case-insensitive).
/// \throw InputError for any other extension.
MeshFormat mesh_format(const std::filesystem::path& path);
/// Whether `path`'s extension names a mesh file format (not an OpenFOAM folder).
bool has_mesh_extension(const std::filesystem::path& path);

/// Reads a mesh file into a Mesh, checked as build_mesh describes.
/// `defer_normals`: as build_mesh's (glTF files get their normals at once).
/// \throw InputError naming the file and the place for anything unreadable.
Mesh read_mesh(const std::string& path, bool defer_normals = false);
/// Two meshes read at once, on two threads (`compare`); A's error first if both fail.
std::pair<Mesh, Mesh> read_mesh_pair(const std::string& a, const std::string& b);

/// How a write deforms what the mesh carries besides positions.
struct WriteOptions {
  /// Carries a rest-space file normal at a vertex into deformed space (empty: as stored).
  NormalTransform transform_normal;
  /// One colour per vertex to write instead of the mesh's own (empty: the mesh's, if any).
  std::vector<Eigen::Vector3f> colors;
  /// PLY and STL: Auto writes binary when the mesh was read from a binary PLY or STL,
  /// ASCII otherwise (OBJ and OFF are text only). Binary STL stores float32.
  enum class Encoding { Auto, Ascii, Binary } encoding = Encoding::Auto;
};

/// Checks that `format` can hold every element of `mesh`: OFF, PLY and STL hold faces
/// only, so a mesh with OBJ lines or points can only be saved as OBJ (or as the glTF it
/// was read from).
/// \throw InputError naming `path` otherwise.
void check_writable(const Mesh& mesh, MeshFormat format, const std::string& path);

/// What the reader kept without interpreting it (an OBJ's `vw`, `mg`, ... statements),
/// one note per kind, and what it accepted against the spec (a glTF accessor's wrong
/// bounds), for the run's warnings.
std::vector<std::string> uninterpreted_data(const Mesh& mesh);

/// What writing `mesh` in `format` leaves out of what it carries, as a phrase for a
/// warning ("the PLY file's vertex alpha, face red are not written (only a PLY holds
/// them)"), or empty when the file holds it all.
std::string unwritten_data(const Mesh& mesh, MeshFormat format);

/// Writes `mesh` in `format` to `os` (elements a format cannot hold are left out:
/// check_writable first). A .gltf written this way embeds its buffers.
void write_mesh(std::ostream& os, MeshFormat format, const Mesh& mesh,
                const WriteOptions& options = {});

/// Stages the files that writing `mesh` to `path` makes (common/atomic_file.h): a
/// .gltf's external buffers first ("STEM.bin", "STEM_1.bin", … beside it), then the mesh
/// file; `bytes` gets their total size. Nothing is in place until each is committed.
/// 	hrow InputError if a buffer file would replace one the mesh was read from.
std::vector<StagedFile> stage_mesh_files(const std::string& path, const Mesh& mesh, const WriteOptions& options,
                                         std::size_t* bytes = nullptr);

/// Writes `mesh` to `path` (format from the extension) whole or not at all.
/// \throw InputError if the folder is missing or the extension unknown, IoError on I/O.
void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& options = {});

}  // namespace ffd
