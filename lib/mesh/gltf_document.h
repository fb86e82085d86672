// The glTF source document, patched (gltf_io.h). A write of a mesh read from glTF edits
// the JSON the file was read from rather than serializing tinygltf's model: only what
// the deformation changed is touched (the accessors it rewrote, their min and max, the
// buffer views, accessors and meshes it appended, the nodes it re-pointed, the buffers'
// lengths and URIs). Everything else, including what tinygltf does not model (empty
// objects, absent optional values, unknown extensions, animation pointers, names), goes
// back as read. Only the glTF reader and writer include it.
#pragma once

#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/gltf_scene.h"

namespace ffd {

/// The JSON chunk of a GLB whose header tinygltf has checked (empty if it has none).
std::string glb_json_chunk(std::string_view bytes);

/// A buffer that is only a meshopt fallback (no URI, no data): its index and byte length.
struct FallbackBuffer {
  int index = -1;
  std::size_t byte_length = 0;
};

/// The indices accessor (without a bufferView: its data is in the Draco stream) of a
/// Draco-compressed primitive.
struct DracoIndices {
  int mesh = -1, primitive = -1, accessor = -1;
};

/// What the JSON tinygltf loads leaves out of the file, for the reader to put back.
struct LoadFixes {
  std::vector<FallbackBuffer> fallbacks;
  std::vector<DracoIndices> draco_indices;
};

/// The file's bytes as tinygltf (which requires data for every buffer and a bufferView for
/// every indices accessor) is to load them: each meshopt fallback buffer (no URI;
/// EXT_ or KHR_meshopt_compression "fallback": true) gets a one-byte data URI, and each
/// Draco primitive's view-less indices are taken out, both recorded in `fixes`. Empty
/// when the file needs no change.
std::string loadable_gltf(std::string_view bytes, bool binary, LoadFixes& fixes);

/// The version a glTF JSON document declares (asset.version), "1.0" for a document
/// without one whose top-level collections are dictionaries (glTF 1.0's), else empty.
std::string gltf_json_version(const std::string& json);

/// What a patched document says of buffer i's "uri", and which of the document's buffers
/// it is (`source`; a write may drop buffers, gltf_repack.h).
struct BufferUri {
  enum class Kind { Keep, Erase, Set } kind = Kind::Keep;  // Erase: a GLB's BIN chunk
  std::string uri;                                           // for Set
  int source = -1;                                           // -1: a new buffer
};

/// `scene.json` with what `model` (the scene's model after a deformation: the same
/// arrays, possibly longer, but for buffers a repack dropped) changed: views re-pointed,
/// and buffer i is the document's `uris[i].source` with the uri `uris[i]` says. `indent` < 0 writes
/// compact JSON. \throw IoError if the source document does not parse (tinygltf read it).
std::string patched_gltf_json(const GltfScene& scene, const tinygltf::Model& model, const std::vector<BufferUri>& uris,
                              int indent);

/// Writes a GLB container: `json` padded with spaces, `bin` (if not empty) as the BIN
/// chunk padded with zeros.
void write_glb(std::ostream& os, const std::string& json, const std::vector<unsigned char>& bin);

/// `bytes` as a base64 data URI of MIME type `mime`.
std::string data_uri(const unsigned char* bytes, std::size_t size, const std::string& mime);

}  // namespace ffd
