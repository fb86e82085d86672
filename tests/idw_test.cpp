// IDW deformers (warp/idw_deformer.h): Shepard's formula written out here, on the bunny,
// for the classical power 2 and a non-integer power; exact targets at the control points;
// the identity; Jacobians against central differences; the idw op through the CLI.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "test_meshes.h"
#include "warp/idw_deformer.h"

namespace ffd {
namespace {

using test::expect_one_error_line;
using test::quoted;
using test::read_file;
using test::run_tool;
using test::script;
using test::temp_folder;
using test::write_file;

/// 40 bunny vertices as control points, and targets moved by up to 3% of the diagonal.
void control_points(const Mesh& mesh, std::vector<Eigen::Vector3d>& X, std::vector<Eigen::Vector3d>& Y, double& diag) {
  const Eigen::Matrix3Xd p = mesh.positions();
  diag = (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-0.03, 0.03);
  for (Eigen::Index v = 0; v < p.cols() && X.size() < 40; v += 47) {
    X.push_back(p.col(v));
    Y.push_back(X.back() + diag * Eigen::Vector3d(u(rng), u(rng), u(rng)));
  }
}

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

std::vector<std::size_t> all_ids(std::size_t n) {
  std::vector<std::size_t> ids(n);
  for (std::size_t i = 0; i < n; ++i) ids[i] = i;
  return ids;
}

TEST(Idw, EqualsShepardsFormulaOnTheBunnyAndHitsEveryTarget) {
  const Mesh mesh = test::bunny();
  std::vector<Eigen::Vector3d> X, Y;
  double diag = 0;
  control_points(mesh, X, Y, diag);
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
  control_points(mesh, X, Y, diag);
  const double h = 1e-6 * diag;
  for (const double p : {2.0, 3.5}) {
    IdwDeformer idw(X, p);
    idw.move_points(0, all_ids(X.size()), Y);
    for (Eigen::Index v = 3; v < mesh.positions().cols(); v += 97) {
      const Eigen::Vector3d x = mesh.positions().col(v) + Eigen::Vector3d(0.011, -0.007, 0.013);
      Eigen::Matrix3d J, fd;
      idw.apply(x, &J);
      for (int a = 0; a < 3; ++a)
        fd.col(a) = (idw.apply(x + h * Eigen::Vector3d::Unit(a), nullptr) - idw.apply(x - h * Eigen::Vector3d::Unit(a), nullptr)) / (2 * h);
      EXPECT_LE((J - fd).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, J.cwiseAbs().maxCoeff())) << "power " << p << " vertex " << v;
    }
  }
}

int run_script(const std::string& dir, const std::string& name, const std::vector<std::string>& steps,
               std::string* err = nullptr) {
  write_file(dir + "/" + name + ".json", script(steps));
  return run_tool("run " + quoted(test::data("bunny.obj")) + " " + quoted(dir + "/" + name + ".json") + " -o " +
                      quoted(dir + "/" + name + ".off") + " --stats " + quoted(dir + "/" + name + ".stats.json") +
                      " --quiet",
                  nullptr, err);
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
