// IDW deformers (warp/idw_deformer.h): Shepard's formula written out here, on the bunny,
// for the classical power 2 and a non-integer power; exact targets at the control points;
// the identity; Jacobians against central differences; the idw op through the CLI.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "test_meshes.h"
#include "warp/idw_deformer.h"

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

/// Shepard's interpolant of the moves, as the textbook writes it.
Eigen::Vector3d shepard(const std::vector<Eigen::Vector3d>& X, const std::vector<Eigen::Vector3d>& Y, double p,
                        const Eigen::Vector3d& x) {
  Eigen::Vector3d num = Eigen::Vector3d::Zero();
  double den = 0;
  for (std::size_t i = 0; i < X.size(); ++i) {
    const double w = 1 / std::pow((x - X[i]).norm(), p);
    num += w * (Y[i] - X[i]);
    den += w;
  }
  return x + num / den;
}

TEST(Idw, EqualsShepardsFormulaOnTheBunnyAndHitsEveryTarget) {
  const Mesh mesh = test::bunny();
  std::vector<Eigen::Vector3d> X, Y;
  double diag = 0;
  control_points(mesh, 47, 6, X, Y, diag);
  for (const double p : {2.0, 3.5, 1.0}) {
    IdwDeformer idw(X, p);
    for (Eigen::Index v = 0; v < mesh.positions().cols(); v += 5)
      ASSERT_EQ(idw.apply(mesh.positions().col(v), nullptr), Eigen::Vector3d(mesh.positions().col(v))) << "unmoved";
    idw.move_points(0, all_ids(X.size()), Y);
    double worst = 0;
    for (Eigen::Index v = 0; v < mesh.positions().cols(); ++v) {
      const Eigen::Vector3d x = mesh.positions().col(v);
      const bool at_control = std::find(X.begin(), X.end(), x) != X.end();
      if (!at_control) worst = std::max(worst, (idw.apply(x, nullptr) - shepard(X, Y, p, x)).norm());
    }
    EXPECT_LE(worst, 1e-12 * diag) << "power " << p;
    for (std::size_t i = 0; i < X.size(); ++i) EXPECT_EQ(idw.apply(X[i], nullptr), Y[i]) << "power " << p << " point " << i;
  }
}

TEST(Idw, JacobiansMatchCentralDifferences) {
  const Mesh mesh = test::bunny();
  std::vector<Eigen::Vector3d> X, Y;
  double diag = 0;
  control_points(mesh, 47, 6, X, Y, diag);
  const double h = 1e-6 * diag;
  for (const double p : {2.0, 3.5}) {
    IdwDeformer idw(X, p);
    idw.move_points(0, all_ids(X.size()), Y);
    for (Eigen::Index v = 3; v < mesh.positions().cols(); v += 97) {
      const Eigen::Vector3d x = mesh.positions().col(v) + Eigen::Vector3d(0.011, -0.007, 0.013);
      Eigen::Matrix3d J;
      idw.apply(x, &J);
      const Eigen::Matrix3d fd = test::central_jacobian(idw, x, h);
      EXPECT_LE((J - fd).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, J.cwiseAbs().maxCoeff())) << "power " << p << " vertex " << v;
    }
  }
}

TEST(IdwCli, AMoveByIndexEqualsTheSameMoveFromAFile) {
  const std::string dir = temp_folder("idw_cli");
  const std::string points = R"("points": [[-3, 0, 0], [3, 0, 0], [0, 3, 5], [0, -3, 2], [0, 0, -4]])";
  write_file(dir + "/moved.txt", "-3 0 0\n3.5 0.25 0\n0 3 5\n0 -3 2\n0 0 -4\n");
  ASSERT_EQ(run_script(dir, "a", {R"({"op": "idw", "name": "W", "power": 3, )" + points + "}",
                                  R"({"op": "move", "lattice": "W", "points": [{"index": 1, "by": [0.5, 0.25, 0]}]})"}),
            0);
  ASSERT_EQ(run_script(dir, "b", {R"({"op": "idw", "name": "W", "power": 3, )" + points + "}",
                                  R"({"op": "move", "lattice": "W", "positions": {"file": "moved.txt"}})"}),
            0);
  EXPECT_EQ(run_tool("compare " + quoted(dir + "/a.off") + " " + quoted(dir + "/b.off") + " --tolerance 1e-12"), 0);
  const nlohmann::json stats = nlohmann::json::parse(read_file(dir + "/a.stats.json"));
  EXPECT_EQ(stats["steps"][0]["control_points"], 5);
  EXPECT_EQ(stats["steps"][1]["points_moved"], 1);
}

TEST(IdwCli, InputErrorsNameTheirPlace) {
  const std::string dir = temp_folder("idw_cli_errors");
  std::string err;
  EXPECT_EQ(run_script(dir, "dup", {R"({"op": "idw", "name": "W", "points": [[0,0,0], [1,0,0], [0,1,0], [1,0,0]]})"}, &err), 2);
  expect_one_error_line(err, {"dup.json: /steps/0/points", "control points 1 and 3 are at the same place"});
  EXPECT_EQ(run_script(dir, "power", {R"({"op": "idw", "name": "W", "power": -1, "points": [[0,0,0], [1,0,0]]})"}, &err), 2);
  expect_one_error_line(err, {"power.json: /steps/0/power"});
  EXPECT_FALSE(std::filesystem::exists(dir + "/dup.off"));
}

}  // namespace
}  // namespace ffd
