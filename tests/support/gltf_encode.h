// glTF files of a triangle mesh in each coding ffdtool reads: plain float, Draco
// (KHR_draco_mesh_compression, by libdraco's encoder), meshopt (EXT_meshopt_compression,
// by meshoptimizer's encoder, with a fallback buffer) and KHR_mesh_quantization (written
// here as gltfpack does: integer positions under a dequantizing node). The encoders are
// the libraries', independent of ffdtool's decoders; the tests, the corpus tool
// (make_gltf_corpus) and ffdbench's io suite use them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ffd::test {

struct PlainGeometry {
  std::vector<float> positions;  // x y z per vertex
  std::vector<float> normals;    // x y z per vertex (unit)
  std::vector<float> uvs;        // u v per vertex
  std::vector<std::uint32_t> triangles;
};

enum class GltfCoding { Plain, Draco, Meshopt, Quantized };

/// The name of a coding: "plain", "draco", "meshopt", "quantized".
const char* coding_name(GltfCoding coding);

/// How a Draco file is encoded: `lossless` keeps every float (sequential coding, no
/// quantization); otherwise edgebreaker with gltf-transform's default quantization
/// (position 14 bits, normal 10, texcoord 12).
struct DracoOptions {
  bool lossless = true;
};

/// The bytes of a glTF file of `g`: a GLB when `binary`, else a .gltf whose buffers are
/// data URIs.
std::string encode_gltf(const PlainGeometry& g, GltfCoding coding, bool binary, DracoOptions draco = {});

/// The geometry of an OBJ file's `v` and triangular `f` lines, with area-weighted normals
/// and UVs from the x and y extent.
PlainGeometry obj_geometry(const std::string& path);

}  // namespace ffd::test
