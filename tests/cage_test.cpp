// Cage deformers (warp/cage_deformer.h, warp/mean_value.h): mean value coordinates against
// an independent implementation written here (Ju, Schaefer and Warren's mean vector form,
// m = 1/2 sum theta_i n_i and lambda_i = n_i.m / n_i.v_i, not the paper's robust
// pseudocode the library follows), for a box cage and a non-convex cage; the exact limits
// on a face, an edge and a vertex against barycentric coordinates; linear precision inside
// and outside; Jacobians against central differences; and the cage op through the CLI.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "test_meshes.h"
#include "warp/cage_deformer.h"

namespace ffd {
namespace {

using test::all_ids;
using test::expect_one_error_line;
using test::quoted;
using test::read_file;
using test::run_script;
using test::run_tool;
using test::temp_folder;
using test::write_file;

struct Cage {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<std::uint32_t>> faces;
};

/// The box [0, 2] x [0, 1] x [0, 1.5] as 8 vertices and 6 outward quads.
Cage box_cage() {
  Cage c;
  for (int i = 0; i < 8; ++i) c.points.emplace_back(2.0 * (i & 1), 1.0 * ((i >> 1) & 1), 1.5 * ((i >> 2) & 1));
  c.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return c;
}

/// The box with its top dented: four triangles to a centre pushed below the top.
Cage dented_cage() {
  Cage c = box_cage();
  c.points.emplace_back(1.0, 0.5, 0.6);
  c.faces[1] = {8, 4, 5};
  c.faces.push_back({8, 5, 7});
  c.faces.push_back({8, 7, 6});
  c.faces.push_back({8, 6, 4});
  return c;
}

MeanValueCage triangles_of(const Cage& c) {
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(c.points.size()));
  for (std::size_t i = 0; i < c.points.size(); ++i) points.col(static_cast<Eigen::Index>(i)) = c.points[i];
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (const auto& f : c.faces)
    for (std::size_t i = 1; i + 1 < f.size(); ++i) triangles.push_back({f[0], f[i], f[i + 1]});
  return mean_value_cage(points, triangles);
}

/// Mean value coordinates by the mean vector of each spherical triangle (x off the cage).
Eigen::VectorXd reference_coordinates(const MeanValueCage& cage, const Eigen::Vector3d& x) {
  Eigen::VectorXd w = Eigen::VectorXd::Zero(cage.points.cols());
  for (const auto& t : cage.triangles) {
    Eigen::Vector3d v[3], n[3];
    double d[3], theta[3];
    for (int i = 0; i < 3; ++i) {
      d[i] = (cage.points.col(t[i]) - x).norm();
      v[i] = (cage.points.col(t[i]) - x) / d[i];
    }
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d &a = v[(i + 1) % 3], &b = v[(i + 2) % 3];
      theta[i] = std::atan2(a.cross(b).norm(), a.dot(b));
      n[i] = a.cross(b).normalized();
      m += 0.5 * theta[i] * n[i];
    }
    for (int i = 0; i < 3; ++i) w[t[i]] += n[i].dot(m) / n[i].dot(v[i]) / d[i];
  }
  return w / w.sum();
}

double max_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).cwiseAbs().maxCoeff(); }

TEST(MeanValue, EqualsTheMeanVectorFormInsideAndOutsideBoxAndDentedCages) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (const Cage& c : {box_cage(), dented_cage()}) {
    const MeanValueCage cage = triangles_of(c);
    for (int k = 0; k < 200; ++k) {
      // Drawn one statement each, z first (the order gcc gave the arguments when this
      // was one call), so that every compiler tests the same points.
      const double z = 1.5 * u(rng), y = u(rng), x0 = 2 * u(rng);
      const Eigen::Vector3d x(x0, y, z);
      Eigen::VectorXd w;
      mean_value_coordinates(cage, x, w);
      EXPECT_LE(max_difference(w, reference_coordinates(cage, x)), 1e-10) << "at " << x.transpose();
      EXPECT_LE((cage.points * w - x).norm(), 1e-10) << "linear precision at " << x.transpose();
    }
  }
}

