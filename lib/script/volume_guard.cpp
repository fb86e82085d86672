#include "script/volume_guard.h"

#include <map>

#include "common/errors.h"
#include "common/numbers.h"
#include "common/timer.h"
#include "mesh/volume_mesh.h"
#include "script/scene.h"

namespace ffd {

namespace {

nlohmann::ordered_json vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Cells counted by kind name, in VTK's type order.
nlohmann::ordered_json cells_by_kind(const VolumeCells& cells) {
  std::map<std::uint8_t, std::size_t> counts;
  for (const std::uint8_t type : cells.type) ++counts[type];
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [type, count] : counts) out[cell_type_name(type)] = count;
  return out;
}

}  // namespace

nlohmann::ordered_json volume_stats(const Mesh& mesh) {
  const VolumeSource* source = mesh.volume_source();
  if (!source) return nullptr;
  nlohmann::ordered_json markers = nlohmann::ordered_json::array();
  for (const VolumeMarker& m : source->markers)
    markers.push_back({{"name", m.name}, {"dimension", m.dimension}, {"elements", m.cells.size()}});
  const auto p = mesh.positions();
  return {{"format", volume_format_name(source->format)},
          {"version", source->version},
          {"encoding", source->encoding},
          {"dimension", source->dimension},
          {"nodes", mesh.num_vertices()},
          {"cells", source->cells.size()},
          {"cells_by_type", cells_by_kind(source->cells)},
          {"markers", markers},
          {"bbox_min", vec3(p.rowwise().minCoeff())},
          {"bbox_max", vec3(p.rowwise().maxCoeff())}};
}

nlohmann::ordered_json guard_scene(Scene& scene) {
  const VolumeSource* source = scene.mesh.volume_source();
  if (!source) return nullptr;
  Stopwatch clock;
  const Eigen::Matrix3Xd& positions = scene.mesh.position_matrix();
  if (!scene.quality || scene.quality_cache.positions != positions)
    scene.quality = cell_quality(source->cells, positions, scene.quality_cache);
  const CellQuality& q = *scene.quality;
  nlohmann::ordered_json worst = nlohmann::ordered_json::array();
  for (const CellMeasure& m : q.worst)
    worst.push_back({{"cell", m.cell},
                     {"type", cell_type_name(source->cells.type[m.cell])},
                     {"scaled_jacobian", m.scaled_jacobian},
                     {"volume", m.volume},
                     {"centroid", vec3(m.centroid)}});
  nlohmann::ordered_json first = nullptr;
  if (q.inverted) first = q.first_inverted;
  return {{"checked_cells", q.checked},
          {"inverted_cells", q.inverted},
          {"first_inverted_cell", first},
          {"min_scaled_jacobian", q.min_scaled_jacobian},
          {"worst_cells", worst},
          {"guard_ms", clock.ms()}};
}

std::string guard_line(const CellQuality& quality) {
  return "cells: " + format_count(quality.inverted) + " inverted of " + format_count(quality.checked) +
         ", min scaled Jacobian " + format_number(quality.min_scaled_jacobian);
}

std::string inverted_cells_warning(const Mesh& mesh, const CellQuality& q, const std::string& output, bool allow,
                                   const std::string& how_to_allow) {
  if (q.inverted == 0) return {};
  const VolumeSource& source = *mesh.volume_source();
  const CellMeasure first = measure_cell(source.cells, q.first_inverted, mesh.position_matrix());
  const std::string what = format_count(q.inverted) + " inverted cell" + (q.inverted > 1 ? "s" : "") +
                           " (the first: cell " + std::to_string(first.cell) + " in file order, a " +
                           cell_type_name(source.cells.type[first.cell]) + " at " + format_number(first.centroid.x()) +
                           " " + format_number(first.centroid.y()) + " " + format_number(first.centroid.z()) +
                           ", volume " + format_number(first.volume) + ")";
  if (!allow)
    throw InputError(At{output}, "the result has " + what + "; nothing is written. Use smaller moves, or " +
                                     how_to_allow + " to write it anyway");
  return output + ": written with " + what + ", as allowed";
}

void check_inverted_cells(Scene& scene, const std::string& output, bool allow) {
  if (!scene.quality) return;
  const std::string warning = inverted_cells_warning(scene.mesh, *scene.quality, output, allow,
                                                     "--allow-inverted (\"allow_inverted\": true in the script)");
  if (!warning.empty()) scene.warnings.push_back(warning);
}

}  // namespace ffd
