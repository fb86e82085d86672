// Ono et al.'s multiresolution lattices (lib/multires) against the paper's Tables 1 and
// 2 ("FFD with automatically generated multiresolution lattices", Pentium 4 1.7 GHz) and
// against a plain cubic B-spline lattice move measured in the same run:
// - memory (Table 1): the 1-cell complex refined k = 0..5 times, its 3 x N positions
//   subdivided by the Catmull-Clark rules each step; bytes = GridComplex::bytes() + the
//   positions of the final step only (what that subdivision keeps), against the paper's
//   bytes for 1..32768 cells.
// - moves (Table 2): per mesh, one OctreeLattice (levels 5, cc_steps 2, no shrink) on the
//   mesh's principal box (padding 0.02), edited level by level 0..5 as a session would
//   (so a finer level's vertices are also re-evaluated in the coarser levels' fields). Per
//   level: the first move (it includes the one-time Catmull-Clark subdivision of the
//   level's rest lattice) alone, then the median of the next moves, each of another point
//   of the level (the point nearest a random mesh vertex) by 1% of the box's largest
//   extent. A move is move_level_points + changed_points + batch apply (positions and normals) of
//   those vertices + clear_changes. Then a local subdivision of level 3 as a new level,
//   moved the same way, and a second pass: every level moved again as before, now that
//   every level has moved (each vertex is re-evaluated through all its levels' tags).
//   Baseline: BSplineLattice(box, {8,8,8}, 3), move_point of a random interior point,
//   then the same changed_points + apply + clear_changes.
// - lattice memory: OctreeLattice::bytes() per mesh after the moves, per lattice cell and
//   per cell of the Catmull-Clark subdivisions held, against the paper's Table 1 bytes
//   per cell of one cube subdivided twice.
// Every mesh on one thread (the paper's machine has one core), the largest again on every
// core (the interactive tool's setting). Medians over 20 moves; --quick: the small mesh
// and the elephant, 5 moves.
// The small mesh is the bundled bunny (1,839 vertices) decimated to the paper's 495 by
// CGAL's edge collapse (Lindstrom-Turk, the default policies).
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <numeric>
#include <random>

#include "bench.h"
#include "common/timer.h"
#include "mesh/halfedge_view_cgal.h"
#include "multires/octree_lattice.h"
#include "multires/volume_subdivision.h"
#include "warp/box_fit.h"
#include "warp/bspline_lattice.h"

