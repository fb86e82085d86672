// The renderer's pictures of this build against another's: the portable build (clang, no
// AVX, no FMA) must draw the same bytes as the default one (GCC, FFD_ARCH=native), which is
// what "the same picture on every machine" rests on. Every build writes its pictures to
// render_outputs.bin in its build folder; a build configured with a reference build
// (FFD_KERNEL_REFERENCE, scripts/sanitize_test.sh) compares its own with that folder's.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "render/heatmap.h"
#include "render/render.h"
#include "test_meshes.h"

namespace ffd {
namespace {

// The bunny smooth and orthographic, flat and in perspective, in normal colours, and a
// heat map of a shear: every shading path's pixels, concatenated.
std::vector<std::uint8_t> render_outputs() {
  const Mesh bunny = test::bunny();
  std::vector<std::uint8_t> out;
  auto add = [&](const Image& im) { out.insert(out.end(), im.rgb.begin(), im.rgb.end()); };
  RenderOptions o;
  set_size(o, "320x240");
  add(render_mesh(bunny, o));
  RenderOptions p = o;
  p.perspective = true;
  p.flat = true;
  set_view(p, "30,-15");
  add(render_mesh(bunny, p));
  RenderOptions n = o;
  n.color = ColorMode::Normals;
  add(render_mesh(bunny, n));
  std::vector<double> d(bunny.num_vertices());
  for (std::size_t v = 0; v < d.size(); ++v) d[v] = std::max(0.0, bunny.positions()(1, Eigen::Index(v)));
  double max = 0;
  for (double x : d) max = std::max(max, x);
  add(render_heatmap(bunny, d, 0.1 * max, max, 0.5 * max, o));
  return out;
}

TEST(RenderPortability, WritesThisBuildsPictures) {
  const std::vector<std::uint8_t> mine = render_outputs();
  std::ofstream os(FFD_RENDER_OUTPUTS, std::ios::binary | std::ios::trunc);
  os.write(reinterpret_cast<const char*>(mine.data()), static_cast<std::streamsize>(mine.size()));
  EXPECT_TRUE(os.good()) << FFD_RENDER_OUTPUTS;
}

#ifdef FFD_RENDER_REFERENCE
TEST(RenderPortability, DrawsTheSameBytesAsTheReferenceBuild) {
  const std::vector<std::uint8_t> mine = render_outputs();
  std::ifstream is(FFD_RENDER_REFERENCE, std::ios::binary);
  ASSERT_TRUE(is) << FFD_RENDER_REFERENCE << " is missing: run the reference build's tests first (scripts/test.sh)";
  const std::vector<std::uint8_t> theirs{std::istreambuf_iterator<char>(is), std::istreambuf_iterator<char>()};
  ASSERT_EQ(theirs.size(), mine.size()) << "a different case list";
  std::size_t differing = 0;
  for (std::size_t i = 0; i < mine.size(); ++i) differing += mine[i] != theirs[i];
  EXPECT_EQ(differing, 0u) << "bytes of " << mine.size() << " differ from " << FFD_RENDER_REFERENCE;
}
#endif

}  // namespace
}  // namespace ffd
