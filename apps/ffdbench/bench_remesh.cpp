// Adaptive refinement and decimation (Gain & Dodgson section 4): quality against the true
// deformed surface, speed, and the memory the level bookkeeping costs.
//
// Quality: the true deformed surface is the same warp applied to a dense uniform midpoint
// subdivision of the rest mesh (midpoints stay on the rest mesh's flat triangles, so this
// samples F(rest surface) as densely as we like). Each candidate is compared with it by
// the two-sided Hausdorff distance and the mean vertex-to-surface distance:
//   (a) no refinement: the warp applied to the input mesh;
//   (b) uniform: midpoint subdivision of the rest mesh, as many times as it takes to reach
//       at least the adaptive face count, then the warp;
//   (c) adaptive: the warp and one remesh step with the default thresholds.
// Target: at equal (or larger, for uniform) face count, Hausdorff(c) <= 0.5 Hausdorff(b).
// Distances are measured between dense samples and surfaces with CGAL's AABB tree: from
// every vertex, edge midpoint and face centroid of one mesh to the other surface, both
// ways (the truth's samples are 4x denser per level than the finest candidate).
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <cstdio>
#include <map>
#include <memory>

#include "bench.h"
#include "common/timer.h"
#include "mesh/build_mesh.h"
#include "mesh/halfedge_view_cgal.h"
#include "mesh/mesh_info.h"
#include "remesh/adaptive_remesher.h"
#include "warp/bspline_lattice.h"
#include "warp/warp_stack.h"