namespace ffd::bench {
namespace {

using json = nlohmann::ordered_json;

constexpr int kLevels = 5;
constexpr int kCcSteps = 2;
constexpr double kMoveFraction = 0.01;  // of the box's largest extent
constexpr double kTargetMs = 10;

/// Paper Table 1: bytes for 0..5 Catmull-Clark subdivisions of one cube.
constexpr double kPaperBytes[] = {1296, 7376, 48336, 345488, 2601744, 20170256};

/// A mesh of the moves rows and the paper's Table 2 row (by vertex count) it is set against.
struct MeshCase {
  const char* name;
  int paper_vertices;
  double paper_fps[kLevels + 1];
};
constexpr MeshCase kSmall{"bunny.obj decimated", 495, {50.0, 25.4, 5.12, 3.13, 4.44, 4.16}};
constexpr MeshCase kArmadillo{"armadillo.off", 22886, {4.54, 3.57, 2.54, 1.97, 2.56, 2.02}};
constexpr MeshCase kBunny00{"bunny00.off", 53417, {3.69, 2.73, 2.19, 1.80, 2.30, 1.90}};
constexpr MeshCase kElephant{"refined_elephant.off", 53417, {3.69, 2.73, 2.19, 1.80, 2.30, 1.90}};

/// The Table 1 row of k Catmull-Clark subdivisions of the unit cube.
json memory_row(int k, int repeats) {
  GridComplex g;
  Eigen::MatrixXd X;
  const double ms = median_ms(repeats, [&] {
    g = make_grid_complex(1, {{0, 0, 0}});
    X.resize(3, static_cast<Eigen::Index>(g.num_points()));
    for (std::size_t p = 0; p < g.num_points(); ++p)
      for (int a = 0; a < 3; ++a) X(a, static_cast<Eigen::Index>(p)) = g.points[p][a];
    for (int s = 0; s < k; ++s) {
      GridComplex fine = refine(g);
      X = subdivide_field(g, fine, X, SubdivisionRule::CatmullClark);
      g = std::move(fine);
    }
  });
  const double topology = static_cast<double>(g.bytes());
  const double positions = 8.0 * 3.0 * static_cast<double>(g.num_points());
  const double bytes = topology + positions, cells = static_cast<double>(g.num_cells());
  return {{"subdivisions", k},
          {"cells", g.num_cells()},
          {"points", g.num_points()},
          {"topology_bytes", topology},
          {"position_bytes", positions},
          {"bytes", bytes},
          {"bytes_per_cell", bytes / cells},
          {"paper_bytes", kPaperBytes[k]},
          {"paper_bytes_per_cell", kPaperBytes[k] / cells},
          {"bytes_vs_paper", bytes / kPaperBytes[k]},
          {"subdivide_ms", ms}};
}

/// The bundled bunny decimated to the paper's 495 vertices (a closed genus-0 mesh has
/// E = 3V - 6 edges; an edge collapse removes one vertex and three edges).
Mesh small_mesh(const Context& ctx) {
  const Mesh bunny = load(ctx, "bunny.obj");
  SurfaceMesh sm = surface_mesh(bunny);
  const std::size_t vertices = static_cast<std::size_t>(kSmall.paper_vertices);
  CGAL::Surface_mesh_simplification::edge_collapse(
      sm, CGAL::Surface_mesh_simplification::Count_stop_predicate<SurfaceMesh>(3 * vertices - 6 + 1));
  sm.collect_garbage();
  return mesh_from_surface(sm, bunny.source());
}

/// The ms of one move: the whole, and its move, changed_points and apply phases.
struct MoveTime {
  double ms = 0, move_ms = 0, changed_ms = 0, apply_ms = 0;
};

/// What the moves of one warp took: ms each (and per phase), vertices re-evaluated, and
/// the octree's report.
struct Moves {
  std::vector<double> ms, move_ms, changed_ms, apply_ms, relocated, subdivided, marked;
  void add(const MoveTime& t, std::size_t v, const OctreeMove& m) {
    ms.push_back(t.ms);
    move_ms.push_back(t.move_ms);
    changed_ms.push_back(t.changed_ms);
    apply_ms.push_back(t.apply_ms);
    relocated.push_back(static_cast<double>(v));
    subdivided.push_back(static_cast<double>(m.cells_subdivided));
    marked.push_back(static_cast<double>(m.cells_marked));
  }
};

/// The vertices and buffers a warp relocates.
struct Scene {
  Eigen::Matrix3Xd pos, nrm, out_pos, out_nrm;
  std::vector<std::uint32_t> ids;
  explicit Scene(const Mesh& mesh)
      : pos(mesh.positions()), nrm(mesh.normals()), out_pos(pos), out_nrm(nrm) {}
};

/// The ms of `move` + changed_points + batch apply + clear_changes; `relocated` gets the
/// number of vertices re-evaluated.
MoveTime timed_move(Warp& warp, Scene& s, const std::function<void()>& move, std::size_t& relocated) {
  MoveTime t;
  Stopwatch clock;
  move();
  warp.prepare();
  t.move_ms = clock.ms();
  s.ids.clear();
  warp.changed_points(s.pos, s.ids);
  t.changed_ms = clock.ms() - t.move_ms;
  WarpCounts counts;
  warp.apply(s.pos, s.nrm, s.ids, s.out_pos, s.out_nrm, counts);
  warp.clear_changes();
  t.ms = clock.ms();
  t.apply_ms = t.ms - t.move_ms - t.changed_ms;
  relocated = s.ids.size();
  return t;
}

Eigen::Vector3d random_offset(std::mt19937& rng, double length) {
  std::normal_distribution<double> normal;
  Eigen::Vector3d d(normal(rng), normal(rng), normal(rng));
  return length * d.normalized();
}

/// `count` points of the level, each the point nearest a random mesh vertex, distinct
/// unless 20 tries per point find no unused one (level 0 has only 8 points: they repeat).
std::vector<std::int32_t> pick_points(const OctreeLattice& lattice, int level, const Eigen::Matrix3Xd& pos,
                                      std::size_t count, std::mt19937& rng) {
  const Eigen::Matrix3Xd& rest = lattice.rest_points(level);
  std::vector<std::uint8_t> used(static_cast<std::size_t>(rest.cols()), 0);
  std::uniform_int_distribution<Eigen::Index> vertex(0, pos.cols() - 1);
  std::vector<std::int32_t> picked;
  for (std::size_t tries = 0; picked.size() < count; ++tries) {
    Eigen::Index best = 0;
    (rest.colwise() - pos.col(vertex(rng))).colwise().squaredNorm().minCoeff(&best);
    if (used[static_cast<std::size_t>(best)] && tries < 20 * count) continue;
    used[static_cast<std::size_t>(best)] = 1;
    picked.push_back(static_cast<std::int32_t>(best));
  }
  return picked;
}

/// The baseline: median ms of `count` moves of random interior points of a cubic
/// B-spline 8 x 8 x 8 lattice on the box, and the median of the vertices re-evaluated.
std::pair<double, double> bspline_moves(const Parallelepiped& box, Scene& s, std::size_t count, std::mt19937& rng) {
  BSplineLattice lattice(box, {8, 8, 8}, 3);
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lattice.movable_span(a, lo[a], hi[a]);
  const double length = kMoveFraction * box.extents().maxCoeff();
  Moves moves;
  for (std::size_t m = 0; m <= count; ++m) {  // move 0: warm-up
    Index3 ijk;
    for (int a = 0; a < 3; ++a) ijk[a] = std::uniform_int_distribution<int>(lo[a], hi[a])(rng);
    const Eigen::Vector3d target = lattice.point(ijk) + random_offset(rng, length);
    std::size_t relocated = 0;
    const MoveTime t = timed_move(lattice, s, [&] { lattice.move_point(ijk, target); }, relocated);
    if (m > 0) moves.add(t, relocated, {});
  }
  return {median(moves.ms), median(moves.relocated)};
}

/// One moves row: `count` + 1 moves of the level's points (the first reported alone).
json level_row(OctreeLattice& lattice, int level, Scene& s, std::size_t count, std::mt19937& rng) {
  const std::vector<std::int32_t> ids = pick_points(lattice, level, s.pos, count + 1, rng);
  const double length = kMoveFraction * lattice.box().extents().maxCoeff();
  Moves first, rest;
  std::size_t distinct = 0;
  std::vector<std::uint8_t> seen(lattice.num_points(level), 0);
  for (std::size_t m = 0; m < ids.size(); ++m) {
    const std::int32_t id = ids[m];
    distinct += !seen[static_cast<std::size_t>(id)];
    seen[static_cast<std::size_t>(id)] = 1;
    const Eigen::Vector3d target = lattice.points(level).col(id) + random_offset(rng, length);
    OctreeMove report;
    std::size_t relocated = 0;
    const MoveTime t = timed_move(lattice, s, [&] { report = lattice.move_level_points(level, {id}, {target}); }, relocated);
    (m == 0 ? first : rest).add(t, relocated, report);
  }
  const double ms = median(rest.ms);
  return {{"level", level},
          {"level_cells", lattice.num_cells(level)},
          {"level_points", lattice.num_points(level)},
          {"first_move_ms", first.ms[0]},
          {"first_move_relocated", first.relocated[0]},
          {"first_move_cells_subdivided", first.subdivided[0]},
          {"moves", rest.ms.size()},
          {"distinct_points", distinct},
          {"ms", ms},
          {"fps", 1e3 / ms},
          {"max_ms", rest.ms.empty() ? 0.0 : *std::max_element(rest.ms.begin(), rest.ms.end())},
          {"move_points_ms", median(rest.move_ms)},
          {"changed_points_ms", median(rest.changed_ms)},
          {"apply_ms", median(rest.apply_ms)},
          {"first_move_points_ms", first.move_ms[0]},
          {"vertices_relocated", median(rest.relocated)},
          {"cells_subdivided", median(rest.subdivided)},
          {"cells_marked", median(rest.marked)}};
}

/// Adds the paper's fps and the ratios to `r`, a level row of `mesh`.
void add_ratios(json& r, const MeshCase& mesh, double bspline_ms) {
  const double ms = r["ms"].get<double>();
  const double paper_fps = mesh.paper_fps[r["level"].get<int>()];
  r["paper_vertices"] = mesh.paper_vertices;
  r["paper_fps"] = paper_fps;
  r["fps_vs_paper"] = r["fps"].get<double>() / paper_fps;
  r["bspline_ms"] = bspline_ms;
  r["ms_vs_bspline"] = ms / bspline_ms;
  r["first_move_ms_vs_bspline"] = r["first_move_ms"].get<double>() / bspline_ms;
  r["within_10_ms"] = ms <= kTargetMs;
  r["first_move_within_10_ms"] = r["first_move_ms"].get<double>() <= kTargetMs;
}

/// The lattice memory row of `lattice` after the moves.
json lattice_memory_row(const OctreeLattice& lattice, const std::string& mesh, std::size_t vertices, double build_ms) {
  // dense: the index arrays over bounding ranges the lattice holds: every level's grid, and
  // the subdivided complexes of the small levels (a large level's are implied, StepGrid).
  std::size_t level_cells = 0, sub_cells = 0, dense = 0;
  const auto index_bytes = [](const GridComplex& g) {
    return (g.cell_index.capacity() + g.point_index.capacity()) * sizeof(std::int32_t);
  };
  for (int l = 0; l < lattice.num_grid_levels(); ++l) {
    const GridComplex& g = lattice.complex(l);
    level_cells += g.num_cells();
    dense += index_bytes(g);
    const bool small = g.num_cells() <= lattice.options().whole_level_cells;
    for (int k = 1; k <= lattice.options().cc_steps; ++k) {
      sub_cells += g.num_cells() << (3 * k);  // every cell of C^k is a child of a level cell
      if (small) dense += index_bytes(lattice.subdivided(l, k));
    }
  }
  const double bytes = static_cast<double>(lattice.bytes());
  const double paper_per_cell = kPaperBytes[kCcSteps] / 64.0;  // one cube subdivided twice: 64 cells
  return {{"mesh", mesh},
          {"vertices", vertices},
          {"levels", lattice.num_grid_levels() - 1},
          {"cc_steps", lattice.options().cc_steps},
          {"build_ms", build_ms},
          {"bytes", bytes},
          {"dense_index_bytes", dense},
          {"lattice_cells", level_cells},
          {"subdivided_cells", sub_cells},
          {"bytes_per_lattice_cell", bytes / static_cast<double>(level_cells)},
          {"bytes_per_subdivided_cell", bytes / static_cast<double>(sub_cells)},
          {"paper_bytes_per_subdivided_cell", paper_per_cell},
          {"bytes_per_subdivided_cell_vs_paper", bytes / static_cast<double>(sub_cells) / paper_per_cell}};
}

/// A session's second pass over the levels, after every level and the local one have
/// moved: each level 0..local moved again as level_row moves it (its "first" move is only
/// the first of this pass). Every vertex now has a tag at most levels, and each move
/// re-reads them all, which the first pass's rows (fewer levels moved yet) do not show.
void second_pass_rows(OctreeLattice& lattice, int local, const MeshCase& mc, Scene& s, std::size_t count,
                      std::mt19937& rng, double bspline_ms, json& moves) {
  for (int level = 0; level <= local; ++level) {
    json r = {{"mesh", mc.name}, {"vertices", s.pos.cols()}, {"threads", omp_get_max_threads()},
              {"case", "second pass: every level moved before"}};
    r.update(level_row(lattice, level, s, count, rng));
    r["bspline_ms"] = bspline_ms;
    r["ms_vs_bspline"] = r["ms"].get<double>() / bspline_ms;
    r["within_10_ms"] = r["ms"].get<double>() <= kTargetMs;
    moves.push_back(r);
  }
}

/// The moves rows of one mesh on `threads` threads (levels 0..5, the local level, the
/// baseline, then the second pass) and its lattice memory row (before the second pass).
void mesh_rows(const MeshCase& mc, const Mesh& mesh, int threads, std::size_t count, json& moves, json& memory) {
  std::fprintf(stderr, "ffdbench: multires: %s, %zu vertices, %d thread(s)\n", mc.name, mesh.num_vertices(), threads);
  omp_set_num_threads(threads);
  Scene s(mesh);
  const Parallelepiped box = fit_principal_box(s.pos, {}, 0.02);
  std::mt19937 rng(20240501u + static_cast<unsigned>(mesh.num_vertices()));
  const auto [bspline_ms, bspline_relocated] = bspline_moves(box, s, count, rng);
  OctreeOptions options;
  options.levels = kLevels;
  options.cc_steps = kCcSteps;
  Stopwatch build_clock;
  OctreeLattice lattice(box, s.pos, options);
  const double build_ms = build_clock.ms();
  for (int level = 0; level <= kLevels; ++level) {
    json r = {{"mesh", mc.name}, {"vertices", mesh.num_vertices()}, {"threads", threads}};
    r.update(level_row(lattice, level, s, count, rng));
    add_ratios(r, mc, bspline_ms);
    moves.push_back(r);
  }
  // Local subdivision (Figure 3): the cells of level 3 whose centroids lie within an
  // eighth of the box of a vertex, as a new level, moved like the others.
  const GridComplex& g3 = lattice.complex(3);
  const Eigen::Matrix3Xd shown = lattice.points(3);
  const Eigen::Vector3d centre = s.pos.col(s.pos.cols() / 2);
  std::vector<std::int32_t> cells;
  for (std::size_t c = 0; c < g3.num_cells(); ++c) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 8; ++k) centroid += shown.col(g3.corner(c, k)) / 8;
    if ((centroid - centre).norm() < box.extents().maxCoeff() / 8) cells.push_back(static_cast<std::int32_t>(c));
  }
  Stopwatch subdivide_clock;
  const int local = lattice.subdivide(3, cells);
  json r = {{"mesh", mc.name}, {"vertices", mesh.num_vertices()}, {"threads", threads},
            {"case", "local subdivision of " + std::to_string(cells.size()) + " cells of level 3"},
            {"subdivide_ms", subdivide_clock.ms()}};
  r.update(level_row(lattice, local, s, count, rng));
  r["bspline_ms"] = bspline_ms;
  r["ms_vs_bspline"] = r["ms"].get<double>() / bspline_ms;
  r["within_10_ms"] = r["ms"].get<double>() <= kTargetMs;
  moves.push_back(r);
  moves.push_back({{"mesh", mc.name},
                   {"vertices", mesh.num_vertices()},
                   {"threads", threads},
                   {"case", "baseline: cubic B-spline 8x8x8, move_point of an interior point"},
                   {"moves", count},
                   {"ms", bspline_ms},
                   {"fps", 1e3 / bspline_ms},
                   {"vertices_relocated", bspline_relocated}});
  memory.push_back(lattice_memory_row(lattice, mc.name, mesh.num_vertices(), build_ms));
  memory.back()["threads"] = threads;
  second_pass_rows(lattice, local, mc, s, count, rng, bspline_ms, moves);
}

