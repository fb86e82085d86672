#include "script/scattered_steps.h"

#include "script/selection.h"

namespace ffd {

DeformerShape scattered_shape(const std::string& kind, std::size_t count, const std::string& noun) {
  DeformerShape shape{kind, false, 0, -1, nullptr};
  shape.grid = false;
  shape.noun = noun;
  shape.unmovable = [count, noun](int, const PointIndex& index) -> std::optional<std::string> {
    const std::string text = count ? noun + " 0 to " + std::to_string(count - 1) : "its " + noun + "' numbers";
    if (index.grid || index.n < 0 || (count && static_cast<std::size_t>(index.n) >= count)) return text;
    return std::nullopt;
  };
  return shape;
}

void check_point_source(const PointSource& source) {
  if (source.select) check_vertex_selection(*source.select);
}

std::vector<Eigen::Vector3d> rest_points(const PointSource& source, const Scene& scene) {
  std::vector<Eigen::Vector3d> rest = source.points;
  if (source.select) {
    const auto positions = scene.mesh.positions();
    for (std::uint32_t v : select_vertices(*source.select, positions, scene.mesh.volume_source())) rest.push_back(positions.col(v));
  }
  return rest;
}

}  // namespace ffd
