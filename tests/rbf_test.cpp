// RBF deformers (warp/rbf_deformer.h): equal to PyGeM's RBF, re-implemented here from its
// source (rbf.py, rbf_factory.py: the system H [W; c; Q] = [Y; 0] solved whole, the kernels
// as PyGeM writes them) for every kernel on the bunny; interpolation, linear precision,
// the identity, Jacobians against central differences; and the rbf op through the CLI.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "test_meshes.h"
#include "warp/rbf_deformer.h"

namespace ffd {
namespace {

using test::all_ids;
using test::control_points;
using test::expect_one_error_line;
using test::quoted;
using test::read_file;
using test::run_script;
using test::run_tool;
using test::temp_folder;
using test::write_file;

struct KernelCase {
  const char* name;
  RbfOptions options;
};

/// Every PyGeM kernel, with radii in the bunny's units (its bounding box is about 15).
std::vector<KernelCase> kernels() {
  return {{"gaussian_spline", {RbfKernel::Gaussian, 4.0, 2}},
          {"multi_quadratic_biharmonic_spline", {RbfKernel::MultiQuadratic, 1.0, 2}},
          {"inv_multi_quadratic_biharmonic_spline", {RbfKernel::InvMultiQuadratic, 2.0, 2}},
          {"thin_plate_spline k=2", {RbfKernel::ThinPlate, 3.0, 2}},
          {"thin_plate_spline k=3", {RbfKernel::ThinPlate, 3.0, 3}},
          {"beckert_wendland_c2_basis", {RbfKernel::Wendland, 9.0, 2}},
          {"polyharmonic_spline k=3", {RbfKernel::Polyharmonic, 5.0, 3}},
          {"polyharmonic_spline k=2", {RbfKernel::Polyharmonic, 5.0, 2}}};
}

/// PyGeM's kernels (rbf_factory.py), written as it writes them.
double pygem_kernel(const RbfOptions& o, double X) {
  const double r = o.radius;
  switch (o.kernel) {
    case RbfKernel::Gaussian:
      return std::exp(-(X * X) / (r * r));
    case RbfKernel::MultiQuadratic:
      return std::sqrt(X * X + r * r);
    case RbfKernel::InvMultiQuadratic:
      return 1.0 / std::sqrt(X * X + r * r);
    case RbfKernel::ThinPlate: {
      const double arg = X / r, result = std::pow(arg, o.k);
      return arg > 0 ? result * std::log(arg) : result;
    }
    case RbfKernel::Wendland: {
      const double arg = X / r, first = 1 - arg > 0 ? std::pow(1 - arg, 4) : 0;
      return first * (4 * arg + 1);
    }
    case RbfKernel::Polyharmonic: {
      const double s = X / r;
      if (o.k & 1) return std::pow(s, o.k);
      return s < 1 ? std::pow(s, o.k - 1) * std::log(std::pow(s, s)) : std::pow(s, o.k) * std::log(s);
    }
  }
  return 0;
}

/// PyGeM's RBF.__call__ after _get_weights: H = [Phi 1 X; 1^T 0 0; X^T 0 0], weights =
/// H^-1 [Y; 0], M(x) = [phi(|x - X|) 1 x] weights.
Eigen::Matrix3Xd pygem_rbf(const std::vector<Eigen::Vector3d>& X, const std::vector<Eigen::Vector3d>& Y,
                           const RbfOptions& o, const Eigen::Matrix3Xd& points) {
  const Eigen::Index n = static_cast<Eigen::Index>(X.size());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n + 4, n + 4), rhs = Eigen::MatrixXd::Zero(n + 4, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) H(i, j) = pygem_kernel(o, (X[i] - X[j]).norm());
    H(n, i) = H(i, n) = 1;
    for (int a = 0; a < 3; ++a) H(i, n + 1 + a) = H(n + 1 + a, i) = X[i][a];
    rhs.row(i) = Y[i].transpose();
  }
  const Eigen::MatrixXd weights = H.fullPivLu().solve(rhs);
  Eigen::Matrix3Xd out(3, points.cols());
  for (Eigen::Index v = 0; v < points.cols(); ++v) {
    Eigen::RowVectorXd row(n + 4);
    for (Eigen::Index i = 0; i < n; ++i) row[i] = pygem_kernel(o, (points.col(v) - X[i]).norm());
    row[n] = 1;
    row.tail<3>() = points.col(v).transpose();
    out.col(v) = (row * weights).transpose();
  }
  return out;
}