TEST(MeanValue, TheLimitsOnAFaceAnEdgeAndAVertexAreBarycentric) {
  const MeanValueCage cage = triangles_of(dented_cage());
  Eigen::VectorXd w, expected = Eigen::VectorXd::Zero(cage.points.cols());
  // On the bottom quad's triangle (0, 2, 3): 0.2, 0.3, 0.5.
  const Eigen::Vector3d on_face = 0.2 * cage.points.col(0) + 0.3 * cage.points.col(2) + 0.5 * cage.points.col(3);
  mean_value_coordinates(cage, on_face, w);
  expected[0] = 0.2, expected[2] = 0.3, expected[3] = 0.5;
  EXPECT_LE(max_difference(w, expected), 1e-10);
  // On a dent triangle (8, 4, 5), off the plane of the box.
  const Eigen::Vector3d on_dent = 0.6 * cage.points.col(8) + 0.1 * cage.points.col(4) + 0.3 * cage.points.col(5);
  mean_value_coordinates(cage, on_dent, w);
  expected.setZero();
  expected[8] = 0.6, expected[4] = 0.1, expected[5] = 0.3;
  EXPECT_LE(max_difference(w, expected), 1e-10);
  // On the edge 1-5, a quarter of the way.
  mean_value_coordinates(cage, 0.75 * cage.points.col(1) + 0.25 * cage.points.col(5), w);
  expected.setZero();
  expected[1] = 0.75, expected[5] = 0.25;
  EXPECT_LE(max_difference(w, expected), 1e-10);
  // On vertex 6.
  mean_value_coordinates(cage, cage.points.col(6), w);
  expected.setZero();
  expected[6] = 1;
  EXPECT_EQ(w, expected);
}

TEST(MeanValue, TheWindingNumberTellsInsideFromOutside) {
  const MeanValueCage cage = triangles_of(dented_cage());
  Eigen::VectorXd w;
  for (const auto& [x, expected] : std::vector<std::pair<Eigen::Vector3d, double>>{
           {{1.0, 0.5, 0.3}, 1.0}, {{1.0, 0.5, 0.9}, 0.0} /* above the dent, under the box's top */, {{3.0, 0.5, 0.3}, 0.0}}) {
    EXPECT_NEAR(winding_number(cage, x), expected, 1e-12) << x.transpose();
    double winding = -1;
    mean_value_coordinates(cage, x, w, nullptr, &winding);
    EXPECT_NEAR(winding, expected, 1e-12) << "with the coordinates, at " << x.transpose();
  }
}

TEST(Cage, AnAffinePoseIsThatAffineMapAndNoPoseIsTheIdentity) {
  const Cage c = dented_cage();
  CageDeformer cage(c.points, c.faces);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  std::vector<Eigen::Vector3d> xs;
  for (int k = 0; k < 100; ++k) xs.emplace_back(2 * u(rng), u(rng), 1.5 * u(rng));
  for (const Eigen::Vector3d& x : xs) ASSERT_EQ(cage.apply(x, nullptr), x) << "unmoved, bit for bit";
  Eigen::Matrix3d A;
  A << 1.1, 0.2, 0, -0.1, 0.9, 0.05, 0.02, 0, 1.2;
  const Eigen::Vector3d b(0.3, -0.2, 0.5);
  std::vector<Eigen::Vector3d> posed;
  for (const Eigen::Vector3d& p : c.points) posed.push_back(A * p + b);
  cage.move_points(0, all_ids(c.points.size()), posed);
  for (const Eigen::Vector3d& x : xs) EXPECT_LE((cage.apply(x, nullptr) - (A * x + b)).norm(), 1e-12);
  for (std::size_t j = 0; j < c.points.size(); ++j) EXPECT_LE((cage.apply(c.points[j], nullptr) - posed[j]).norm(), 1e-15);
  cage.move_points(0, all_ids(c.points.size()), c.points);
  EXPECT_EQ(cage.apply(xs[5], nullptr), xs[5]) << "back at rest: the identity again";
}

TEST(Cage, JacobiansMatchCentralDifferencesInsideAndOutside) {
  const Cage c = dented_cage();
  CageDeformer cage(c.points, c.faces);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-0.2, 0.2), v(-0.5, 1.5);
  std::vector<Eigen::Vector3d> posed;
  for (const Eigen::Vector3d& p : c.points) posed.push_back(p + Eigen::Vector3d(u(rng), u(rng), u(rng)));
  cage.move_points(0, all_ids(c.points.size()), posed);
  const double h = 1e-6;
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector3d x(2 * v(rng), v(rng), 1.5 * v(rng));
    Eigen::Matrix3d J;
    cage.apply(x, &J);
    const Eigen::Matrix3d fd = test::central_jacobian(cage, x, h);
    EXPECT_LE((J - fd).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, J.cwiseAbs().maxCoeff())) << "at " << x.transpose();
  }
}

