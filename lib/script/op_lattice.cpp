// The lattice op: a named lattice on top of the warp stack.
#include "common/numbers.h"
#include "multires/octree_lattice.h"
#include "script/op.h"
#include "script/selection.h"
#include "warp/bernstein_lattice.h"
#include "warp/box_fit.h"
#include "warp/lattice_spec.h"

namespace ffd {
namespace {

enum class Basis { BSpline, Bernstein, Octree };
const std::vector<std::pair<std::string, Basis>> kBases = {
    {"bspline", Basis::BSpline}, {"bernstein", Basis::Bernstein}, {"octree", Basis::Octree}};

struct LatticeStep final : Step {
  bool needs_vertex_normals() const override { return false; }
  std::string name;
  Basis basis = Basis::BSpline;
  int degree = 3;
  BoxSpec box;
  std::optional<Index3> cells;
  OctreeOptions octree;
  std::optional<double> shrink;
  std::optional<std::string> enclose;

  /// The tensor-product lattice's shape (bspline, bernstein).
  LatticeSpec spec() const {
    return {basis == Basis::Bernstein ? Lattice::Basis::Bernstein : Lattice::Basis::BSpline, degree,
            cells.value_or(Index3{0, 0, 0})};
  }
  void check(ScriptChecks& checks) const override;
  void check_octree_options(ScriptChecks& checks) const;
  void run(Scene& scene, StepContext& ctx) const override;
  void make_octree(Scene& scene, StepContext& ctx) const;
};

KeyTable<LatticeStep> lattice_keys() {
  using S = LatticeStep;
  const nlohmann::json cells = {{"type", "array"}, {"items", schema_integer(1, 1000)}, {"minItems", 3}, {"maxItems", 3}};
  return {{
      key<S>("/name", schema_text(), nullptr, "Name used by later steps.", [](auto& s) -> auto& { return s.name; })
          .required(),
      enum_key<S>("/basis", kBases, "bspline",
                  "bspline: uniform B-spline with fixed influenced and phantom zones (identity outside the box, "
                  "C^(degree-1) across it). bernstein: Sederberg & Parry's Bézier volume. octree: Ono et al.'s "
                  "multiresolution lattices fitted to the mesh, deforming by Catmull-Clark subdivision volumes.",
                  [](auto& s) -> auto& { return s.basis; }),
      key<S>("/degree", schema_integer(1, 3), 3,
             "B-spline degree (bspline only; a Bernstein lattice's degree per axis is its cell count).",
             [](auto& s) -> auto& { return s.degree; }),
      key<S>("/box", schema_ref("box"), write_value(BoxSpec{}),
             "The lattice's box (an octree lattice's level 0). fit \"obb\" is the box along the principal "
             "components of the vertices (Gottschalk's OBB, what Ono et al. use), for every basis.",
             [](auto& s) -> auto& { return s.box; })
          .about("box"),
      key<S>("/cells", cells, nullptr,
             "Cells per axis [l, m, n]: B-spline knot spans across the box, or Bernstein degrees (required for "
             "bspline and bernstein; an octree lattice takes levels).",
             [](auto& s) -> auto& { return s.cells; }),
      key<S>("/levels", schema_integer(0, 6), 3,
             "octree: octree subdivisions of the box; level l has up to 2^l cells per axis, the cells holding "
             "no vertex of the region cut.",
             [](auto& s) -> auto& { return s.octree.levels; }),
      key<S>("/cc_steps", schema_integer(0, 4), 2,
             "octree: Catmull-Clark volume subdivisions n that approximate the deformation (error about 4x "
             "smaller per step).",
             [](auto& s) -> auto& { return s.octree.cc_steps; }),
      key<S>("/shrink", schema_number(0), nullptr,
             "octree: move each level's boundary points toward the region along each axis, stopping this "
             "offset (mesh units) short of it (at most 0.45 of a cell).",
             [](auto& s) -> auto& { return s.shrink; }),
      key<S>("/enclose", schema_text(), nullptr,
             "octree: a lattice created earlier; the box is fitted around the mesh and that lattice's control "
             "points, which this lattice then deforms too (global editing after local).",
             [](auto& s) -> auto& { return s.enclose; }),
  }};
}

void LatticeStep::check_octree_options(ScriptChecks& checks) const {
  if (cells) checks.fail(pointer + "/cells", "an octree lattice takes levels, not cells");
  // The finest subdivided lattice has 2^(levels + cc_steps) cells per axis at most.
  if (octree.levels + octree.cc_steps > 8)
    checks.fail(pointer + "/cc_steps", "levels + cc_steps is at most 8 (2^8 subdivided cells per axis); use fewer "
                                        "Catmull-Clark steps on a fine level");
  if (enclose) {
    if (!checks.deformers.count(*enclose))
      checks.fail(pointer + "/enclose", "no lattice named '" + *enclose + "' is created before this step");
    if (box.kind != BoxSpec::Kind::Fit)
      checks.fail(pointer + "/box", "enclose fits the box around the mesh and the lattice; give {\"fit\": ...}");
  }
  DeformerShape shape{"octree", true, octree.levels, octree.levels, nullptr};
  // A local level's nodes are at twice its source's resolution; the run checks them.
  shape.unmovable = [grid = octree.levels](int level, const PointIndex& index) -> std::optional<std::string> {
    const int top = 1 << std::min(level, grid + 1);
    for (int a = 0; a < 3; ++a)
      if (index.ijk[a] < 0 || index.ijk[a] > top) return octree_points_text(level, top);
    return std::nullopt;
  };
  checks.deformers[name] = shape;
}

void LatticeStep::check(ScriptChecks& checks) const {
  checks.check_new_lattice(name, pointer + "/name");
  if (box.select) check_vertex_selection(*box.select);
  if (basis == Basis::Octree) return check_octree_options(checks);
  if (shrink) checks.fail(pointer + "/shrink", "shrink is for octree lattices");
  if (enclose) checks.fail(pointer + "/enclose", "enclose is for octree lattices");
  if (!cells) checks.fail(pointer + "/cells", "a " + name_of(kBases, basis) + " lattice needs cells [l, m, n]");
  const LatticeSpec lattice = spec();
  const bool bspline = lattice.basis == Lattice::Basis::BSpline;
  double points = 1;
  for (int a = 0; a < 3; ++a) {
    const std::string cell = pointer + "/cells/" + std::to_string(a);
    if (!bspline && lattice.cells[a] > BernsteinLattice::kMaxDegree)
      checks.fail(cell, "a Bernstein lattice's degree per axis is at most " +
                            std::to_string(BernsteinLattice::kMaxDegree) + "; use basis \"bspline\" for finer lattices");
    if (bspline && lattice.cells[a] < lattice.degree + 1)
      checks.fail(cell, "a degree-" + std::to_string(lattice.degree) + " B-spline lattice needs at least " +
                            std::to_string(lattice.degree + 1) +
                            " cells per axis to have a movable point (its influenced and phantom zones stay fixed)");
    points *= lattice.cells[a] + (bspline ? lattice.degree : 1);
  }
  if (points > 16.0 * 1024 * 1024) checks.fail(pointer + "/cells", "the lattice would have more than 16M control points");
  DeformerShape shape{name_of(kBases, basis), false, 0, -1, nullptr};
  shape.unmovable = [lattice](int, const PointIndex& index) -> std::optional<std::string> {
    for (int a = 0; a < 3; ++a) {
      int lo, hi;
      movable_span(lattice, a, lo, hi);
      if (index.ijk[a] < lo || index.ijk[a] > hi) return movable_text(lattice);
    }
    return std::nullopt;
  };
  checks.deformers[name] = shape;
}

/// The box of kind `fit` around the columns `ids` of `points` (all when empty).
Parallelepiped fit_box(BoxSpec::Fit fit, const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                       const std::vector<std::uint32_t>& ids, double padding) {
  switch (fit) {
    case BoxSpec::Fit::Obb:
      return fit_principal_box(points, ids, padding);
    case BoxSpec::Fit::MinVolume:
      return fit_min_volume_box(points, ids, padding);
    case BoxSpec::Fit::Aabb:
      break;
  }
  return fit_aabb(points, ids, padding);
}

/// The box `box` asks for around the mesh. An axis-aligned fit to every vertex also keeps
/// their bounds in `bounds` (when given), for vertices_inside().
Parallelepiped make_box(const Scene& scene, const BoxSpec& box, std::optional<PointBounds>* bounds = nullptr) {
  if (box.kind == BoxSpec::Kind::MinMax) return Parallelepiped::from_min_max(box.min, box.max);
  if (box.kind == BoxSpec::Kind::OriginAxes) return Parallelepiped(box.origin, box.axes);
  if (bounds && box.fit == BoxSpec::Fit::Aabb && !box.select) {
    *bounds = point_bounds(scene.mesh.positions(), {});
    return aabb_around(**bounds, box.padding);
  }
  std::vector<std::uint32_t> ids;
  if (box.select) ids = select_vertices(*box.select, scene.mesh.positions(), scene.mesh.volume_source());
  return fit_box(box.fit, scene.mesh.positions(), ids, box.padding);
}

/// How many mesh vertices lie in `placed`; `bounds`, where known, bound every vertex. Box
/// coordinates in an axis-aligned box are each a rounded difference times a positive
/// number (the other terms exact zeros), so they never decrease as a world coordinate
/// grows: when the bounds' two corners are inside, so is every vertex, and the count (a
/// pass over every position, 24 MB on a 1M-vertex mesh) is skipped.
std::size_t vertices_inside(const Parallelepiped& placed, const std::optional<PointBounds>& bounds, const Mesh& mesh) {
  const auto positions = mesh.positions();
  if (bounds && Lattice::inside(placed.to_local(bounds->lo)) && Lattice::inside(placed.to_local(bounds->hi)))
    return static_cast<std::size_t>(positions.cols());
  std::size_t inside = 0;
  for (Eigen::Index v = 0; v < positions.cols(); ++v) inside += Lattice::inside(placed.to_local(positions.col(v)));
  return inside;
}

nlohmann::json vec_json(const Eigen::Vector3d& v) { return write_value(v); }

nlohmann::json box_json(const Parallelepiped& box) {
  return {{"origin", vec_json(box.origin())},
          {"axes", {vec_json(box.axes().col(0)), vec_json(box.axes().col(1)), vec_json(box.axes().col(2))}}};
}

/// The points an octree lattice is fitted and cut around: the region's vertices, and with
/// `enclose` the enclosed deformer's control points (every level's) where the mesh sees them.
/// The region is written straight into its matrix: a vector of points grown one vertex at a
/// time was reallocated and copied some 17 times on a 39k-vertex mesh.
Eigen::Matrix3Xd octree_region(Scene& scene, const BoxSpec& box, const std::optional<std::string>& enclose) {
  const auto positions = scene.mesh.positions();
  std::vector<std::uint32_t> ids;
  if (box.select) ids = select_vertices(*box.select, positions, scene.mesh.volume_source());
  std::vector<Eigen::Vector3d> carried;  // the enclosed deformer's points, where the mesh sees them
  if (enclose) {
    const std::size_t k = scene.stack.index_of(*enclose);
    const Deformer& enclosed = scene.deformer(*enclose);
    for (int l = 0; l < enclosed.num_levels(); ++l) {
      const Eigen::Matrix3Xd level = enclosed.points(l);
      for (Eigen::Index p = 0; p < level.cols(); ++p) carried.push_back(scene.stack.carry_from(k, level.col(p)));
    }
  }
  // An empty selection (none given, or none selected) is the whole mesh.
  const Eigen::Index vertices = ids.empty() ? positions.cols() : static_cast<Eigen::Index>(ids.size());
  Eigen::Matrix3Xd region(3, vertices + static_cast<Eigen::Index>(carried.size()));
  if (ids.empty()) region.leftCols(vertices) = positions;
  for (std::size_t i = 0; i < ids.size(); ++i) region.col(static_cast<Eigen::Index>(i)) = positions.col(ids[i]);
  for (std::size_t i = 0; i < carried.size(); ++i) region.col(vertices + static_cast<Eigen::Index>(i)) = carried[i];
  return region;
}

Parallelepiped fit_octree_box(const Scene& scene, const BoxSpec& box, const Eigen::Matrix3Xd& region) {
  return box.kind == BoxSpec::Kind::Fit ? fit_box(box.fit, region, {}, box.padding) : make_box(scene, box);
}

void LatticeStep::make_octree(Scene& scene, StepContext& ctx) const {
  const Eigen::Matrix3Xd region = concerning("box", [&] { return octree_region(scene, box, enclose); });
  const Parallelepiped placed = concerning("box", [&] { return fit_octree_box(scene, box, region); });
  OctreeOptions options = octree;
  options.shrink = shrink.value_or(-1.0);
  auto made = std::make_unique<OctreeLattice>(placed, region, options);
  OctreeLattice* raw = made.get();
  scene.stack.push(scene.mesh, name, std::move(made));
  scene.deformers[name] = raw;

  nlohmann::json levels = nlohmann::json::array();
  for (int l = 0; l < raw->num_levels(); ++l)
    levels.push_back({{"level", l},
                      {"points", raw->complex(l).num_points()},
                      {"cells", raw->complex(l).num_cells()},
                      {"cut_cells", raw->cut_cells(l)}});
  const std::size_t inside = vertices_inside(placed, std::nullopt, scene.mesh);
  ctx.stats["name"] = name;
  ctx.stats["basis"] = "octree";
  ctx.stats["levels"] = levels;
  ctx.stats["cc_steps"] = octree.cc_steps;
  if (shrink) ctx.stats["shrink"] = *shrink;
  if (enclose) ctx.stats["enclose"] = *enclose;
  ctx.stats["box"] = box_json(placed);
  ctx.stats["vertices_inside"] = inside;
  ctx.stats["bytes"] = raw->bytes();
  const GridComplex& finest = raw->complex(raw->num_levels() - 1);
  ctx.summary = "lattice '" + name + "': octree, levels 0-" + std::to_string(octree.levels) + " (finest: " +
                format_count(finest.num_cells()) + " cells, " + format_count(finest.num_points()) + " points), " +
                "cc_steps " + std::to_string(octree.cc_steps) + ", " + format_count(inside) + " vertices inside";
  if (inside == 0) scene.warnings.push_back(ctx.pointer + ": lattice '" + name + "' contains no mesh vertex");
}

void LatticeStep::run(Scene& scene, StepContext& ctx) const {
  if (basis == Basis::Octree) return make_octree(scene, ctx);
  const LatticeSpec lattice = spec();
  std::optional<PointBounds> bounds;
  const Parallelepiped placed = concerning("box", [&] { return make_box(scene, box, &bounds); });
  std::unique_ptr<Lattice> made = make_lattice(lattice, placed);
  Lattice* raw = made.get();
  scene.stack.push(scene.mesh, name, std::move(made));
  scene.deformers[name] = raw;

  std::size_t movable = 0;
  for (std::size_t f = 0; f < raw->num_points(); ++f) movable += raw->movable(raw->index(f));
  const std::size_t inside = vertices_inside(placed, bounds, scene.mesh);
  const Index3 degree = raw->degree();
  const std::string basis_name = name_of(kBases, basis);
  const Index3& cells = lattice.cells;
  ctx.stats["name"] = name;
  ctx.stats["basis"] = basis_name;
  ctx.stats["degree"] = write_value(degree);
  ctx.stats["cells"] = write_value(cells);
  ctx.stats["control_points"] = raw->num_points();
  ctx.stats["movable_points"] = movable;
  ctx.stats["vertices_inside"] = inside;
  ctx.stats["box"] = box_json(placed);
  ctx.stats["boundary_continuity"] = raw->boundary_continuity();
  ctx.summary = "lattice '" + name + "': " + basis_name +
                (lattice.basis == Lattice::Basis::BSpline ? " degree " + std::to_string(degree[0]) : std::string()) +
                ", " + std::to_string(cells[0]) + "x" + std::to_string(cells[1]) + "x" + std::to_string(cells[2]) +
                " cells, " + format_count(raw->num_points()) + " points (" + format_count(movable) + " movable), " +
                format_count(inside) + " vertices inside";
  if (inside == 0) scene.warnings.push_back(ctx.pointer + ": lattice '" + name + "' contains no mesh vertex");
}

}  // namespace

const OpInfo& lattice_op() {
  static const OpDecl<LatticeStep> op{"lattice", "Creates a named lattice on top of the warp stack.", lattice_keys()};
  return op;
}

}  // namespace ffd