void print_moves(const json& moves) {
  std::fprintf(stderr, "\nmultires: ms per move (first: with the level's Catmull-Clark subdivision; cells: "
                       "subdivided; vs bspl: ms over the cubic B-spline move's)\n");
  std::fprintf(stderr, "%-22s %7s %3s %5s %9s %8s %8s %9s %9s %8s %9s\n", "mesh", "verts", "thr", "level", "first ms",
               "ms", "fps", "paper fps", "relocated", "cells", "vs bspl");
  for (const json& r : moves) {
    if (!r.contains("level")) {  // the B-spline baseline
      std::fprintf(stderr, "%-22s %7zu %3d %5s %9s %8.2f %8.1f %9s %9.0f %8s %9s\n",
                   r["mesh"].get<std::string>().c_str(), r["vertices"].get<std::size_t>(), r["threads"].get<int>(), "bspl", "-", r["ms"].get<double>(), r["fps"].get<double>(), "-",
                   r["vertices_relocated"].get<double>(), "-", "1");
      continue;
    }
    // A second pass's level is shown as "2/level".
    const bool second = r.value("case", std::string()).rfind("second pass", 0) == 0;
    const std::string level = (second ? "2/" : "") + std::to_string(r["level"].get<int>());
    std::fprintf(stderr, "%-22s %7zu %3d %5s %9.2f %8.2f %8.1f %9.2f %9.0f %8.0f %9.2f\n",
                 r["mesh"].get<std::string>().c_str(), r["vertices"].get<std::size_t>(), r["threads"].get<int>(),
                 level.c_str(),
                 r["first_move_ms"].get<double>(), r["ms"].get<double>(), r["fps"].get<double>(),
                 r.value("paper_fps", 0.0), r["vertices_relocated"].get<double>(),
                 r["cells_subdivided"].get<double>(), r["ms_vs_bspline"].get<double>());
  }
  std::fprintf(stderr, "\n");
}

}  // namespace