TEST(Cage, BoundPointsGiveTheFreshEvaluationsPositions) {
  const Cage c = box_cage();
  CageDeformer cage(c.points, c.faces);
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 50).cwiseAbs();
  Eigen::Matrix3Xd n = Eigen::Matrix3Xd::Zero(3, 50);
  n.row(2).setOnes();
  std::size_t outside = 0;
  ASSERT_EQ(cage.bind(x, true, 1 << 20, outside), CageDeformer::Binding::WeightsAndGradients);
  EXPECT_EQ(outside, 0u);
  cage.move_points(0, {3, 6}, {c.points[3] + Eigen::Vector3d(0.3, 0.1, 0), c.points[6] - Eigen::Vector3d(0, 0.2, 0.1)});
  std::vector<std::uint32_t> ids(50);
  for (std::uint32_t i = 0; i < 50; ++i) ids[i] = i;
  Eigen::Matrix3Xd pos(3, 50), nrm(3, 50);
  WarpCounts counts;
  x.col(7) += Eigen::Vector3d(0.01, 0, 0);  // moved since binding: evaluated afresh
  cage.apply(x, n, ids, pos, nrm, counts);
  for (Eigen::Index i = 0; i < 50; ++i) {
    Eigen::Matrix3d J;
    EXPECT_EQ(pos.col(i), cage.apply(Eigen::Vector3d(x.col(i)), &J)) << i;
    EXPECT_LE((nrm.col(i) - transformed_normal(J, n.col(i))).norm(), 1e-6) << i;  // single-precision gradients
  }
}

/// OBJ text of the bunny's bounding box grown by `pad` on each side, as a quad cage.
std::string bunny_cage_obj(double pad) {
  const Mesh bunny = test::bunny();
  const Eigen::Vector3d lo = bunny.positions().rowwise().minCoeff().array() - pad;
  const Eigen::Vector3d hi = bunny.positions().rowwise().maxCoeff().array() + pad;
  std::string obj;
  for (int i = 0; i < 8; ++i) {
    char line[128];
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", (i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1],
                  (i & 4) ? hi[2] : lo[2]);
    obj += line;
  }
  return obj + "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
}

// A cage pose by index and the same pose from a posed cage's file give one mesh; save
// writes the posed cage with its faces; remesh after a cage move; a cage after a lattice.
TEST(CageCli, MovesByIndexOrFileSaveTheCageRemeshAndStack) {
  const std::string dir = temp_folder("cage_cli"), bunny = test::data("bunny.obj");
  write_file(dir + "/cage.obj", bunny_cage_obj(0.5));
  const std::string cage = R"({"op": "cage", "name": "C", "cage": "cage.obj", "coordinates": "mean_value"})";
  const std::string move = R"({"op": "move", "lattice": "C", "points": [{"index": 7, "by": [0.5, 0.5, -0.3]}]})";
  ASSERT_EQ(run_script(dir, "a", {cage, move, R"({"op": "save", "lattice": "C", "path": "posed.obj"})"}), 0);
  ASSERT_EQ(run_script(dir, "b", {cage, R"({"op": "move", "lattice": "C", "positions": {"file": "posed.obj"}})"}), 0);
  EXPECT_EQ(run_tool("compare " + quoted(dir + "/a.off") + " " + quoted(dir + "/b.off") + " --tolerance 1e-12"), 0);
  const std::string posed = read_file(dir + "/posed.obj");
  EXPECT_NE(posed.find("\nf 1 3 4 2\n"), std::string::npos) << posed;
  const nlohmann::json stats = nlohmann::json::parse(read_file(dir + "/a.stats.json"));
  EXPECT_EQ(stats["steps"][0]["vertices_outside"], 0);
  EXPECT_EQ(stats["steps"][0]["binding"], "weights and gradients");
  EXPECT_EQ(run_tool("compare " + quoted(dir + "/a.off") + " " + quoted(bunny) + " --tolerance 1e-3"), 1)
      << "the pose moved the bunny";
  ASSERT_EQ(run_script(dir, "c", {R"({"op": "lattice", "name": "L", "basis": "bspline", "box": {"fit": "aabb", "padding": 0.05}, "cells": [4, 4, 4]})",
                                  R"({"op": "move", "lattice": "L", "points": [{"index": [2, 2, 2], "by": [0, 0, 0.4]}]})",
                                  cage, move, R"({"op": "remesh"})"}),
            0);
  const nlohmann::json remeshed = nlohmann::json::parse(read_file(dir + "/c.stats.json"));
  EXPECT_EQ(remeshed["steps"][2]["vertices_outside"], 0);
}

