// The compressed-glTF fuzz targets' inputs, shared with the ctest replay of their corpus:
// the fuzzed bytes become the compressed stream of a small, otherwise valid glTF (GLB),
// which then goes through check_gltf_round_trip. Mutating the stream itself reaches the
// decoders (Draco, meshopt) far more often than mutating whole files would.
//
// - gltf_draco: [u32 points][u32 corners][Draco stream] for one primitive with POSITION,
//   NORMAL, TEXCOORD_0 (Draco attributes 0, 1, 2) and indices.
// - gltf_meshopt: [u8 mode][u8 filter][u8 stride / 4 - 1][u32 count][stream] for one
//   EXT_meshopt_compression view in a fallback buffer: the POSITION of a point primitive
//   (ATTRIBUTES), or the indices of a triangle primitive over three plain vertices
//   (TRIANGLES, INDICES).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "gltf_input.h"

namespace ffd::fuzz {

inline std::uint32_t input_u32(std::string_view bytes, std::size_t at) {
  std::uint32_t v = 0;
  if (bytes.size() >= at + 4) std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

/// A GLB of `json` with `bin` as its BIN chunk.
inline std::string fuzz_glb(std::string json, std::string bin) {
  json.append((4 - json.size() % 4) % 4, ' ');
  bin.append((4 - bin.size() % 4) % 4, '\0');
  auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  return "glTF" + u32(2) + u32(static_cast<std::uint32_t>(28 + json.size() + bin.size())) +
         u32(static_cast<std::uint32_t>(json.size())) + "JSON" + json + u32(static_cast<std::uint32_t>(bin.size())) +
         std::string("BIN\0", 4) + bin;
}

inline std::string draco_glb(std::string_view input) {
  // Counts past 2^20 would only make the harness slow: the decoder refuses them anyway.
  const std::uint32_t points = std::min<std::uint32_t>(input_u32(input, 0), 1u << 20);
  const std::uint32_t corners = std::min<std::uint32_t>(input_u32(input, 4), 1u << 22);
  const std::string stream(input.substr(std::min<std::size_t>(8, input.size())));
  const std::string p = std::to_string(points), c = std::to_string(corners), n = std::to_string(stream.size());
  const std::string json =
      R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],)"
      R"("extensionsRequired":["KHR_draco_mesh_compression"],"buffers":[{"byteLength":)" + n +
      R"(}],"bufferViews":[{"buffer":0,"byteLength":)" + n +
      R"(}],"accessors":[{"componentType":5126,"count":)" + p + R"(,"type":"VEC3","min":[0,0,0],"max":[1,1,1]},)"
      R"({"componentType":5126,"count":)" + p + R"(,"type":"VEC3"},{"componentType":5126,"count":)" + p +
      R"(,"type":"VEC2"},{"componentType":5125,"count":)" + c + R"(,"type":"SCALAR"}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3,)"
      R"("extensions":{"KHR_draco_mesh_compression":{"bufferView":0,"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}}}}]}],)"
      R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0})";
  return fuzz_glb(json, stream);
}

inline std::string meshopt_glb(std::string_view input) {
  static const char* const modes[] = {"ATTRIBUTES", "TRIANGLES", "INDICES"};
  static const char* const filters[] = {"NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"};
  const std::string mode = modes[input.size() > 0 ? static_cast<unsigned char>(input[0]) % 3 : 0];
  const std::string filter = filters[input.size() > 1 ? static_cast<unsigned char>(input[1]) % 4 : 0];
  const std::size_t stride = 4 * (1 + (input.size() > 2 ? static_cast<unsigned char>(input[2]) % 8 : 2));
  const std::uint32_t count = std::min<std::uint32_t>(input_u32(input, 3), 1u << 16);
  const std::string stream(input.substr(std::min<std::size_t>(7, input.size())));
  // Buffer 0: three plain vertices, then the stream. Buffer 1: the fallback.
  std::string bin(36, '\0');
  const float corner[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::memcpy(bin.data(), corner, 36);
  bin += stream;
  const std::string length = std::to_string(count * stride), s = std::to_string(stride), k = std::to_string(count);
  const bool attributes = mode == "ATTRIBUTES";
  const std::string prim = attributes ? R"({"attributes":{"POSITION":1},"mode":0})"
                                      : R"({"attributes":{"POSITION":0},"indices":1})";
  const std::string index_type = stride == 2 ? "5123" : "5125";
  const std::string json =
      R"({"asset":{"version":"2.0"},"extensionsUsed":["EXT_meshopt_compression"],)"
      R"("extensionsRequired":["EXT_meshopt_compression"],"buffers":[{"byteLength":)" + std::to_string(bin.size()) +
      R"(},{"byteLength":)" + length + R"(,"extensions":{"EXT_meshopt_compression":{"fallback":true}}}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":36},{"buffer":1,"byteLength":)" + length +
      (attributes ? R"(,"byteStride":)" + s : std::string()) +
      R"(,"extensions":{"EXT_meshopt_compression":{"buffer":0,"byteOffset":36,"byteLength":)" +
      std::to_string(stream.size()) + R"(,"byteStride":)" + s + R"(,"count":)" + k + R"(,"mode":")" + mode +
      R"(","filter":")" + filter + R"("}}}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,)"
      R"("type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":)" +
      (attributes ? std::string("5126") : index_type) + R"(,"count":)" + k + R"(,"type":")" +
      (attributes ? "VEC3" : "SCALAR") + R"("}],"meshes":[{"primitives":[)" + prim +
      R"(]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0})";
  return fuzz_glb(json, bin);
}

}  // namespace ffd::fuzz