/// The small-level threshold (OctreeOptions::whole_level_cells): median ms of
/// move_level_points at levels 2..5 of `mesh` when every level moves by its steps' matrices
/// (rows built where moves reach) and when every move re-subdivides N_{S,3}, and the memory
/// each way adds to the lattice.
json threshold_rows(const Mesh& mesh, const char* name, std::size_t count) {
  const Eigen::Matrix3Xd x = mesh.positions();
  const Parallelepiped box = fit_principal_box(x, {}, 0.02);
  json rows = json::array();
  for (const bool matrices : {false, true}) {
    OctreeOptions options;
    options.levels = kLevels;
    options.cc_steps = kCcSteps;
    options.whole_level_cells = matrices ? std::size_t{1} << 30 : 0;
    OctreeLattice lattice(box, x, options);
    for (int level = 2; level <= kLevels; ++level) {
      std::mt19937 rng(5u + static_cast<unsigned>(level));
      std::vector<double> ms;
      const double before = static_cast<double>(lattice.bytes());
      for (std::size_t m = 0; m <= count; ++m) {  // move 0 builds the level's subdivision
        const auto id = static_cast<std::int32_t>(
            std::uniform_int_distribution<std::size_t>(0, lattice.num_points(level) - 1)(rng));
        const Eigen::Vector3d target = lattice.points(level).col(id) + random_offset(rng, 0.01 * box.extents().maxCoeff());
        Stopwatch clock;
        lattice.move_level_points(level, {id}, {target});
        if (m > 0) ms.push_back(clock.ms());
        lattice.clear_changes();
      }
      rows.push_back({{"mesh", name},
                      {"case", matrices ? "by the step matrices' rows" : "N_{S,3} by stencils"},
                      {"level", level},
                      {"level_cells", lattice.num_cells(level)},
                      {"move_points_ms", median(ms)},
                      {"bytes_added", static_cast<double>(lattice.bytes()) - before}});
    }
  }
  return rows;
}