TEST(CageCli, InputErrorsNameTheirPlace) {
  const std::string dir = temp_folder("cage_cli_errors");
  std::string err;
  write_file(dir + "/open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n");
  EXPECT_EQ(run_script(dir, "open", {R"({"op": "cage", "name": "C", "cage": "open.obj"})"}, &err), 2);
  expect_one_error_line(err, {"open.json: /steps/0/cage", "cage edge 0-2 of face 0 has no face on its other side"});
  write_file(dir + "/flipped.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 3 4\n");
  EXPECT_EQ(run_script(dir, "flipped", {R"({"op": "cage", "name": "C", "cage": "flipped.obj"})"}, &err), 2);
  expect_one_error_line(err, {"flipped.json: /steps/0/cage", "cage edge 0-2 is used in the same direction by faces 0 and 3"});
  write_file(dir + "/flat.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 4 3 2\n");
  EXPECT_EQ(run_script(dir, "flat", {R"({"op": "cage", "name": "C", "cage": "flat.obj"})"}, &err), 2);
  expect_one_error_line(err, {"flat.json: /steps/0/cage", "the cage encloses no volume"});
  write_file(dir + "/cage.obj", bunny_cage_obj(0.5));
  write_file(dir + "/three.txt", "0 0 0\n1 1 1\n2 2 2\n");
  EXPECT_EQ(run_script(dir, "count", {R"({"op": "cage", "name": "C", "cage": "cage.obj"})",
                                      R"({"op": "move", "lattice": "C", "positions": {"file": "three.txt"}})"},
                       &err),
            2);
  expect_one_error_line(err, {"count.json: /steps/1/positions", "has 3 points", "has 8"});
  EXPECT_EQ(run_script(dir, "index", {R"({"op": "cage", "name": "C", "cage": "cage.obj"})",
                                      R"({"op": "move", "lattice": "C", "points": [{"index": 8, "by": [1, 0, 0]}]})"},
                       &err),
            2);
  expect_one_error_line(err, {"index.json: /steps/1/points/0/index", "(movable: cage vertices 0 to 7)"});
  EXPECT_EQ(run_script(dir, "missing", {R"({"op": "cage", "name": "C", "cage": "nowhere.obj"})"}, &err), 2);
  expect_one_error_line(err, {"missing.json: /steps/0/cage", "nowhere.obj"});
  EXPECT_FALSE(std::filesystem::exists(dir + "/open.off"));
}

TEST(CageCli, VerticesOutsideAreCountedAndWarned) {
  const std::string dir = temp_folder("cage_cli_outside");
  write_file(dir + "/cage.obj", bunny_cage_obj(-1.0));  // smaller than the bunny
  ASSERT_EQ(run_script(dir, "small", {R"({"op": "cage", "name": "C", "cage": "cage.obj"})"}), 0);
  const nlohmann::json stats = nlohmann::json::parse(read_file(dir + "/small.stats.json"));
  EXPECT_GT(stats["steps"][0]["vertices_outside"].get<int>(), 0);
  ASSERT_EQ(stats["warnings"].size(), 1u);
  EXPECT_NE(stats["warnings"][0].get<std::string>().find("vertices lie outside cage 'C'"), std::string::npos);
}

// RBF (dense and compact), IDW and a cage in one stack: the same bytes and counts on one
// thread and on two (each vertex is evaluated on its own; the binding's order is fixed).
TEST(ScatteredKinds, TheSameBytesAtOneAndTwoThreads) {
  const std::string dir = temp_folder("scattered_threads");
  write_file(dir + "/cage.obj", bunny_cage_obj(0.5));
  const std::string points = R"("points": {"select": {"indices": [0, 200, 400, 600, 800, 1000, 1200, 1400, 1600, 1800]}})";
  write_file(dir + "/s.json",
             test::script({R"({"op": "rbf", "name": "R", "kernel": "thin_plate_spline", "radius": 2, )" + points + "}",
                           R"({"op": "move", "lattice": "R", "points": [{"index": 3, "by": [0.3, 0, 0]}]})",
                           R"({"op": "rbf", "name": "W", "kernel": "beckert_wendland_c2_basis", "radius": 9, )" + points + "}",
                           R"({"op": "move", "lattice": "W", "points": [{"index": 5, "by": [0, 0.3, 0]}]})",
                           R"({"op": "idw", "name": "I", "power": 2.5, )" + points + "}",
                           R"({"op": "move", "lattice": "I", "points": [{"index": 7, "by": [0, 0, 0.3]}]})",
                           R"({"op": "cage", "name": "C", "cage": "cage.obj"})",
                           R"({"op": "move", "lattice": "C", "points": [{"index": 6, "by": [0.4, 0.2, 0]}]})"}));
  std::string outputs[2];
  nlohmann::json stats[2];
  for (int t = 1; t <= 2; ++t) {
    const std::string out = dir + "/t" + std::to_string(t);
    ASSERT_EQ(run_tool("run " + quoted(test::data("bunny.obj")) + " " + quoted(dir + "/s.json") + " -o " +
                       quoted(out + ".ply") + " --stats " + quoted(out + ".json") + " --quiet --threads " +
                       std::to_string(t)),
              0);
    outputs[t - 1] = read_file(out + ".ply");
    stats[t - 1] = test::without_measurements(nlohmann::json::parse(read_file(out + ".json")));
  }
  EXPECT_FALSE(outputs[0].empty());
  EXPECT_EQ(outputs[0], outputs[1]);
  stats[0].erase("threads"), stats[1].erase("threads");
  EXPECT_EQ(stats[0]["steps"], stats[1]["steps"]);
}

}  // namespace
}  // namespace ffd