TEST(Rbf, EveryKernelEqualsPyGemsMapOnTheBunny) {
  const Mesh mesh = test::bunny();
  std::vector<Eigen::Vector3d> X, Y;
  double diag = 0;
  control_points(mesh, 46, 5, X, Y, diag);
  ASSERT_EQ(X.size(), 40u);
  for (const KernelCase& k : kernels()) {
    RbfDeformer rbf(X, k.options);
    rbf.move_points(0, all_ids(X.size()), Y);
    const Eigen::Matrix3Xd expected = pygem_rbf(X, Y, k.options, mesh.positions());
    double worst = 0, interpolation = 0;
    for (Eigen::Index v = 0; v < expected.cols(); ++v)
      worst = std::max(worst, (rbf.apply(mesh.positions().col(v), nullptr) - expected.col(v)).norm());
    for (std::size_t i = 0; i < X.size(); ++i) interpolation = std::max(interpolation, (rbf.apply(X[i], nullptr) - Y[i]).norm());
    EXPECT_LE(worst, 1e-9 * diag) << k.name << " (condition " << rbf.condition() << ")";
    EXPECT_LE(interpolation, 1e-12 * diag) << k.name << ": control points reach their targets";
  }
}

TEST(Rbf, AnAffineMoveIsThatAffineMapAndNoMoveIsTheIdentity) {
  const Mesh mesh = test::bunny();
  std::vector<Eigen::Vector3d> X, Y;
  double diag = 0;
  control_points(mesh, 46, 5, X, Y, diag);
  Eigen::Matrix3d A;
  A << 1.1, 0.2, 0, -0.1, 0.9, 0.05, 0.02, 0, 1.2;
  const Eigen::Vector3d b(0.3, -0.2, 0.5);
  std::vector<Eigen::Vector3d> affine;
  for (const Eigen::Vector3d& x : X) affine.push_back(A * x + b);
  for (const KernelCase& k : kernels()) {
    RbfDeformer rbf(X, k.options);
    for (Eigen::Index v = 0; v < mesh.positions().cols(); ++v) {
      const Eigen::Vector3d x = mesh.positions().col(v);
      ASSERT_EQ(rbf.apply(x, nullptr), x) << k.name << ": unmoved, bit for bit";
    }
    rbf.move_points(0, all_ids(X.size()), affine);
    double worst = 0;
    for (Eigen::Index v = 0; v < mesh.positions().cols(); ++v) {
      const Eigen::Vector3d x = mesh.positions().col(v);
      worst = std::max(worst, (rbf.apply(x, nullptr) - (A * x + b)).norm());
    }
    EXPECT_LE(worst, 1e-9 * diag) << k.name;
    rbf.move_points(0, all_ids(X.size()), X);  // back at rest: the identity again
    EXPECT_EQ(rbf.apply(mesh.positions().col(7), nullptr), Eigen::Vector3d(mesh.positions().col(7))) << k.name;
  }
}

TEST(Rbf, JacobiansMatchCentralDifferences) {
  const Mesh mesh = test::bunny();
  std::vector<Eigen::Vector3d> X, Y;
  double diag = 0;
  control_points(mesh, 46, 5, X, Y, diag);
  const double h = 1e-6 * diag;
  for (const KernelCase& k : kernels()) {
    RbfDeformer rbf(X, k.options);
    rbf.move_points(0, all_ids(X.size()), Y);
    for (Eigen::Index v = 3; v < mesh.positions().cols(); v += 97) {
      const Eigen::Vector3d x = mesh.positions().col(v) + Eigen::Vector3d(0.011, -0.007, 0.013);
      Eigen::Matrix3d J;
      rbf.apply(x, &J);
      const Eigen::Matrix3d fd = test::central_jacobian(rbf, x, h);
      EXPECT_LE((J - fd).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, J.cwiseAbs().maxCoeff())) << k.name << " at vertex " << v;
    }
  }
}

// Wendland's compact kernel at a radius that covers a few neighbours: a sparse system
// (UMFPACK, neighbours from the k-d tree), still PyGeM's map.
TEST(Rbf, TheCompactKernelFactorsASparseSystemAndIsStillPyGemsMap) {
  const Mesh mesh = test::bunny();
  std::vector<Eigen::Vector3d> X, Y;
  const Eigen::Matrix3Xd p = mesh.positions();
  const double diag = (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  for (Eigen::Index v = 0; v < p.cols(); v += 9) {
    X.push_back(p.col(v));
    Y.push_back(X.back() + diag * Eigen::Vector3d(u(rng), u(rng), u(rng)));
  }
  const RbfOptions wendland{RbfKernel::Wendland, 0.15 * diag, 2};
  RbfDeformer rbf(X, wendland);
  const std::size_t n = X.size();
  EXPECT_TRUE(rbf.sparse());
  EXPECT_LT(rbf.matrix_entries(), n * n / 4) << n << " points";
  rbf.move_points(0, all_ids(n), Y);
  const Eigen::Matrix3Xd expected = pygem_rbf(X, Y, wendland, p);
  double worst = 0;
  for (Eigen::Index v = 0; v < p.cols(); ++v) worst = std::max(worst, (rbf.apply(p.col(v), nullptr) - expected.col(v)).norm());
  EXPECT_LE(worst, 1e-9 * diag);
}

TEST(Rbf, ASingularLayoutIsRefusedNamingThePoints) {
  std::vector<Eigen::Vector3d> X = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}};
  test::expect_input_error([&] { RbfDeformer(X, RbfOptions{}); }, "control points 1 and 4 are at the same place");
  std::vector<Eigen::Vector3d> flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 3, 0}};
  test::expect_input_error([&] { RbfDeformer(flat, RbfOptions{}); }, "the control points lie in one plane");
}

