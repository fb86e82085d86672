// The point rules of one subdivision step of a GridComplex: Ono et al.'s octree
// subdivision (section 2.1) and MacCracken & Joy's Catmull-Clark subdivision volumes
// (Ono et al.'s appendix, with its boundary rules). Both produce the connectivity of
// refine(); they differ only in where the new points go.
//
// A new point is named by its node at twice the coarse resolution. The parity of its
// coordinates says what it was made for: all even, the coarse point at half the
// coordinates (vertex point); one odd, the edge along that axis; two odd, the face across
// the even axis; three odd, the cell.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "multires/grid_complex.h"
#include "multires/step_grid.h"

namespace ffd {

enum class SubdivisionRule {
  Octree,        // cell and face points: averages; edge points: midpoints; old points kept
  CatmullClark,  // the appendix's volume rules, its boundary rules and surface rules
};

/// Coarse point indices and weights (they sum to 1) of one new point.
using Stencil = std::vector<std::pair<std::int32_t, double>>;

/// The weights of the coarse points that place the new point at `node` (twice the
/// coarse resolution), replacing `out`. The node must be a corner of a child of a cell of
/// `coarse`.
void subdivision_stencil(const GridComplex& coarse, const GridIndex& node, SubdivisionRule rule, Stencil& out);
/// The same over a large octree level's implied C^k (point indices: its slots).
void subdivision_stencil(const StepGrid& coarse, const GridIndex& node, SubdivisionRule rule, Stencil& out);

/// The field on the points of `fine` (a sub-complex of refine(coarse), or all of it) from
/// the field X on the points of `coarse` (one column per point, any number of rows: the
/// rules are linear, so positions and displacements subdivide alike). Deterministic for
/// any thread count.
Eigen::MatrixXd subdivide_field(const GridComplex& coarse, const GridComplex& fine, const Eigen::MatrixXd& X,
                                SubdivisionRule rule);

/// subdivide_field for a field that is zero but near a few coarse points: new points whose
/// stencils read only zeros are left zero without computing them (the same values, bit
/// for bit, as subdivide_field's). `nonzero`: per coarse point, whether X's column may be
/// non-zero.
Eigen::MatrixXd subdivide_sparse_field(const GridComplex& coarse, const GridComplex& fine, const Eigen::MatrixXd& X,
                                       const std::vector<std::uint8_t>& nonzero, SubdivisionRule rule);

/// subdivide_field and subdivision_matrix(coarse, fine.points, rule) from one pass over
/// the stencils (the field's values are subdivide_field's, bit for bit).
Eigen::MatrixXd subdivide_field_and_matrix(const GridComplex& coarse, const GridComplex& fine, const Eigen::MatrixXd& X,
                                           SubdivisionRule rule, Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix);

/// Rows of the subdivision matrix of a step C^(k-1) -> C^k (columns: the coarse points of
/// a StepGrid, or its slots when its C^(k-1) is implied), built one at a time where they
/// are needed. A row is the one subdivision_matrix() makes: a point's weights merged
/// (summed in the stencil's order) and listed in the order of the points' nodes (k, j, i),
/// a built complex's column order. So a product of some rows with a field gives each of
/// them the value the whole matrix's product gives, bit for bit.
class SubdivisionRows {
public:
  /// Appends the row of the new point at `node` (a corner of a child of a cell of
  /// `coarse`); returns its index.
  std::int32_t append(const StepGrid& coarse, const GridIndex& node, SubdivisionRule rule);
  /// The matrix of the listed rows (in that order) over `cols` coarse points (or slots).
  Eigen::SparseMatrix<double, Eigen::RowMajor> matrix(const std::vector<std::int32_t>& rows, Eigen::Index cols) const;
  std::size_t bytes() const;

private:
  std::vector<int> starts_{0};
  std::vector<std::int32_t> columns_;
  std::vector<double> values_;
  Stencil stencil_;
  std::vector<std::uint8_t> near_;
};

/// The same map as a matrix, for the new points at `nodes` (rows) from the coarse points
/// (columns), a point's weights merged: with nodes = fine.points,
/// subdivide_field(coarse, fine, X, rule) = (S * X^T)^T up to rounding.
Eigen::SparseMatrix<double, Eigen::RowMajor> subdivision_matrix(const GridComplex& coarse,
                                                               const std::vector<GridIndex>& nodes, SubdivisionRule rule);

}  // namespace ffd
