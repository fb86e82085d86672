// The picture `ffdtool compare --heatmap` draws: mesh B shaded, each vertex coloured by
// its distance to mesh A, with the max and mean distance written on it.
//
// - Grey where the distance is within the tolerance (and where it is unknown).
// - Beyond it, viridis (perceptually uniform, readable in grey and by colour-blind
//   viewers) from the tolerance (dark violet) to the largest distance (yellow).
// - A legend bar with its end values, drawn only when some vertex is beyond tolerance.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/mesh.h"
#include "render/image.h"
#include "render/render.h"

namespace ffd {

/// viridis at t in [0, 1] (clamped), RGB in [0, 1].
Eigen::Vector3f viridis(double t);

/// One colour per distance: grey within `tolerance` or NaN, else viridis from tolerance
/// to `max_distance`.
std::vector<Eigen::Vector3f> distance_colors(const std::vector<double>& distances, double tolerance,
                                             double max_distance);

/// Renders `b` coloured by `distances` (one per vertex of b) and writes "max … mean …
/// tolerance …" and, when a distance exceeds the tolerance, the legend bar.
Image render_heatmap(const Mesh& b, const std::vector<double>& distances, double tolerance, double max_distance,
                     double mean_distance, const RenderOptions& options);

}  // namespace ffd
