// Ground truth for boundary-constraint modeling with the paper's operator (Botsch &
// Kobbelt eq. 4 and 5): on a small irregular patch whose cotangent weights are partly
// negative (obtuse triangles, non-Delaunay edges), Δ^k = (M⁻¹W)^k is built densely from
// the definition by code that shares nothing with lib/bcm, solved densely with the
// editor's constraints, and compared with the editor for k = 1, 2, 3. The negative
// weights keep the system positive definite; "cotan_positive" drops them.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "bcm/bcm_editor.h"
#include "bcm/cotan_laplacian.h"
#include "bcm_test_util.h"
#include "mesh/build_mesh.h"
#include "test_meshes.h"

namespace ffd {
namespace {

// The one place these tests call the editor: set up on
// `mesh` with `options`, pose handle 0 by x ↦ linear·x + translation, return all
// positions (3 × n) after the update.
Eigen::Matrix3Xd bcm_result(const Mesh& mesh, const std::vector<std::uint32_t>& support,
                            const std::vector<BcmHandle>& handles, const BcmOptions& options,
                            const Eigen::Matrix3d& linear, const Eigen::Vector3d& translation) {
  BcmData data = bcm_precompute(mesh, support, handles, options);
  bcm_set_pose(data, 0, linear, translation);
  Eigen::Matrix3Xd positions = mesh.positions();
  bcm_pose(data, positions);
  return positions;
}

// --- The patch -------------------------------------------------------------------------

constexpr int kSide = 8;  // 8 × 8 vertices, vertex (i, j) is j·kSide + i
std::uint32_t vertex(int i, int j) { return static_cast<std::uint32_t>(j * kSide + i); }

// A sheared, jittered 8 × 8 patch (a topological disk) on a curved height field. Each
// row is shifted by 0.45 of a cell, so every quad is a parallelogram with one long
// diagonal; a third of the quads are split along it, which makes both angles facing it
// obtuse (about 117°) and its weight negative. `planar` keeps z = 0.
PolygonSoup sheared_patch(bool planar = false) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> jitter(-0.08, 0.08);
  PolygonSoup soup;
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      const double x = (i + 0.45 * j + jitter(rng)) / (kSide - 1), y = (0.9 * j + jitter(rng)) / (kSide - 1);
      soup.positions.emplace_back(x, y, planar ? 0.0 : 0.25 * std::sin(2.5 * x) * std::cos(1.7 * y));
    }
  for (int j = 0; j + 1 < kSide; ++j)
    for (int i = 0; i + 1 < kSide; ++i) {
      const std::uint32_t a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
      if ((i + 2 * j) % 3 == 0) {  // the long diagonal a–c: non-Delaunay
        soup.elements.add_polygon({a, b, c});
        soup.elements.add_polygon({a, c, d});
      } else {  // the short one
        soup.elements.add_polygon({a, b, d});
        soup.elements.add_polygon({b, c, d});
      }
    }
  return soup;
}

