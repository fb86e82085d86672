#include "render/control_net.h"

namespace ffd {

Overlay control_net(const Deformer& deformer, int level) {
  Overlay net;
  const Eigen::Matrix3Xd points = deformer.points(level);
  net.points.reserve(static_cast<std::size_t>(points.cols()));
  for (Eigen::Index p = 0; p < points.cols(); ++p) net.points.push_back(points.col(p));
  for (const auto& e : deformer.net_edges(level)) net.edges.push_back({e[0], e[1]});
  return net;
}

}  // namespace ffd
