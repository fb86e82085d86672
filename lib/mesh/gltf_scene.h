// What a Mesh read from glTF keeps of its file (gltf_io.h): the tinygltf model and the
// JSON as read, and where each primitive's vertices went. Only the glTF reader and writer
// include it.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace ffd {

/// One node drawing one glTF mesh, with the node's world matrix (identity for a skinned
/// node: its vertices are in bind pose, mesh space).
struct GltfInstance {
  int node = -1;
  int mesh = -1;
  Eigen::Matrix4d world = Eigen::Matrix4d::Identity();
};

/// The vertices one POSITION accessor (with its NORMAL accessor, or -1) gave one
/// instance: mesh vertices first .. first + count - 1, in accessor order.
struct GltfRun {
  std::size_t instance = 0;
  int position = -1;
  int normal = -1;
  std::uint32_t first = 0;
  std::uint32_t count = 0;
};

struct GltfScene {
  tinygltf::Model model;
  /// The file's JSON (a GLB's JSON chunk), which a write patches (gltf_document.h).
  std::string json;
  std::vector<GltfInstance> instances;  // depth-first order of the default scene
  std::vector<GltfRun> runs;            // by first vertex
  std::size_t num_vertices = 0;         // the mesh's vertex count when read
  bool binary = false;                  // read from a .glb
  /// The folder of the file read: where relative image URIs resolve.
  std::filesystem::path folder;
  /// The files the model's buffers came from (absolute), which a write must not replace.
  std::vector<std::filesystem::path> buffer_files;
  /// Buffer i was a data URI in the source (a .gltf write embeds it again).
  std::vector<bool> buffer_embedded;
  std::vector<std::string> notes;
  /// The extensions the reader decoded (Draco, meshopt): a write removes them, its data
  /// being plain.
  std::vector<std::string> decoded_extensions;
  /// The accessors given data by decoding Draco (their bounds were the encoder's).
  std::vector<int> decoded_accessors;
  /// What the file holds that is not as the spec says but was read anyway, and what a
  /// write will not give back as it was (decoded compression).
  std::vector<std::string> warnings;
};

}  // namespace ffd
