// inverse_trilinear for four cells at once: the locates of a batch apply, where a first
// move of a level finds thousands of vertices in their subdivided rest cells.
#pragma once

#include <cstdint>

#include "multires/cell_coordinates.h"

namespace ffd {

/// Four inverse_trilinear problems side by side, one per lane: a cell's corners, a point
/// and a guess. Lane-major arrays, so that the kernel loads each coefficient of the four
/// lanes at once.
struct TrilinearLanes {
  static constexpr int kLanes = 4;
  // Inputs: corner c's coordinate i, the point and the guess, per lane.
  alignas(32) double corners[3][8][kLanes];
  alignas(32) double x[3][kLanes];
  alignas(32) double guess[3][kLanes];
  // Outputs, where `decided` is set: inverse_trilinear returned true with this u and dx_du.
  // Elsewhere (the line search had to halve a step, the map was singular, or Newton's
  // method ran long) undecided: call inverse_trilinear, whose result is then the same.
  alignas(32) double u[3][kLanes];
  alignas(32) double dx_du[3][3][kLanes];  // [row][column]
  bool decided[kLanes] = {};

  /// Lane `lane`'s cell: its corners' columns of `positions`, by index.
  template <class Positions>
  void set_cell(int lane, const Positions& positions, const std::int32_t corner[8]) {
    for (int c = 0; c < 8; ++c)
      for (int i = 0; i < 3; ++i) corners[i][c][lane] = positions(i, corner[c]);
  }
  /// Every lane's cell at once, lane j's corners being the columns corner[j][0..8) of
  /// `positions`: what set_cell writes, by four-wide stores, which the kernel's four-wide
  /// loads then read whole (narrow stores of set_cell make them wait for the last one).
  void set_cells(const Eigen::Matrix3Xd& positions, const std::int32_t corner[kLanes][8]);
  void set_point(int lane, const Eigen::Vector3d& point, const Eigen::Vector3d& start) {
    for (int i = 0; i < 3; ++i) x[i][lane] = point[i], guess[i][lane] = start[i];
  }
  /// Copies lane 0's problem into lanes `from`.. (unused lanes of a last, partial batch).
  void pad(int from);
  /// pad() of the points and guesses only (set_cells fills every lane's corners).
  void pad_points(int from);
  Eigen::Vector3d u_of(int lane) const { return {u[0][lane], u[1][lane], u[2][lane]}; }
  /// Writes lane `lane`'s dx_du into J, coefficient by coefficient.
  void get_dx_du(int lane, Eigen::Matrix3d& J) const {
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) J(i, j) = dx_du[i][j][lane];
  }
};

/// Solves the lanes' problems as inverse_trilinear does, with its roundings: where the build
/// compiles inverse_trilinear with fused multiply-adds (GCC with FMA), in vector registers,
/// every lane's arithmetic in the scalar code's order and fusions (checked bit for bit by
/// tests/multires_test.cpp); elsewhere by calling it for each lane.
void inverse_trilinear(TrilinearLanes& lanes);

}  // namespace ffd
