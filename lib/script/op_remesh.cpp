// The remesh op: adaptive refinement and reversible decimation after the deformations so
// far (Gain & Dodgson section 4).
#include <optional>

#include "common/numbers.h"
#include "mesh/mesh_io.h"
#include "remesh/adaptive_remesher.h"
#include "script/op.h"

namespace ffd {
namespace {

const std::vector<std::pair<std::string, RemeshTrigger>> kTriggers = {{"normal", RemeshTrigger::Normal},
                                                                       {"midpoint", RemeshTrigger::Midpoint}};
const std::vector<std::pair<std::string, bool>> kSplits = {{"edge", false}, {"longest", true}};

struct RemeshStep final : Step {
  RemeshOptions options;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
};

// l_max: a length, or "auto" (empty: the smallest lattice cell).
Key<RemeshStep> l_max_key() {
  const nlohmann::json schema = {
      {"oneOf", {schema_number(0), {{"type", "string"}, {"const", "auto"}}}}};
  return custom_key<RemeshStep>(
             "/l_max", schema, "auto",
             "Longest edge where a lattice can act, in mesh units; \"auto\": the smallest lattice cell extent.",
             [](RemeshStep& s, const nlohmann::json& v, const ScriptPlace&) {
               if (v.is_number()) s.options.l_max = v.get<double>();
             },
             [](const RemeshStep& s) { return s.options.l_max ? nlohmann::json(*s.options.l_max) : "auto"; })
      .about("l_max");
}

KeyTable<RemeshStep> remesh_keys() {
  using S = RemeshStep;
  return {{
      key<S>("/theta_max_deg", schema_number(0, 90), 25.7,
             "Refine an edge with a deformed endpoint when its deformed endpoint normals diverge by more than this.",
             [](auto& s) -> auto& { return s.options.theta_max_deg; }),
      key<S>("/theta_min_deg", schema_number(0, 90), 20.0,
             "Decimation: endpoint normals diverging by less than this (must be below theta_max_deg).",
             [](auto& s) -> auto& { return s.options.theta_min_deg; }),
      l_max_key(),
      key<S>("/max_level", schema_integer(1, 30), 8,
             "Refinement level no vertex exceeds; edges it stops are counted.",
             [](auto& s) -> auto& { return s.options.max_level; }),
      enum_key<S>("/trigger", kTriggers, "normal",
                  "normal: endpoint normal divergence (the paper's choice); midpoint: Greissmair & Purgathofer's "
                  "midpoint distance, with thresholds L·tan(theta/4) for an edge of length L, or the tolerances below.",
                  [](auto& s) -> auto& { return s.options.trigger; }),
      enum_key<S>("/split", kSplits, "edge",
                  "edge: split the edge that triggered (the paper). longest: first split a longer edge of a face on "
                  "it (Rivara's longest-edge bisection), so repeated refinement of one spot makes no sliver fans; the "
                  "mesh then follows a distance tolerance with fewer faces.",
                  [](auto& s) -> auto& { return s.options.longest_edge_first; }),
      key<S>("/tolerance", schema_number(0), nullptr,
             "Midpoint trigger: refine an edge whose chord midpoint stands farther than this from the true deformed "
             "surface (a length: bounds the distance to the true surface instead of angles).",
             [](auto& s) -> auto& { return s.options.tolerance; }),
      key<S>("/tolerance_min", schema_number(0), nullptr,
             "Midpoint trigger with a tolerance: decimate below this distance (default tolerance / 2).",
             [](auto& s) -> auto& { return s.options.tolerance_min; }),
  }};
}

void RemeshStep::check(ScriptChecks& checks) const {
  const std::string& p = pointer;
  const RemeshOptions& o = options;
  if (!(o.theta_min_deg < o.theta_max_deg))
    checks.fail(p + "/theta_min_deg", "must be below theta_max_deg, or refinement and decimation would undo each other");
  if (o.l_max && !(*o.l_max > 0)) checks.fail(p + "/l_max", "must be a positive length or \"auto\"");
  if ((o.tolerance || o.tolerance_min) && o.trigger != RemeshTrigger::Midpoint)
    checks.fail(p + "/tolerance", "a distance tolerance goes with \"trigger\": \"midpoint\"");
  if (o.tolerance_min && !o.tolerance) checks.fail(p + "/tolerance_min", "give tolerance too");
  if (o.tolerance && !(*o.tolerance > 0)) checks.fail(p + "/tolerance", "must be a positive length");
  if (o.tolerance_min && !(*o.tolerance_min < *o.tolerance))
    checks.fail(p + "/tolerance_min", "must be below tolerance, or refinement and decimation would undo each other");
  if (!o.l_max && checks.deformers.empty())
    checks.fail(p + "/l_max", "\"auto\" takes the smallest lattice cell, but no lattice is created before this step");
}

// What the remesher did with each attribute the mesh carries (adaptive_remesher.cpp):
// a new vertex's colour, and a new corner's UV and file normal, come from the split edge's
// ends; OBJ groups, materials and smoothing are per face, and the faces a split makes
// inherit them. What the file it was read from holds beyond these cannot follow a change
// of connectivity: it is named here, and warned about when the output is written.
nlohmann::ordered_json attribute_policy(const Mesh& mesh) {
  nlohmann::ordered_json interpolated = nlohmann::ordered_json::array(), kept = nlohmann::ordered_json::array();
  interpolated.push_back("positions (a new vertex: the edge's rest-space midpoint, through every warp)");
  if (mesh.has_uvs()) interpolated.push_back("uv (a new corner: the mean of the edge's two corners)");
  if (mesh.has_file_normals())
    interpolated.push_back("file normals (a new corner: the normalized mean of the edge's two corners)");
  if (!mesh.colors().empty()) interpolated.push_back("vertex colors (a new vertex: the mean of the edge's ends)");
  // The format read (a mesh made from arrays, or a run's result, may have no file).
  const std::optional<MeshFormat> from =
      has_mesh_extension(mesh.source()) ? std::optional<MeshFormat>(mesh_format(mesh.source())) : std::nullopt;
  if (from == MeshFormat::Obj && !mesh.groups().empty())
    kept.push_back("OBJ groups, materials and smoothing groups (per face, inherited)");
  std::string dropped;
  if (from == MeshFormat::Gltf || from == MeshFormat::Glb)
    dropped = "a glTF output is one plain primitive: the source's nodes, materials and attributes other than "
              "positions and normals are not kept";
  else if (from)
    dropped = unwritten_data(mesh, *from);
  return {{"interpolated", interpolated},
          {"kept", kept},
          {"dropped", dropped.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(dropped)}};
}

void RemeshStep::run(Scene& scene, StepContext& ctx) const {
  require_surface_mesh(scene.mesh, "remesh");
  const RemeshStats stats = adaptive_remesh(scene.mesh, scene.halfedges, scene.stack, options, ctx.progress);
  ctx.stats["attributes"] = attribute_policy(scene.mesh);
  ctx.stats["l_max"] = stats.l_max;
  ctx.stats["trigger"] = name_of(kTriggers, options.trigger);
  ctx.stats["split"] = name_of(kSplits, options.longest_edge_first);
  ctx.stats["triangulated_faces"] = stats.triangulated_faces;
  ctx.stats["edges_tested"] = stats.edges_tested;
  ctx.stats["refinements"] = stats.refinements;
  ctx.stats["decimations"] = stats.decimations;
  ctx.stats["max_level_hits"] = stats.max_level_hits;
  ctx.stats["faces_before"] = stats.faces_before;
  ctx.stats["faces_after"] = stats.faces_after;
  ctx.stats["highest_level"] = stats.highest_level;
  ctx.stats["ms_test"] = stats.ms_test;
  ctx.stats["ms_refine"] = stats.ms_refine;
  ctx.stats["ms_decimate"] = stats.ms_decimate;
  if (stats.triangulated_faces)
    scene.warnings.push_back(ctx.pointer + ": " + format_count(stats.triangulated_faces) +
                             " polygon faces were triangulated (refinement works on triangles)");
  if (stats.max_level_hits)
    scene.warnings.push_back(ctx.pointer + ": max_level " + std::to_string(options.max_level) + " stopped " +
                             format_count(stats.max_level_hits) + " refinements");
  ctx.summary = "remesh: " + format_count(stats.refinements) + " refinements, " + format_count(stats.decimations) +
                " decimations, faces " + format_count(stats.faces_before) + " -> " + format_count(stats.faces_after) +
                ", highest level " + std::to_string(stats.highest_level);
}

}  // namespace

const OpInfo& remesh_op() {
  static const OpDecl<RemeshStep> op{"remesh",
                                     "Adaptive refinement and reversible decimation after the deformations so far "
                                     "(Gain & Dodgson section 4). Polygon faces are triangulated first.",
                                     remesh_keys()};
  return op;
}

}  // namespace ffd