// The patch's regions: the support is every vertex off the patch's border, the handle the
// 2 × 2 vertices in the middle.
std::vector<std::uint32_t> patch_support() {
  std::vector<std::uint32_t> out;
  for (int j = 1; j + 1 < kSide; ++j)
    for (int i = 1; i + 1 < kSide; ++i) out.push_back(vertex(i, j));
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<BcmHandle> patch_handles() {
  std::vector<std::uint32_t> h = {vertex(3, 3), vertex(4, 3), vertex(3, 4), vertex(4, 4)};
  std::sort(h.begin(), h.end());
  return {{"middle", h}};
}

// --- The definition, densely -----------------------------------------------------------

// Dense W and M of eq. 4 from scratch: W_ij = ½(cot α_ij + cot β_ij), W_ii = −Σ_j W_ij,
// M_ii the mixed Voronoi area (Meyer et al. 2003: the Voronoi share of non-obtuse
// triangles, half an obtuse triangle at its obtuse corner, a quarter at the others).
// `positive` zeroes negative off-diagonal weights. No clamping: the patch has no angle
// near 0° or 180°.
struct DenseLaplacian {
  Eigen::MatrixXd w;
  Eigen::VectorXd area;
  double min_angle_deg = 180, max_angle_deg = 0;
};

DenseLaplacian dense_laplacian(const PolygonSoup& soup, bool positive = false) {
  const std::vector<test::SoupFace> soup_faces = test::soup_faces(soup);
  const Eigen::Index n = static_cast<Eigen::Index>(soup.positions.size());
  DenseLaplacian out{Eigen::MatrixXd::Zero(n, n), Eigen::VectorXd::Zero(n)};
  for (const test::SoupFace& face : soup_faces) {
    const auto& v = face.vertices;
    double angle[3];
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d e1 = soup.positions[v[(c + 1) % 3]] - soup.positions[v[c]];
      const Eigen::Vector3d e2 = soup.positions[v[(c + 2) % 3]] - soup.positions[v[c]];
      angle[c] = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      out.min_angle_deg = std::min(out.min_angle_deg, angle[c] * 180 / M_PI);
      out.max_angle_deg = std::max(out.max_angle_deg, angle[c] * 180 / M_PI);
    }
    const double area =
        0.5 * (soup.positions[v[1]] - soup.positions[v[0]]).cross(soup.positions[v[2]] - soup.positions[v[0]]).norm();
    const bool obtuse = std::max({angle[0], angle[1], angle[2]}) > M_PI / 2;
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t i = v[(c + 1) % 3], j = v[(c + 2) % 3];  // the edge facing corner c
      out.w(i, j) += 0.5 / std::tan(angle[c]);
      out.w(j, i) += 0.5 / std::tan(angle[c]);
      const double squared = (soup.positions[i] - soup.positions[j]).squaredNorm();
      if (!obtuse) {  // the edge ij's share of the Voronoi regions of i and of j
        out.area[i] += squared / std::tan(angle[c]) / 8;
        out.area[j] += squared / std::tan(angle[c]) / 8;
      } else {
        out.area[v[c]] += angle[c] > M_PI / 2 ? area / 2 : area / 4;
      }
    }
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (positive)
      for (Eigen::Index j = 0; j < n; ++j)
        if (i != j) out.w(i, j) = std::max(out.w(i, j), 0.0);
    out.w(i, i) = 0;
    out.w(i, i) = -out.w.row(i).sum();
  }
  return out;
}

// (M⁻¹W)^k by matrix powers.
Eigen::MatrixXd laplacian_power(const DenseLaplacian& lap, int k) {
  const Eigen::MatrixXd delta = lap.area.cwiseInverse().asDiagonal() * lap.w;
  Eigen::MatrixXd power = delta;
  for (int i = 1; i < k; ++i) power = delta * power;
  return power;
}

// Eq. 5 solved densely: rows `free` of Δ^k times p equal zero; every other vertex sits at
// `target` (the handle posed, the rest where it is). Returns all positions, 3 × n.
Eigen::Matrix3Xd dense_solve(const Eigen::MatrixXd& power, const std::vector<std::uint32_t>& free,
                             const Eigen::Matrix3Xd& target) {
  const Eigen::Index n = target.cols(), p = static_cast<Eigen::Index>(free.size());
  std::vector<char> is_free(static_cast<std::size_t>(n), 0);
  for (std::uint32_t v : free) is_free[v] = 1;
  Eigen::MatrixXd a(p, p), rhs = Eigen::MatrixXd::Zero(p, 3);
  for (Eigen::Index r = 0; r < p; ++r) {
    for (Eigen::Index c = 0; c < p; ++c) a(r, c) = power(free[r], free[c]);
    for (Eigen::Index j = 0; j < n; ++j)
      if (!is_free[static_cast<std::size_t>(j)]) rhs.row(r) -= power(free[r], j) * target.col(j).transpose();
  }
  const Eigen::MatrixXd x = a.fullPivLu().solve(rhs);
  Eigen::Matrix3Xd out = target;
  for (Eigen::Index r = 0; r < p; ++r) out.col(free[r]) = x.row(r).transpose();
  return out;
}

// The free vertices: support minus handle.
std::vector<std::uint32_t> free_of(const std::vector<std::uint32_t>& support, const std::vector<BcmHandle>& handles) {
  std::vector<std::uint32_t> out;
  std::set_difference(support.begin(), support.end(), handles[0].vertices.begin(), handles[0].vertices.end(),
                      std::back_inserter(out));
  return out;
}

