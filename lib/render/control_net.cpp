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
  const GridComplex& g = lattice.complex(level);
  const Eigen::Matrix3Xd points = lattice.points(level);
  for (Eigen::Index p = 0; p < points.cols(); ++p) net.points.push_back(points.col(p));
  // The edge from node n along `axis` belongs to a cell when one of the 4 cells around it is kept.
  for (std::size_t p = 0; p < g.num_points(); ++p) {
    const GridIndex& n = g.points[p];
    for (int axis = 0; axis < 3; ++axis) {
      GridIndex m = n;
      ++m[axis];
      const std::int32_t q = g.point(m);
      if (q < 0) continue;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      bool used = false;
      for (int k = 0; k < 4 && !used; ++k) {
        GridIndex c = n;
        c[u] -= k & 1;
        c[v] -= k >> 1;
        used = g.has_cell(c[0], c[1], c[2]);
      }
      if (used) net.edges.push_back({static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(q)});
    }
  }
  return net;
}

}  // namespace ffd
