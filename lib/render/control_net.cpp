#include "render/control_net.h"

namespace ffd {

Overlay control_net(const Lattice& lattice) {
  Overlay net;
  const std::size_t n = lattice.num_points();
  net.points.resize(n);
  for (std::size_t f = 0; f < n; ++f) net.points[f] = lattice.point(lattice.index(f));
  for (std::size_t f = 0; f < n; ++f) {
    const Index3 ijk = lattice.index(f);
    for (int axis = 0; axis < 3; ++axis) {
      Index3 next = ijk;
      ++next[axis];
      if (lattice.in_range(next))
        net.edges.push_back({static_cast<std::uint32_t>(f), static_cast<std::uint32_t>(lattice.flat(next))});
    }
  }
  return net;
}

Overlay control_net(const OctreeLattice& lattice, int level) {
  Overlay net;
  const Eigen::Matrix3Xd points = lattice.points(level);
  for (Eigen::Index p = 0; p < points.cols(); ++p) net.points.push_back(points.col(p));
  for (const auto& e : lattice.edges(level))
    net.edges.push_back({static_cast<std::uint32_t>(e[0]), static_cast<std::uint32_t>(e[1])});
  return net;
}

}  // namespace ffd
