// Sensitivities: the derivative of every vertex's current position with respect to the
// movable control points of one level of a deformer in the warp stack, dx/dp, the input
// of gradient-based shape optimisation (pyGeo's totalSensitivity, SU2_DOT).
//
// Vertex v's position is x_v = G(F(y_v)): y_v is its position in the input space of the
// deformer F (the warps created before F applied), G the warps created after it. F is
// linear in its points, dF(y)/dp_j = w_j(y) I (Deformer::movable_weights, exact), so by
// the chain rule
//   dx_v/dp_j = J_G(F(y_v)) w_j(y_v),
// a 3x3 block; with no warp after F, J_G = I and the block is w_j I. J_G is the product of
// the later warps' Jacobians at the inputs the stack keeps for each vertex. Exact for
// every linear deformer; a deformer frozen into the mesh by a surface edit (bcm) is gone
// from the stack, so it has no sensitivity to give (the script layer refuses it).
#pragma once

#include <cstddef>
#include <ostream>
#include <vector>

#include "mesh/mesh.h"
#include "warp/deformer.h"
#include "warp/warp_stack.h"

namespace ffd {

/// What a sensitivity matrix holds.
struct SensitivityCounts {
  std::size_t rows = 0;     // 3 · vertices
  std::size_t columns = 0;  // 3 · movable points
  std::size_t points = 0;   // movable points of the level
  std::size_t entries = 0;  // non-zero entries written
};

/// A fixed point's entry in movable_columns().
inline constexpr std::uint32_t kFixedPoint = UINT32_MAX;

/// Each of the level's points' column block in dx/dp: m for the m-th movable point in net
/// order (its columns are 3 m + axis), kFixedPoint for a point that cannot move.
std::vector<std::uint32_t> movable_columns(const Deformer& deformer, int level);

/// Writes dx/dp for the deformer at position `k` of `stack` (`deformer`, the same object)
/// and its level `level` as a Matrix Market coordinate real general matrix: row 3·v + axis
/// for vertex v, column 3·m + axis for the m-th movable point in net order (1-based in the
/// file, as the format has it), entries in row-major order with 17 significant digits,
/// exact zeros left out. The header has a comment line per point, "% point m index i j k"
/// (or "index n" for scattered points). Deterministic for any thread count.
SensitivityCounts write_sensitivity(std::ostream& os, const WarpStack& stack, std::size_t k,
                                    const Deformer& deformer, int level, const Mesh& mesh);

}  // namespace ffd
