// Options and counts of adaptive refinement and decimation (Gain & Dodgson section 4).
#pragma once

#include <cstddef>
#include <optional>

namespace ffd {

enum class RemeshTrigger {
  Normal,    // Nimscheck's endpoint normal divergence, ε = 1 − n̄1·n̄2 (the paper's choice)
  Midpoint,  // Greissmair & Purgathofer's midpoint distance (the paper's figure 5)
};

struct RemeshOptions {
  /// Refine an edge whose deformed endpoint normals diverge by more than this.
  double theta_max_deg = 25.7;  // π/7, the paper's example
  /// Decimation candidates: endpoint normals diverge by less than this.
  double theta_min_deg = 20.0;  // π/9
  /// Longest allowed edge; empty: the smallest lattice cell extent (the paper's choice).
  std::optional<double> l_max;
  /// Vertices of this level are not split further (guards runaway refinement).
  int max_level = 8;
  RemeshTrigger trigger = RemeshTrigger::Normal;
  /// Before splitting an edge, split a longer edge of a face on it first (Rivara's
  /// longest-edge bisection). Off: the triggered edge itself, as the paper does.
  bool longest_edge_first = false;
  /// Midpoint trigger only: refine an edge whose chord midpoint stands farther than this
  /// from the true deformed surface (one closest-point step per face); decimate
  /// below `tolerance_min` (default tolerance / 2). Empty: Greissmair & Purgathofer's
  /// d1 + d2 against L·tan(θ/4) for an edge of length L.
  std::optional<double> tolerance;
  std::optional<double> tolerance_min;
};

struct RemeshStats {
  std::size_t triangulated_faces = 0;  // polygon faces split into triangles first
  std::size_t edges_tested = 0;        // trigger evaluations (scan and new edges)
  std::size_t refinements = 0;
  std::size_t decimations = 0;
  std::size_t max_level_hits = 0;      // edges that triggered but whose split would exceed max_level
  std::size_t faces_before = 0, faces_after = 0;
  int highest_level = 0;
  double l_max = 0;                    // the Lmax used
  double ms_test = 0, ms_refine = 0, ms_decimate = 0;
};

}  // namespace ffd
