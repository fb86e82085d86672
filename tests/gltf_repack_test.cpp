// The buffers of a decoded meshopt file repacked for a write (mesh/gltf_repack.h): only
// the bytes views cover are kept, each at its old offset modulo 8, a GLB's fallback goes
// into buffer 0, and a buffer left without a view goes.
#include <gtest/gtest.h>

#include <numeric>

#include "mesh/gltf_repack.h"

namespace ffd {
namespace {

tinygltf::BufferView repack_view(int buffer, std::size_t offset, std::size_t length) {
  tinygltf::BufferView v;
  v.buffer = buffer;
  v.byteOffset = offset;
  v.byteLength = length;
  return v;
}

// The view's bytes in the model's buffers.
std::vector<unsigned char> view_bytes(const tinygltf::Model& m, int index) {
  const tinygltf::BufferView& v = m.bufferViews.at(static_cast<std::size_t>(index));
  const std::vector<unsigned char>& data = m.buffers.at(static_cast<std::size_t>(v.buffer)).data;
  return {data.begin() + static_cast<std::ptrdiff_t>(v.byteOffset),
          data.begin() + static_cast<std::ptrdiff_t>(v.byteOffset + v.byteLength)};
}

// Buffer 0: an image's 10 bytes at 0, then two compressed streams (12..22, 22..32) that
// views 1 and 2 of the fallback buffer 1 (decoded, 24 bytes) were made from. Buffer 1 is
// the fallback; view 3 reads the middle of view 2's bytes.
tinygltf::Model decoded_meshopt_model() {
  tinygltf::Model m;
  m.buffers.resize(2);
  m.buffers[0].data.resize(32);
  std::iota(m.buffers[0].data.begin(), m.buffers[0].data.end(), static_cast<unsigned char>(0));
  m.buffers[1].data.resize(24);
  std::iota(m.buffers[1].data.begin(), m.buffers[1].data.end(), static_cast<unsigned char>(100));
  tinygltf::Value::Object fallback{{"fallback", tinygltf::Value(true)}};
  m.buffers[1].extensions["EXT_meshopt_compression"] = tinygltf::Value(fallback);
  m.bufferViews = {repack_view(0, 0, 10), repack_view(1, 0, 12), repack_view(1, 12, 12), repack_view(1, 16, 4)};
  for (int k : {1, 2}) {
    tinygltf::Value::Object ext{{"buffer", tinygltf::Value(0)}, {"byteOffset", tinygltf::Value(2 + 10 * k)},
                                {"byteLength", tinygltf::Value(10)}};
    m.bufferViews[static_cast<std::size_t>(k)].extensions["EXT_meshopt_compression"] = tinygltf::Value(ext);
  }
  return m;
}

TEST(GltfRepack, AGlbKeepsWhatItsViewsCoverInItsBinChunk) {
  const tinygltf::Model before = decoded_meshopt_model();
  tinygltf::Model m = before;
  EXPECT_EQ(repack_meshopt_buffers(m, true), std::vector<int>({0}));
  ASSERT_EQ(m.buffers.size(), 1u);
  // The image, then the fallback's one run of views at 16 (its old offset 0 modulo 8).
  EXPECT_EQ(m.buffers[0].data.size(), 16u + 24u);
  for (int v = 0; v < 4; ++v) {
    EXPECT_EQ(m.bufferViews[static_cast<std::size_t>(v)].buffer, 0);
    EXPECT_EQ(view_bytes(m, v), view_bytes(before, v)) << "view " << v;
  }
  EXPECT_EQ(m.bufferViews[3].byteOffset, 32u);
}

TEST(GltfRepack, AGltfDropsTheCompressedStreamsAndKeepsItsFallbackBuffer) {
  const tinygltf::Model before = decoded_meshopt_model();
  tinygltf::Model m = before;
  EXPECT_EQ(repack_meshopt_buffers(m, false), std::vector<int>({0, 1}));
  EXPECT_EQ(m.buffers[0].data.size(), 10u);
  EXPECT_EQ(m.buffers[1].data, before.buffers[1].data);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(view_bytes(m, v), view_bytes(before, v)) << "view " << v;

  // Without the image, buffer 0 holds only streams: it goes, and the fallback is buffer 0.
  tinygltf::Model streams_only = before;
  streams_only.bufferViews.erase(streams_only.bufferViews.begin());
  EXPECT_EQ(repack_meshopt_buffers(streams_only, false), std::vector<int>({1}));
  ASSERT_EQ(streams_only.buffers.size(), 1u);
  for (const tinygltf::BufferView& v : streams_only.bufferViews) EXPECT_EQ(v.buffer, 0);
  EXPECT_EQ(streams_only.buffers[0].data, before.buffers[1].data);
}

TEST(GltfRepack, AModelWithoutMeshoptIsLeftAlone) {
  tinygltf::Model m = decoded_meshopt_model();
  for (tinygltf::BufferView& v : m.bufferViews) v.extensions.clear();
  const tinygltf::Model before = m;
  EXPECT_TRUE(repack_meshopt_buffers(m, true).empty());
  EXPECT_EQ(m.buffers[0].data, before.buffers[0].data);
  EXPECT_EQ(m.buffers.size(), 2u);
}

TEST(GltfRepack, OddOffsetsKeepTheirAlignmentModuloEight) {
  tinygltf::Model m = decoded_meshopt_model();
  m.bufferViews[0] = repack_view(0, 3, 5);  // the image's bytes 3..8
  const tinygltf::Model before = m;
  repack_meshopt_buffers(m, true);
  EXPECT_EQ(m.bufferViews[0].byteOffset, 3u);
  EXPECT_EQ(m.bufferViews[1].byteOffset % 8, 0u);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(view_bytes(m, v), view_bytes(before, v)) << "view " << v;
}

}  // namespace
}  // namespace ffd