// A 9-dof pose about the handle's centroid: a 25° turn, an uneven scale and a lift.
test::Pose handle_pose(const Mesh& mesh, const BcmHandle& handle) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (std::uint32_t v : handle.vertices) centre += mesh.positions().col(v) / static_cast<double>(handle.vertices.size());
  test::Pose pose;
  pose.linear = Eigen::AngleAxisd(25 * M_PI / 180, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix() *
                Eigen::Vector3d(1.1, 0.9, 1.2).asDiagonal();
  pose.translation = centre + Eigen::Vector3d(0.05, -0.03, 0.2) - pose.linear * centre;
  return pose;
}

Eigen::Matrix3Xd posed_target(const Mesh& mesh, const BcmHandle& handle, const test::Pose& pose) {
  Eigen::Matrix3Xd target = mesh.positions();
  for (std::uint32_t v : handle.vertices) target.col(v) = pose.linear * target.col(v) + pose.translation;
  return target;
}

BcmOptions options_for(int k, LaplacianKind laplacian) {
  BcmOptions options;
  options.k = k;
  options.detail = false;
  options.laplacian = laplacian;  // continuity: k − 1 by default
  return options;
}

std::vector<Triangle> triangles_of(const PolygonSoup& soup) {
  const std::vector<test::SoupFace> soup_faces = test::soup_faces(soup);
  std::vector<Triangle> out;
  for (const test::SoupFace& f : soup_faces) out.push_back({f.vertices[0], f.vertices[1], f.vertices[2]});
  return out;
}

Eigen::Matrix3Xd positions_of(const PolygonSoup& soup) {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(soup.positions.size()));
  for (std::size_t i = 0; i < soup.positions.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = soup.positions[i];
  return out;
}

// Off-diagonal entries of W below zero.
int negative_offdiagonals(const Eigen::MatrixXd& w) {
  int count = 0;
  for (Eigen::Index i = 0; i < w.rows(); ++i)
    for (Eigen::Index j = 0; j < w.cols(); ++j) count += i != j && w(i, j) < 0;
  return count;
}

// --- Tests -------------------------------------------------------------------------------