void bench_multires(Context& ctx) {
  json memory = json::array();
  for (int k = 0; k <= 5; ++k) memory.push_back(memory_row(k, ctx.repeats));
  const int cores = omp_get_num_procs();
  const std::size_t count = ctx.quick ? 5 : 20;
  json moves = json::array(), lattice_memory = json::array();
  mesh_rows(kSmall, small_mesh(ctx), 1, count, moves, lattice_memory);
  const std::vector<MeshCase> big = ctx.quick ? std::vector<MeshCase>{kElephant}
                                              : std::vector<MeshCase>{kArmadillo, kBunny00, kElephant};
  for (const MeshCase& mc : big) mesh_rows(mc, load(ctx, mc.name), 1, count, moves, lattice_memory);
  if (cores > 1) mesh_rows(kElephant, load(ctx, kElephant.name), cores, count, moves, lattice_memory);
  omp_set_num_threads(1);
  const json threshold = threshold_rows(load(ctx, kElephant.name), kElephant.name, count);
  omp_set_num_threads(cores);
  print_moves(moves);
  for (const json& r : threshold)
    std::fprintf(stderr, "multires threshold: %-24s level %d, %5zu cells: move_points %6.2f ms, +%.1f MB\n",
                 r["case"].get<std::string>().c_str(), r["level"].get<int>(), r["level_cells"].get<std::size_t>(),
                 r["move_points_ms"].get<double>(), r["bytes_added"].get<double>() / 1e6);
  ctx.out["multires"] = {
      {"memory", memory}, {"moves", moves}, {"lattice_memory", lattice_memory}, {"threshold", threshold}};
}

}  // namespace ffd::bench
