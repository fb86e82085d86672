// Mean value coordinates of a point with respect to a closed triangle mesh (Ju, Schaefer
// and Warren, "Mean Value Coordinates for Closed Triangular Meshes", SIGGRAPH 2005,
// section 3.3 and its robust pseudocode, figure 4).
//
// Choices where the paper leaves a tolerance open (each relative to the cage's size or an
// angle, so they do not depend on the cage's units):
// - x is on a cage vertex when |x - p_j| < 1e-12 times the cage's diagonal: the weights
//   are that vertex's (1 there, 0 elsewhere).
// - x is on a triangle when pi - h < 1e-10 (its three angles, seen from x, sum to 2 pi):
//   the weights are the triangle's barycentric coordinates, sin(theta_i) d_(i-1) d_(i+1)
//   normalized (this also covers its edges: the weight opposite the edge is 0).
// - A triangle whose |s_i| <= 1e-10 for some i lies in a plane through x without
//   containing it, and adds nothing.
// Outside the cage the same formula applies (the coordinates stay defined, can be
// negative, and keep linear precision).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

namespace ffd {

struct MeanValueCage {
  Eigen::Matrix3Xd points;                             // the cage's vertices
  std::vector<std::array<std::uint32_t, 3>> triangles;  // outward oriented
  double diagonal = 0;                                  // of the points' bounding box
  /// Each edge once, and per triangle the edge opposite each corner: the angle an edge
  /// subtends at x is computed once for its two triangles.
  std::vector<std::array<std::uint32_t, 2>> edges;
  std::vector<std::array<std::uint32_t, 3>> opposite_edges;
};

/// A cage of `points` and `triangles` with its edges and diagonal filled in.
MeanValueCage mean_value_cage(Eigen::Matrix3Xd points, std::vector<std::array<std::uint32_t, 3>> triangles);

/// The mean value coordinates w (sum 1) of x, one per cage vertex, and, when `gradient` is
/// given, their gradients with respect to x as its columns (3 x m; forward-mode automatic
/// differentiation of the same formula, so exact to rounding). On the cage (a vertex or a
/// triangle) the gradient is that of the limit formula used there. With `winding`, also
/// the winding number (1 on the cage), from the same angles.
void mean_value_coordinates(const MeanValueCage& cage, const Eigen::Vector3d& x, Eigen::VectorXd& w,
                            Eigen::Matrix3Xd* gradient = nullptr, double* winding = nullptr);

/// The winding number of the closed cage around x (sum of the triangles' signed solid
/// angles over 4 pi, Van Oosterom and Strackee's formula): about 1 inside, 0 outside.
double winding_number(const MeanValueCage& cage, const Eigen::Vector3d& x);

}  // namespace ffd