TEST(BcmGroundTruth, ThePatchHasObtuseTrianglesAndNegativeCotanWeights) {
  const PolygonSoup soup = sheared_patch();
  const DenseLaplacian reference = dense_laplacian(soup);
  EXPECT_GT(reference.max_angle_deg, 110);
  EXPECT_GT(reference.min_angle_deg, 10);  // far from kMaxCotangent's clamp: the definition applies as is
  EXPECT_GE(negative_offdiagonals(reference.w), 2 * 10);  // 10+ edges, each twice

  // lib/bcm's operator is the same matrix, negative weights included.
  const Laplacian lap = cotan_laplacian(positions_of(soup), triangles_of(soup));
  const Eigen::MatrixXd w(lap.weights);
  EXPECT_EQ(negative_offdiagonals(w), negative_offdiagonals(reference.w));
  EXPECT_LT((w - reference.w).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((lap.areas - reference.area).cwiseAbs().maxCoeff(), 1e-15);
  double smallest = 0;
  for (Eigen::Index i = 0; i < w.rows(); ++i)
    for (Eigen::Index j = 0; j < w.cols(); ++j)
      if (i != j) smallest = std::min(smallest, w(i, j));
  EXPECT_LT(smallest, -0.3);  // about cot 117° = −0.5 on the long diagonals
}

// Eq. 5 for k = 1, 2, 3 with C^(k−1) boundaries: the editor equals the dense solve of the
// definition, and its result solves Δ^k p = 0 on the free rows.
TEST(BcmGroundTruth, EditorEqualsTheDenseDefinitionForEveryOrder) {
  const PolygonSoup soup = sheared_patch();
  const Mesh mesh = build_mesh(soup, "patch");
  const auto support = patch_support();
  const auto handles = patch_handles();
  const auto free = free_of(support, handles);
  const test::Pose pose = handle_pose(mesh, handles[0]);
  const Eigen::Matrix3Xd target = posed_target(mesh, handles[0], pose);
  const DenseLaplacian lap = dense_laplacian(soup);
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    const Eigen::MatrixXd power = laplacian_power(lap, k);
    const Eigen::Matrix3Xd expected = dense_solve(power, free, target);
    Eigen::Matrix3Xd ours;
    // Positive definite despite the negative weights: setup (a Cholesky factorization of
    // the free block) succeeds.
    ASSERT_NO_THROW(ours = bcm_result(mesh, support, handles, options_for(k, LaplacianKind::Cotan), pose.linear,
                                      pose.translation));
    EXPECT_LT((ours - expected).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_GT((ours - mesh.positions()).cwiseAbs().maxCoeff(), 0.05);  // a real edit

    // The residual of Δ^k p on the free rows, against ‖Δ^k‖∞·‖p‖∞.
    const Eigen::MatrixXd applied = power * ours.transpose();
    double residual = 0;
    for (std::uint32_t v : free) residual = std::max(residual, applied.row(v).cwiseAbs().maxCoeff());
    const double scale = power.cwiseAbs().rowwise().sum().maxCoeff() * ours.cwiseAbs().maxCoeff();
    EXPECT_LE(residual, 1e-10 * scale) << residual << " against " << scale;

    // The symmetric form (−1)^k M Δ^k on the free block is positive definite.
    const Eigen::MatrixXd scaled = (k % 2 ? -1.0 : 1.0) * (lap.area.asDiagonal() * power);
    Eigen::MatrixXd block(free.size(), free.size());
    for (std::size_t r = 0; r < free.size(); ++r)
      for (std::size_t c = 0; c < free.size(); ++c) block(r, c) = scaled(free[r], free[c]);
    EXPECT_LT((block - block.transpose()).cwiseAbs().maxCoeff(), 1e-9 * block.cwiseAbs().maxCoeff());
    const Eigen::VectorXd eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(block).eigenvalues();
    EXPECT_GT(eigenvalues.minCoeff(), 0) << "smallest eigenvalue " << eigenvalues.minCoeff();
  }
}

// "cotan_positive": no negative off-diagonal entry on the same patch, a different operator
// there, and the editor with it equals the dense definition with negative weights zeroed.
TEST(BcmGroundTruth, PositiveWeightsDropTheNegativeOnesAndTheEditorFollows) {
  const PolygonSoup soup = sheared_patch();
  const Laplacian standard = cotan_laplacian(positions_of(soup), triangles_of(soup));
  const Laplacian positive = cotan_laplacian(positions_of(soup), triangles_of(soup), CotanWeights::Positive);
  const Eigen::MatrixXd w(positive.weights);
  EXPECT_EQ(negative_offdiagonals(w), 0);
  EXPECT_GT((w - Eigen::MatrixXd(standard.weights)).cwiseAbs().maxCoeff(), 0.3);
  EXPECT_LT((w * Eigen::VectorXd::Ones(w.cols())).cwiseAbs().maxCoeff(), 1e-14);  // rows sum to zero
  EXPECT_TRUE(positive.areas == standard.areas);
  EXPECT_LT((w - dense_laplacian(soup, true).w).cwiseAbs().maxCoeff(), 1e-13);

  const Mesh mesh = build_mesh(soup, "patch");
  const auto support = patch_support();
  const auto handles = patch_handles();
  const test::Pose pose = handle_pose(mesh, handles[0]);
  const Eigen::Matrix3Xd target = posed_target(mesh, handles[0], pose);
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    const Eigen::Matrix3Xd expected =
        dense_solve(laplacian_power(dense_laplacian(soup, true), k), free_of(support, handles), target);
    const Eigen::Matrix3Xd ours =
        bcm_result(mesh, support, handles, options_for(k, LaplacianKind::CotanPositive), pose.linear, pose.translation);
    EXPECT_LT((ours - expected).cwiseAbs().maxCoeff(), 1e-10);
    const Eigen::Matrix3Xd paper =
        bcm_result(mesh, support, handles, options_for(k, LaplacianKind::Cotan), pose.linear, pose.translation);
    EXPECT_GT((ours - paper).cwiseAbs().maxCoeff(), 1e-4);
  }
}

