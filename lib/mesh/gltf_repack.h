// The buffers of a decoded meshopt file, repacked for a write (gltf_io.h). The reader
// decodes each EXT_/KHR_meshopt_compression view into its place in the fallback buffer
// and the write removes the extension: the compressed streams are then bytes nothing
// points at, and a fallback buffer has no URI, which a GLB can only give its first buffer.
// So a write keeps of each buffer only the bytes some buffer view covers, and a GLB's
// fallback buffers go into its BIN chunk (buffer 0). Only the glTF writer includes it.
#pragma once

#include <vector>

#include <tiny_gltf.h>

namespace ffd {

/// Repacks `model`'s buffers when a view of it carries a meshopt extension; returns, for
/// each buffer of the repacked model, the index of the buffer it was (its JSON object),
/// or an empty vector when there was nothing to repack.
/// - a buffer that held compressed streams keeps only the byte ranges of its views, in
///   their order, each run of touching or overlapping views placed at its old offset
///   modulo 8 (so every accessor keeps its alignment);
/// - with `binary`, each fallback buffer's view ranges are appended to buffer 0 and the
///   fallback buffer goes;
/// - a buffer no view points at any more goes; views are re-pointed.
std::vector<int> repack_meshopt_buffers(tinygltf::Model& model, bool binary);

}  // namespace ffd