// The same control points from a list, a file and a selection; moves by index and from a
// file of positions give the same mesh.
TEST(RbfCli, PointsFromAListAFileOrASelectionAndMovesByIndexOrFile) {
  const std::string dir = temp_folder("rbf_cli");
  const Mesh bunny = test::bunny();
  std::string list = "[", lines;
  const std::vector<int> ids = {0, 150, 300, 450, 600, 750, 900, 1050, 1200, 1350, 1500, 1650};
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const Eigen::Vector3d p = bunny.positions().col(ids[i]);
    char buf[160];
    std::snprintf(buf, sizeof buf, "[%.17g, %.17g, %.17g]", p[0], p[1], p[2]);
    list += (i ? ", " : "") + std::string(buf);
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p[0] + (i == 4 ? 0.5 : 0.0), p[1], p[2]);
    lines += buf;
  }
  list += "]";
  write_file(dir + "/moved.txt", lines);
  const std::string kind = R"("kernel": "thin_plate_spline", "radius": 2)";
  const std::string move = R"({"op": "move", "lattice": "R", "points": [{"index": 4, "by": [0.5, 0, 0]}]})";
  std::string selection = "[";
  for (std::size_t i = 0; i < ids.size(); ++i) selection += (i ? ", " : "") + std::to_string(ids[i]);
  selection += "]";
  ASSERT_EQ(run_script(dir, "a", {R"({"op": "rbf", "name": "R", )" + kind + R"(, "points": )" + list + "}", move}), 0);
  ASSERT_EQ(run_script(dir, "b", {R"({"op": "rbf", "name": "R", )" + kind + R"(, "points": {"select": {"indices": )" + selection + "}}}", move}), 0);
  ASSERT_EQ(run_script(dir, "c", {R"({"op": "rbf", "name": "R", )" + kind + R"(, "points": )" + list + "}",
                                  R"({"op": "move", "lattice": "R", "positions": {"file": "moved.txt"}})"}), 0);
  for (const char* other : {"b", "c"})
    EXPECT_EQ(run_tool("compare " + quoted(dir + "/a.off") + " " + quoted(dir + "/" + other + ".off") + " --tolerance 1e-12"), 0) << other;
  const nlohmann::json stats = nlohmann::json::parse(read_file(dir + "/c.stats.json"));
  EXPECT_EQ(stats["steps"][1]["points_moved"], 1);
  EXPECT_GT(stats["steps"][0]["condition_number"].get<double>(), 1.0);
}

TEST(RbfCli, InputErrorsNameTheirPlace) {
  const std::string dir = temp_folder("rbf_cli_errors");
  std::string err;
  EXPECT_EQ(run_script(dir, "dup", {R"({"op": "rbf", "name": "R", "points": [[0,0,0], [1,0,0], [0,1,0], [0,0,1], [1,0,0]]})"}, &err), 2);
  expect_one_error_line(err, {"dup.json: /steps/0/points", "control points 1 and 4 are at the same place"});
  EXPECT_EQ(run_script(dir, "radius", {R"({"op": "rbf", "name": "R", "radius": -1, "points": [[0,0,0], [1,0,0], [0,1,0], [0,0,1]]})"}, &err), 2);
  expect_one_error_line(err, {"radius.json: /steps/0/radius"});
  write_file(dir + "/two.txt", "0 0 0\n1 1 1\n");
  EXPECT_EQ(run_script(dir, "count", {R"({"op": "rbf", "name": "R", "points": [[0,0,0], [1,0,0], [0,1,0], [0,0,1]]})",
                                      R"({"op": "move", "lattice": "R", "positions": {"file": "two.txt"}})"}, &err), 2);
  expect_one_error_line(err, {"count.json: /steps/1/positions", "has 2 points", "has 4"});
  EXPECT_EQ(run_script(dir, "index", {R"({"op": "rbf", "name": "R", "points": [[0,0,0], [1,0,0], [0,1,0], [0,0,1]]})",
                                      R"({"op": "move", "lattice": "R", "points": [{"index": 4, "by": [1, 0, 0]}]})"}, &err), 2);
  expect_one_error_line(err, {"index.json: /steps/1/points/0/index", "point 4 is not movable (movable: control points 0 to 3)"});
  EXPECT_FALSE(std::filesystem::exists(dir + "/dup.off"));
}

}  // namespace
}  // namespace ffd
