// glTF 2.0 (.gltf with its buffers, and .glb), read and written with tinygltf.
//
// Reading: every mesh primitive of the default scene (scene 0 when none is named; every
// root node when the file has no scene), in world space (node transforms applied down
// the hierarchy), becomes vertices and elements of one Mesh: triangles
// (lists, strips and fans) as polygons, lines and points as OBJ-style line and point
// elements. Sparse accessors are read; KHR_mesh_quantization's integer attributes are
// dequantized; Draco and meshopt compression are decoded (gltf_decode.h), and a glTF
// output holds that data uncompressed, without the extension (a warning says so).
// glTF 1.0, UTF-16/32 text and non-finite positions are refused by name. TEXCOORD_0
// becomes the corners' UVs, NORMAL their file normals, so an OBJ written from a glTF
// keeps both.
//
// Instancing: a primitive drawn by two nodes is two sets of vertices, one per node, each
// deformed where it is in world space; a POSITION accessor that two primitives of one
// node share is one set of vertices. A skinned mesh is deformed in its bind pose (the
// positions as stored: glTF ignores a skinned node's transform), a morph-targeted mesh
// in its base shape (the targets' offsets are kept); the scene's notes say so. A node
// scaled to zero (no inverse) is read flat and written back as it was.
//
// Writing patches the file's own JSON (gltf_document.h): POSITION and NORMAL data are
// replaced in place, in each node's local space again, with the min and max of each
// accessor rewritten recomputed; everything else in the document (nodes, meshes,
// materials, textures, images, samplers, animations, skins, cameras, extensions, extras,
// names, empty objects, absent optional values) is written back as read, and every other
// attribute's data (TEXCOORD_n, TANGENT, COLOR_n, JOINTS_n, WEIGHTS_n) stays byte for
// byte. A POSITION accessor whose min and max are not its data's bounds is read with a
// warning (gltf_warnings). An instanced mesh whose instances no longer agree after the
// deformation is split: each further node gets its own copy of the mesh with its own
// POSITION and NORMAL accessors (appended to buffer 0), so every instance is where the
// deformation put it. A mesh with no glTF source (another format), or
// whose connectivity changed (remesh), is written as one node, one mesh and one
// primitive of triangles with POSITION and NORMAL.
#pragma once

#include <cstddef>
#include <filesystem>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/file_normals.h"
#include "mesh/mesh.h"

namespace ffd {

/// What a glTF file holds, for `ffdtool info`.
struct GltfSummary {
  std::size_t nodes = 0, meshes = 0, primitives = 0, instances = 0;
  std::size_t materials = 0, textures = 0, images = 0, animations = 0, skins = 0;
  bool binary = false;                 // read from a .glb
  std::vector<std::string> notes;      // skinned and morph-targeted meshes, split instances
};

/// Reads a glTF file's bytes (`binary`: GLB) as a Mesh carrying its GltfScene.
/// \throw InputError naming `path` and the accessor, primitive or node at fault.
Mesh read_gltf(std::string_view bytes, const std::string& path, bool binary);

/// The summary of the glTF source of `mesh`; all zero when it has none.
GltfSummary gltf_summary(const Mesh& mesh);

/// What the reader of the glTF source of `mesh` accepted against the spec (accessor
/// bounds that are not the data's), one line each.
std::vector<std::string> gltf_warnings(const Mesh& mesh);

struct GltfScene;
/// Whether `file` (absolute, normalized) is one the scene's buffers were read from.
bool gltf_reads_file(const GltfScene& scene, const std::filesystem::path& file);

/// A file a glTF write makes beside the main file: an external buffer (`name` is
/// relative to the main file's folder).
struct CompanionFile {
  std::string name;
  std::vector<unsigned char> bytes;
};

/// The image files the glTF source of `mesh` refers to by a relative URI inside its
/// folder (no "..", no absolute path), with their bytes, so a write to another folder
/// can put them beside the output; files that cannot be read are left out.
std::vector<CompanionFile> gltf_image_files(const Mesh& mesh);
/// The folder the glTF source of `mesh` was read from (empty when it has none).
std::filesystem::path gltf_folder(const Mesh& mesh);

/// Writes `mesh` as glTF to `os`: GLB when `binary`, else .gltf JSON. With `companions`
/// null every buffer is embedded (GLB: buffer 0 as the BIN chunk, the rest as data
/// URIs); otherwise a .gltf's external buffers are appended to *companions, named after
/// `stem` ("stem.bin", "stem_1.bin", …), and buffers that were data URIs stay embedded.
void write_gltf(std::ostream& os, const Mesh& mesh, const NormalTransform& transform_normal, bool binary,
                const std::string& stem = "", std::vector<CompanionFile>* companions = nullptr);

}  // namespace ffd
