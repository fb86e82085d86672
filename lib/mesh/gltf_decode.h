// Compressed glTF geometry, decoded on read (gltf_io.h), so that the rest of the reader
// and the writer see plain accessors:
// - KHR_draco_mesh_compression (Debian's libdraco): each compressed primitive's
//   attributes and indices are decoded, in the component types their accessors declare,
//   into new views appended to buffer 0;
// - EXT_meshopt_compression and KHR_meshopt_compression (Debian's meshoptimizer): each
//   compressed bufferView is decoded (ATTRIBUTES, TRIANGLES, INDICES; the OCTAHEDRAL,
//   QUATERNION and EXPONENTIAL filters) into its own place in its buffer, which for a
//   fallback buffer (no data of its own) is made for it.
// A write gives the data back uncompressed and removes the extensions
// (GltfScene::decoded_extensions): ffdtool does not re-encode, and a decoder that read the
// stale compressed data would undo the deformation. Only the glTF reader includes it.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "mesh/gltf_document.h"
#include "mesh/gltf_scene.h"

namespace ffd {

/// Decodes every Draco-compressed primitive of `model`, first giving back the indices
/// the loader was not shown; returns the accessors it gave data.
/// \throw InputError naming the mesh, primitive or accessor when the data does not decode
/// or does not fit the accessors.
std::vector<int> decode_draco(tinygltf::Model& model, const std::vector<DracoIndices>& indices);

/// Decodes every meshopt-compressed bufferView of `model` into its buffer, first giving
/// each fallback buffer its byte length; returns the extension names decoded.
/// \throw InputError naming the bufferView when the data does not decode.
std::vector<std::string> decode_meshopt(tinygltf::Model& model, const std::vector<FallbackBuffer>& fallbacks);

}  // namespace ffd
