// The lattice kernels and vertex normals of this build against those of another: the
// portable build (FFD_ARCH empty: no AVX, no FMA contraction, SLEEF's two-lane atan2)
// must agree with the default one (FFD_ARCH=native: AVX-512 or AVX2 lanes, FMA) to
// 1e-12 of the box size. Every build writes its outputs to kernel_outputs.bin in its
// build folder; a build configured with -DFFD_KERNEL_REFERENCE=<another build's file>
// (scripts/sanitize_test.sh: the sanitizers' portable build against build/) compares.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>

#include "mesh/vertex_normals.h"
#include "test_meshes.h"
#include "warp/bernstein_lattice.h"
#include "warp/bspline_lattice.h"

namespace ffd {
namespace {

// Every movable point moved by up to 5% of the box's size (fixed seed), so that every
// cell is evaluated and some fold.
void perturb(Lattice& lattice, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  const double size = 0.05 * lattice.box().extents().maxCoeff();
  for (std::size_t f = 0; f < lattice.num_points(); ++f) {
    const Index3 ijk = lattice.index(f);
    if (!lattice.movable(ijk)) continue;
    // Drawn one statement each: the order of a call's arguments is the compiler's (gcc
    // and clang, the two builds compared, draw them in opposite orders).
    const double dx = uniform(rng), dy = uniform(rng), dz = uniform(rng);
    lattice.move_point(ijk, lattice.point(ijk) + size * Eigen::Vector3d(dx, dy, dz));
  }
  lattice.prepare();
}

// The outputs compared: the bunny's vertex normals, then positions and normals of each
// lattice applied to every vertex, in units of the box size (normals are unit vectors).
std::vector<double> kernel_outputs() {
  const Mesh bunny = test::bunny();
  const Eigen::Matrix3Xd pos = bunny.positions(), nrm = vertex_normals(bunny, bunny.positions());
  std::vector<double> out(nrm.data(), nrm.data() + nrm.size());
  std::vector<std::uint32_t> ids(bunny.num_vertices());
  for (std::uint32_t v = 0; v < ids.size(); ++v) ids[v] = v;
  const Eigen::Vector3d lo = pos.rowwise().minCoeff(), hi = pos.rowwise().maxCoeff();
  const double size = 1.1 * (hi - lo).maxCoeff();
  const Parallelepiped box = Parallelepiped::from_min_max(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo));
  std::vector<std::unique_ptr<Lattice>> lattices;
  for (int degree : {1, 2, 3}) lattices.push_back(std::make_unique<BSplineLattice>(box, Index3{6, 5, 7}, degree));
  lattices.push_back(std::make_unique<BernsteinLattice>(box, Index3{4, 3, 5}));
  for (std::size_t k = 0; k < lattices.size(); ++k) {
    perturb(*lattices[k], static_cast<unsigned>(k + 1));
    Eigen::Matrix3Xd p(3, pos.cols()), n(3, pos.cols());
    WarpCounts counts;
    lattices[k]->apply(pos, nrm, ids, p, n, counts);
    for (Eigen::Index i = 0; i < p.size(); ++i) out.push_back(p.data()[i] / size);
    out.insert(out.end(), n.data(), n.data() + n.size());
  }
  return out;
}

// This build's outputs, for a build configured with this one as its reference.
TEST(KernelPortability, WritesThisBuildsOutputs) {
  const std::vector<double> mine = kernel_outputs();
  std::ofstream os(FFD_KERNEL_OUTPUTS, std::ios::binary | std::ios::trunc);
  os.write(reinterpret_cast<const char*>(mine.data()), static_cast<std::streamsize>(mine.size() * sizeof(double)));
  EXPECT_TRUE(os.good()) << FFD_KERNEL_OUTPUTS;
}

#ifdef FFD_KERNEL_REFERENCE
TEST(KernelPortability, AgreesWithTheReferenceBuildTo1e12OfTheBoxSize) {
  const std::vector<double> mine = kernel_outputs();
  std::ifstream is(FFD_KERNEL_REFERENCE, std::ios::binary);
  ASSERT_TRUE(is) << FFD_KERNEL_REFERENCE << " is missing: run the reference build's tests first (scripts/test.sh)";
  std::vector<double> theirs(mine.size() + 1);
  is.read(reinterpret_cast<char*>(theirs.data()), static_cast<std::streamsize>(theirs.size() * sizeof(double)));
  ASSERT_EQ(static_cast<std::size_t>(is.gcount()), mine.size() * sizeof(double)) << "a different case list";
  double worst = 0;
  std::size_t differing = 0;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    worst = std::max(worst, std::abs(mine[i] - theirs[i]));
    differing += mine[i] != theirs[i];
  }
  EXPECT_LE(worst, 1e-12);
  std::printf("kernel outputs: %zu values, %zu differ from %s, by at most %.3g\n", mine.size(), differing,
              FFD_KERNEL_REFERENCE, worst);
}
#endif

}  // namespace
}  // namespace ffd
