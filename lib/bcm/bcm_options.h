// Options of a boundary-constraint editor (Botsch & Kobbelt), mapped 1:1 to the `bcm`
// script step.
#pragma once

#include <string>


namespace ffd {

enum class LaplacianKind {
  Cotan,          // eq. 4: cotangent weights (negative ones kept), mixed Voronoi areas, on the surface at setup
  CotanPositive,  // the same with negative weights set to zero: a discrete maximum principle
  Uniform,        // 1/valence umbrella operator
  Anisotropic,    // cotangent weights on the support's conformal map scaled to equal diameters
};

struct BcmOptions {
  /// Order of the energy: Δ^k p = 0 (1 membrane, 2 thin plate, 3 minimal curvature variation).
  int k = 3;
  /// Boundary smoothness c ∈ [0, k−1] at the outer (fixed) and inner (handle) boundary;
  /// negative means k − 1 (C^(k−1), the clamped solution).
  double outer_continuity = -1;
  double inner_continuity = -1;
  LaplacianKind laplacian = LaplacianKind::Cotan;
  /// Multiresolution editing (section 4): edit a smooth base, carry the support's detail.
  bool detail = true;
};

}  // namespace ffd