// Linear precision, the property the negative weights pay for: on a planar triangulation
// Σ_j W_ij (p_j − p_i) = 0 at every interior vertex with the standard weights, Delaunay or
// not; zeroing the negative weights breaks it at the non-Delaunay edges.
TEST(BcmGroundTruth, StandardWeightsHaveLinearPrecisionOnANonDelaunayPlane) {
  const PolygonSoup soup = sheared_patch(true);
  const Eigen::Matrix3Xd p = positions_of(soup);
  const Eigen::MatrixXd standard =
      Eigen::MatrixXd(cotan_laplacian(p, triangles_of(soup)).weights) * p.transpose();
  const Eigen::MatrixXd positive =
      Eigen::MatrixXd(cotan_laplacian(p, triangles_of(soup), CotanWeights::Positive).weights) * p.transpose();
  double standard_worst = 0, positive_worst = 0;
  for (std::uint32_t v : patch_support()) {
    standard_worst = std::max(standard_worst, standard.row(v).norm());
    positive_worst = std::max(positive_worst, positive.row(v).norm());
  }
  EXPECT_LT(standard_worst, 1e-14);
  EXPECT_GT(positive_worst, 1e-2);
}

// The script: "laplacian": "cotan_positive" validates, runs, says so in its stats, and
// moves the patch differently from "cotan".
TEST(BcmGroundTruth, CotanPositiveFromAScript) {
  const std::string dir = test::temp_folder("bcm_cotan_positive");
  const PolygonSoup soup = sheared_patch();
  const std::vector<test::SoupFace> soup_faces = test::soup_faces(soup);
  std::string obj;
  for (const Eigen::Vector3d& q : soup.positions)
    obj += "v " + std::to_string(q.x()) + " " + std::to_string(q.y()) + " " + std::to_string(q.z()) + "\n";
  for (const test::SoupFace& f : soup_faces)
    obj += "f " + std::to_string(f.vertices[0] + 1) + " " + std::to_string(f.vertices[1] + 1) + " " +
           std::to_string(f.vertices[2] + 1) + "\n";
  test::write_file(dir + "/patch.obj", obj);
  const auto script = [](const std::string& laplacian) {
    nlohmann::json bcm = {{"op", "bcm"}, {"name", "e"}, {"k", 2}, {"detail", false}, {"laplacian", laplacian}};
    bcm["support"] = {{"indices", patch_support()}};
    bcm["handles"] = {{{"name", "h"}, {"select", {{"indices", patch_handles()[0].vertices}}}}};
    const nlohmann::json lift = {{"op", "transform"}, {"editor", "e"}, {"transform", {{"translate", {0, 0, 0.3}}}}};
    return nlohmann::json{{"version", 1}, {"steps", {bcm, lift}}}.dump();
  };
  for (const char* laplacian : {"cotan_positive", "cotan"}) {
    test::write_file(dir + "/" + laplacian + ".json", script(laplacian));
    std::string out, err;
    ASSERT_EQ(test::run_tool("validate --resolved " + test::quoted(dir + "/" + laplacian + ".json"), &out, &err), 0) << err;
    EXPECT_EQ(nlohmann::json::parse(out)["steps"][0]["laplacian"], laplacian);
    ASSERT_EQ(test::run_tool("run " + test::quoted(dir + "/patch.obj") + " " + test::quoted(dir + "/" + laplacian + ".json") +
                                 " -o " + test::quoted(dir + "/" + laplacian + ".obj") + " --stats " +
                                 test::quoted(dir + "/" + laplacian + "_stats.json") + " --quiet",
                             nullptr, &err),
              0)
        << err;
    const nlohmann::json stats = nlohmann::json::parse(test::read_file(dir + "/" + laplacian + "_stats.json"));
    EXPECT_EQ(stats["steps"][0]["laplacian"], laplacian);
    EXPECT_EQ(stats["steps"][0]["solver"], "supernodal Cholesky");
  }
  std::string cmp;
  EXPECT_NE(test::run_tool("compare " + test::quoted(dir + "/cotan_positive.obj") + " " + test::quoted(dir + "/cotan.obj") +
                               " --tolerance 1e-6",
                           &cmp),
            0)
      << cmp;
}

}  // namespace
}  // namespace ffd
