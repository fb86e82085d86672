#include "support/eigen_lu.h"

#include <Eigen/Dense>

namespace ffd {

void eigen_partial_pivot_solve(const double A[9], const double b[3], double x[3]) {
  const Eigen::Matrix3d M = Eigen::Map<const Eigen::Matrix3d>(A);
  const Eigen::Vector3d r = Eigen::Map<const Eigen::Vector3d>(b);
  const Eigen::Vector3d solution = M.partialPivLu().solve(r);  // as inverse_trilinear called it
  for (int i = 0; i < 3; ++i) x[i] = solution[i];
}

}  // namespace ffd