namespace ffd::bench {
namespace {

using json = nlohmann::ordered_json;

// Splits every triangle into four at its rest-space edge midpoints (rest positions become
// the new mesh's positions: the warp is applied afterwards).
Mesh midpoint_subdivision(const Mesh& mesh) {
  PolygonSoup soup;
  const auto rest = mesh.rest_positions();
  for (Eigen::Index v = 0; v < rest.cols(); ++v) soup.positions.push_back(rest.col(v));
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
  const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::minmax(a, b);
    auto [it, inserted] = mid.try_emplace(key, 0);
    if (inserted) {
      soup.positions.push_back(0.5 * (soup.positions[a] + soup.positions[b]));
      it->second = static_cast<std::uint32_t>(soup.positions.size() - 1);
    }
    return it->second;
  };
  for (const auto& f : mesh.faces()) {
    const std::uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
    soup.elements.add_polygon({f[0], ab, ca});
    soup.elements.add_polygon({f[1], bc, ab});
    soup.elements.add_polygon({f[2], ca, bc});
    soup.elements.add_polygon({ab, bc, ca});
  }
  return build_mesh(std::move(soup), "subdivision");
}

// A deformation: lattice over the mesh's padded box, then point moves.
struct Deformation {
  std::string name;
  void (*apply)(BSplineLattice&);
};

// Extrude: the movable points in the upper-front quarter push out along +z.
void extrude(BSplineLattice& l) {
  for (std::size_t f = 0; f < l.num_points(); ++f) {
    const Index3 ijk = l.index(f);
    if (!l.movable(ijk) || ijk[1] < 4 || ijk[2] < 4) continue;
    l.move_point(ijk, l.point(ijk) + Eigen::Vector3d(0, 0, 0.18 * l.box().extents()[2]));
  }
}

// Twist: each layer along y turns about the box's vertical axis by up to 40 degrees.
void twist(BSplineLattice& l) {
  const Eigen::Vector3d centre = l.box().to_world(Eigen::Vector3d(0.5, 0.5, 0.5));
  int lo, hi;
  l.movable_span(1, lo, hi);
  for (std::size_t f = 0; f < l.num_points(); ++f) {
    const Index3 ijk = l.index(f);
    if (!l.movable(ijk)) continue;
    const double t = hi > lo ? double(ijk[1] - lo) / (hi - lo) : 1.0;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(t * 40 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d p = l.point(ijk);
    l.move_point(ijk, centre + R * (p - centre));
  }
}

// Puts `mesh` under a fresh 8×8×8 cubic lattice with `deform` applied; returns the stack.
std::unique_ptr<WarpStack> deform(Mesh& mesh, const Parallelepiped& box, const Deformation& d) {
  auto stack = std::make_unique<WarpStack>();
  auto owned = std::make_unique<BSplineLattice>(box, Index3{8, 8, 8}, 3);
  BSplineLattice* lattice = owned.get();
  stack->push(mesh, "l", std::move(owned));
  d.apply(*lattice);
  stack->update(mesh, "l");
  return stack;
}

// Distances from dense samples of one mesh to another's surface (CGAL AABB tree).
class SurfaceDistance {
public:
  explicit SurfaceDistance(const Mesh& surface)
      : sm_(surface_mesh(surface)), tree_(faces(sm_).first, faces(sm_).second, sm_) {
    tree_.accelerate_distance_queries();
  }
  // Largest and mean distance of `from`'s vertices (and, with `dense`, its edge midpoints
  // and face centroids) to the surface.
  std::pair<double, double> from(const Mesh& from, bool dense) const {
    const SurfaceMesh sm = surface_mesh(from);
    double worst = 0, sum = 0;
    std::size_t n = 0;
    const auto sample = [&](const Point3& p) {
      const double d = std::sqrt(tree_.squared_distance(p));
      worst = std::max(worst, d);
      sum += d;
      ++n;
    };
    for (VertexIndex v : sm.vertices()) sample(sm.point(v));
    if (dense) {
      for (EdgeIndex e : sm.edges()) sample(CGAL::midpoint(sm.point(sm.vertex(e, 0)), sm.point(sm.vertex(e, 1))));
      for (FaceIndex f : sm.faces()) {
        const HalfedgeIndex h = sm.halfedge(f);
        sample(CGAL::centroid(sm.point(sm.source(h)), sm.point(sm.target(h)), sm.point(sm.target(sm.next(h)))));
      }
    }
    return {worst, sum / std::max<std::size_t>(n, 1)};
  }

private:
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  const SurfaceMesh sm_;
  Tree tree_;
};

// Two-sided Hausdorff and mean distance between a candidate and the truth: candidate
// samples (vertices, edge midpoints, centroids) to the true surface, and the truth's
// vertices (a denser sampling of it) to the candidate.
json error_row(const std::string& method, const Mesh& candidate, const Mesh& truth,
               const SurfaceDistance& to_truth, double diag) {
  const auto [a, mean_a] = to_truth.from(candidate, true);
  const auto [b, mean_b] = SurfaceDistance(candidate).from(truth, false);
  const double hausdorff = std::max(a, b);
  return {{"method", method}, {"faces", candidate.num_faces()}, {"hausdorff", hausdorff},
          {"mean", 0.5 * (mean_a + mean_b)}, {"hausdorff_rel_diag", hausdorff / diag}};
}

// One mesh under one deformation: what every candidate of quality() is measured with.
struct QualityCase {
  const Mesh& input;
  const Parallelepiped& box;
  double diag;
  const Deformation& deformation;
  const Mesh& truth;
  const SurfaceDistance& to_truth;
};

using UniformPoint = std::pair<std::size_t, double>;                  // (faces, Hausdorff)
using AdaptivePoint = std::tuple<std::string, std::size_t, double>;  // (label, faces, Hausdorff)

// The candidates without adaptive refinement: the warp on the input ("none"), then on each
// uniform subdivision below the truth's level; the uniform ones' points go to `points`.
void fixed_rows(const QualityCase& c, const std::vector<Mesh>& uniform, int truth_level, json& methods,
                std::vector<UniformPoint>& points) {
  Mesh none = c.input.clone();
  deform(none, c.box, c.deformation);
  methods.push_back(error_row("none", none, c.truth, c.to_truth, c.diag));
  for (int level = 1; level < truth_level; ++level) {
    Mesh u = uniform[level].clone();
    deform(u, c.box, c.deformation);
    methods.push_back(error_row("uniform x" + std::to_string(level), u, c.truth, c.to_truth, c.diag));
    points.emplace_back(u.num_faces(), methods.back()["hausdorff"].get<double>());
  }
}

// The warp and one remesh step with `options` on the input: its error row, with the
// step's counts, goes to `methods` and its point to `points`.
void adaptive_row(const QualityCase& c, const RemeshOptions& options, const std::string& label, json& methods,
                  std::vector<AdaptivePoint>& points) {
  Mesh a = c.input.clone();
  auto stack = deform(a, c.box, c.deformation);
  HalfedgeCache cache;
  const RemeshStats stats = adaptive_remesh(a, cache, *stack, options);
  methods.push_back(error_row(label, a, c.truth, c.to_truth, c.diag));
  methods.back()["refinements"] = stats.refinements;
  methods.back()["max_level_hits"] = stats.max_level_hits;
  points.emplace_back(label, a.num_faces(), methods.back()["hausdorff"].get<double>());
}

// Both triggers over angle thresholds swept to compare at equal face counts (θmin = 0.75 θmax).
void angle_sweep(const QualityCase& c, json& methods, std::vector<AdaptivePoint>& points) {
  const std::vector<double> thetas = {25.7, 15, 10, 6, 4};
  for (RemeshTrigger trigger : {RemeshTrigger::Normal, RemeshTrigger::Midpoint})
    for (double theta : thetas) {
      RemeshOptions options;
      options.theta_max_deg = theta;
      options.theta_min_deg = 0.75 * theta;
      options.trigger = trigger;
      char label[64];
      std::snprintf(label, sizeof label, "adaptive %s %.3g deg", trigger == RemeshTrigger::Normal ? "normal" : "midpoint",
                    theta);
      adaptive_row(c, options, label, methods, points);
    }
}

// The midpoint trigger with absolute distance tolerances (fractions of the diagonal),
// splitting the triggered edge (the paper) and the longest edge first: the first
// builds sliver fans under uneven stretch (the extruded bunny) whose levels reach
// max_level before the tolerance is met; the second's closure splits climb levels
// faster where a twist refines widely (the elephant).
void tolerance_sweep(const QualityCase& c, json& methods, std::vector<AdaptivePoint>& points) {
  for (bool longest : {false, true})
    for (double fraction : {4e-4, 2e-4, 1e-4, 5e-5, 2.5e-5, 1.25e-5}) {
      RemeshOptions options;
      options.trigger = RemeshTrigger::Midpoint;
      options.tolerance = fraction * c.diag;
      options.max_level = 16;
      options.longest_edge_first = longest;
      char label[64];
      std::snprintf(label, sizeof label, "adaptive midpoint tol %.3g diag, split %s", fraction,
                    longest ? "longest" : "edge");
      adaptive_row(c, options, label, methods, points);
    }
}

// At equal face count: for each uniform level, the best adaptive run with no more faces
// (also printed to stderr, under `name` and `deformation`).
json at_equal_faces(const std::string& name, const std::string& deformation, const std::vector<UniformPoint>& uniform,
                    const std::vector<AdaptivePoint>& adaptive) {
  json equal = json::array();
  for (const auto& [faces, hausdorff] : uniform) {
    const AdaptivePoint* best = nullptr;
    for (const auto& p : adaptive)
      if (std::get<1>(p) <= faces && (!best || std::get<2>(p) < std::get<2>(*best))) best = &p;
    if (!best) continue;
    equal.push_back({{"uniform_faces", faces}, {"adaptive", std::get<0>(*best)},
                     {"adaptive_faces", std::get<1>(*best)},
                     {"adaptive_over_uniform_hausdorff", std::get<2>(*best) / hausdorff}});
    std::fprintf(stderr, "  quality %s %s: %zu uniform faces, %s with %zu faces: Hausdorff ratio %.3f\n",
                 name.c_str(), deformation.c_str(), faces, std::get<0>(*best).c_str(), std::get<1>(*best),
                 std::get<2>(*best) / hausdorff);
  }
  return equal;
}

void quality(Context& ctx, json& rows) {
  const std::vector<std::string> names =
      ctx.quick ? std::vector<std::string>{"bunny.obj"}
                : std::vector<std::string>{"bunny.obj", "armadillo.off", "refined_elephant.off"};
  const std::vector<Deformation> deformations = {{"extrude", extrude}, {"twist", twist}};
  for (const std::string& name : names) {
    const Mesh input = load(ctx, name);
    const Parallelepiped box = fit_aabb(input.positions(), {}, 0.05);
    const double diag = box.extents().norm();
    // Uniform midpoint subdivisions of the rest mesh: 1 and 2 levels for the candidates,
    // 3 (small meshes) or 2 levels beyond the input for the truth.
    std::vector<Mesh> uniform;
    uniform.push_back(input.clone());
    const int truth_level = input.num_faces() < 20000 ? 3 : 2;
    for (int level = 1; level <= truth_level; ++level) uniform.push_back(midpoint_subdivision(uniform.back()));
    for (const Deformation& d : deformations) {
      Mesh truth = uniform[truth_level].clone();
      deform(truth, box, d);
      const SurfaceDistance to_truth(truth);
      const QualityCase c{input, box, diag, d, truth, to_truth};
      json methods = json::array();
      std::vector<UniformPoint> uniform_points;
      fixed_rows(c, uniform, truth_level, methods, uniform_points);
      std::vector<AdaptivePoint> adaptive_points;
      angle_sweep(c, methods, adaptive_points);
      tolerance_sweep(c, methods, adaptive_points);
      rows.push_back({{"mesh", name}, {"deformation", d.name}, {"input_faces", input.num_faces()},
                      {"truth_faces", truth.num_faces()}, {"methods", methods},
                      {"at_equal_faces", at_equal_faces(name, d.name, uniform_points, adaptive_points)}});
    }
  }
}

// One whole FFD + remesh step on `input` (and a decimating step back), with the uniform
// midpoint subdivision of the same mesh as the reference.
json speed(Context& ctx, const Mesh& input, const std::string& name) {
  const Parallelepiped box = fit_aabb(input.positions(), {}, 0.05);
  // One whole FFD + remesh step: move the lattice, re-evaluate, refine and decimate.
  RemeshStats step_stats;
  double update_ms = 0;
  const double step_ms = median_ms(ctx.repeats, [&] {
    Mesh mesh = input.clone();
    WarpStack stack;
    auto owned = std::make_unique<BSplineLattice>(box, Index3{8, 8, 8}, 3);
    BSplineLattice* lattice = owned.get();
    stack.push(mesh, "l", std::move(owned));
    Stopwatch clock;
    extrude(*lattice);
    stack.update(mesh, "l");
    update_ms = clock.ms();
    HalfedgeCache cache;
    step_stats = adaptive_remesh(mesh, cache, stack, RemeshOptions{});
  });
  const double uniform_ms = median_ms(ctx.repeats, [&] { midpoint_subdivision(input); });
  // Decimation speed: flatten what the extrusion refined.
  Mesh mesh = input.clone();
  auto stack = deform(mesh, box, {"extrude", extrude});
  HalfedgeCache cache;
  adaptive_remesh(mesh, cache, *stack, RemeshOptions{});
  auto* lattice = dynamic_cast<BSplineLattice*>(&stack->warp(0));
  for (std::size_t f = 0; f < lattice->num_points(); ++f) {
    const Index3 ijk = lattice->index(f);
    if (lattice->movable(ijk)) lattice->move_point(ijk, lattice->rest_point(ijk));
  }
  stack->update(mesh, "l");
  const RemeshStats back = adaptive_remesh(mesh, cache, *stack, RemeshOptions{});

  // Level bookkeeping: one byte per vertex (level), one per edge (level), four per face
  // (the first vertex, so unwound faces come back as written).
  const double bytes_per_face =
      (double(mesh.num_vertices()) * 1 + double(mesh_info(mesh).edges) * 1 + double(mesh.num_faces()) * 4) /
      double(mesh.num_faces());
  // The whole step, ms: the lattice update plus test, refine, decimate.
  const double step_parts = update_ms + step_stats.ms_test + step_stats.ms_refine + step_stats.ms_decimate;
  std::fprintf(stderr, "  speed %s (%zu faces): FFD + remesh %.1f ms, uniform subdivision %.1f ms\n", name.c_str(),
               input.num_faces(), step_ms, uniform_ms);
  return {{"mesh", name},
         {"faces", input.num_faces()},
         {"ffd_plus_remesh_ms", step_ms},
         {"of_which_ffd_update_ms", update_ms},
         {"of_which_remesh_ms", step_parts - update_ms},
         {"uniform_subdivision_ms", uniform_ms},
         {"step_over_uniform_subdivision", step_ms / uniform_ms},
         {"refinements", step_stats.refinements},
         {"edges_tested_per_s", step_stats.edges_tested / (step_stats.ms_test + step_stats.ms_refine) * 1e3},
         {"refinements_per_s", step_stats.refinements / step_stats.ms_refine * 1e3},
         {"decimations", back.decimations},
         {"decimations_per_s", back.decimations / back.ms_decimate * 1e3},
         {"level_bytes_per_face", bytes_per_face}};
}

}  // namespace

void bench_remesh(Context& ctx) {
  json quality_rows = json::array();
  quality(ctx, quality_rows);
  // The largest real mesh here (88,928 faces), and its midpoint subdivision (355,712
  // faces) for a step on a mesh beyond 100k faces.
  const std::string name = ctx.quick ? "bunny.obj" : "refined_elephant.off";
  const Mesh input = load(ctx, name);
  json speed_rows = json::array();
  speed_rows.push_back(speed(ctx, input, name));
  if (!ctx.quick) speed_rows.push_back(speed(ctx, midpoint_subdivision(input), name + " subdivided once"));
  ctx.out["remesh"] = {{"quality", quality_rows}, {"speed", speed_rows}};
}

}  // namespace ffd::bench
