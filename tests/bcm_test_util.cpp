#include "bcm_test_util.h"

#include <Eigen/SparseLU>

namespace ffd::test {

Eigen::Matrix3Xd direct_kharmonic(const Mesh& mesh, const Eigen::Matrix3Xd& setup, const std::vector<std::uint32_t>& free,
                                  const Eigen::Matrix3Xd& target, int k, bool uniform) {
  using Sparse = Eigen::SparseMatrix<double>;
  const std::vector<Triangle> triangles = all_triangles(mesh);
  const Laplacian lap = uniform ? uniform_laplacian(setup.cols(), triangles) : cotan_laplacian(setup, triangles);
  const Sparse l = Sparse(lap.areas.cwiseInverse().asDiagonal() * lap.weights);
  Sparse lk = l;
  for (int i = 1; i < k; ++i) lk = Sparse(l * lk);
  const Eigen::Index n = setup.cols();
  std::vector<Eigen::Index> slot(static_cast<std::size_t>(n), -1);
  for (std::size_t i = 0; i < free.size(); ++i) slot[free[i]] = static_cast<Eigen::Index>(i);
  const Eigen::Index p = static_cast<Eigen::Index>(free.size());
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(p, 3);
  const Sparse rows = lk.transpose();  // column i = row i of L^k
  for (Eigen::Index i = 0; i < p; ++i)
    for (Sparse::InnerIterator it(rows, free[static_cast<std::size_t>(i)]); it; ++it) {
      const Eigen::Index j = it.row();
      if (slot[static_cast<std::size_t>(j)] >= 0)
        entries.emplace_back(static_cast<int>(i), static_cast<int>(slot[static_cast<std::size_t>(j)]), it.value());
      else
        rhs.row(i) -= it.value() * target.col(j).transpose();
    }
  Sparse a(p, p);
  a.setFromTriplets(entries.begin(), entries.end());
  a.makeCompressed();
  Eigen::SparseLU<Sparse> lu(a);
  return Eigen::MatrixXd(lu.solve(rhs)).transpose();
}

}  // namespace ffd::test
