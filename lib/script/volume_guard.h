// The run's side of volume meshes: their facts and the quality guard (mesh/cell_quality.h)
// as stats, after the read and after every step, and the refusal of a result with
// inverted cells unless the run allows it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "mesh/cell_quality.h"
#include "mesh/mesh.h"

namespace ffd {

struct Scene;

/// The input's volume facts for the stats: format, encoding, nodes, cells by kind,
/// markers with their element counts, and the bounding box. Null for a surface mesh.
nlohmann::ordered_json volume_stats(const Mesh& mesh);

/// Runs the guard on the scene's mesh at its current positions (unless no node moved since
/// the last run), keeps the verdict in
/// `scene.quality`, and returns it as stats: inverted_cells, min_scaled_jacobian,
/// worst_cells (cell, scaled_jacobian, volume, centroid), guard_ms. Null for a surface mesh.
nlohmann::ordered_json guard_scene(Scene& scene);

/// The guard's line for the console ("cells: 0 inverted, min scaled Jacobian 0.412").
std::string guard_line(const CellQuality& quality);

/// A mesh about to be written at `output` whose guard verdict is `quality`: with inverted
/// cells it is refused (InputError naming the count and the first cell, so nothing is
/// written; the message ends "Use smaller moves, or `how_to_allow` to write it anyway"), or
/// with `allow` the warning to give is returned. Empty when none is inverted.
std::string inverted_cells_warning(const Mesh& mesh, const CellQuality& quality, const std::string& output, bool allow,
                                   const std::string& how_to_allow);

/// The same after a run's last step, on scene.quality; the warning goes on scene.warnings.
void check_inverted_cells(Scene& scene, const std::string& output, bool allow);

}  // namespace ffd
