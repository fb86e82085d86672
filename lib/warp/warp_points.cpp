#include "warp/warp_points.h"

#include <cstdint>
#include <numeric>
#include <vector>

#include "warp/bernstein_lattice.h"
#include "warp/bspline_lattice.h"

namespace ffd {

void warp_points(const Warp& warp, const Eigen::Ref<const Eigen::Matrix3Xd>& in, Eigen::Ref<Eigen::Matrix3Xd> out,
                 double* jacobians) {
  const Eigen::Index n = in.cols();
  // The lattices have positions-only kernels (basis values once per point and axis, and
  // the sums across several points at a time); every other warp evaluates point by point.
  // The positions come from that path whether or not Jacobians are asked for, so they
  // never differ by it.
  const auto* bspline = dynamic_cast<const BSplineLattice*>(&warp);
  const auto* bernstein = dynamic_cast<const BernsteinLattice*>(&warp);
  // The kernels take point ids: 0..n-1, kept between calls (a loop over batches of points
  // would otherwise allocate and fault in 4 bytes a point every time).
  thread_local std::vector<std::uint32_t> all_ids;
  if ((bspline || bernstein) && all_ids.size() != static_cast<std::size_t>(n)) {
    all_ids.resize(static_cast<std::size_t>(n));
    std::iota(all_ids.begin(), all_ids.end(), 0u);
  }
  const std::vector<std::uint32_t>& ids = all_ids;
  if (bspline) {
    bspline->apply_positions(in, ids, out);
  } else if (bernstein) {
    bernstein->apply_positions(in, ids, out);
  } else {
#pragma omp parallel for schedule(static)
    for (Eigen::Index i = 0; i < n; ++i) out.col(i) = warp.apply(in.col(i), nullptr);
  }
  if (!jacobians) return;
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Matrix3d J;
    warp.apply(in.col(i), &J);
    double* row = jacobians + 9 * i;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) row[3 * r + c] = J(r, c);
  }
}

}  // namespace ffd
