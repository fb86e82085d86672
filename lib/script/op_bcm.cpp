// The bcm op: sets up a boundary-constraint modeling editor (Botsch & Kobbelt) on the
// (baked) surface; transform steps then move its handles.
#include <algorithm>

#include "bcm/bcm_editor.h"
#include "common/numbers.h"
#include "script/op.h"
#include "script/selection.h"
#include "script/surface_edits.h"

namespace ffd {
namespace {

const std::vector<std::pair<std::string, LaplacianKind>> kLaplacians = {{"cotan", LaplacianKind::Cotan},
                                                                       {"cotan_positive", LaplacianKind::CotanPositive},
                                                                       {"uniform", LaplacianKind::Uniform},
                                                                       {"anisotropic", LaplacianKind::Anisotropic}};

struct HandleSpec {
  std::string name;
  Selection select;
};

struct BcmStep final : Step {
  std::string name;
  Selection support;
  std::vector<HandleSpec> handles;
  BcmOptions options;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
  void report(const BcmData& bcm, std::size_t support_size, StepContext& ctx) const;
};

KeyTable<HandleSpec> handle_keys() {
  using H = HandleSpec;
  return {{key<H>("/name", schema_text(), nullptr, "Name used by transform steps.",
                  [](auto& h) -> auto& { return h.name; })
               .required(),
           key<H>("/select", schema_ref("selection"), nullptr, "The handle's vertices; all inside the support.",
                  [](auto& h) -> auto& { return h.select; })
               .required()}};
}

KeyTable<BcmStep> bcm_keys() {
  using S = BcmStep;
  return {{
      key<S>("/name", schema_text(), nullptr,
             "Name used by transform steps; a later bcm step with the same name replaces the editor.",
             [](auto& s) -> auto& { return s.name; })
          .required(),
      key<S>("/support", schema_ref("selection"), nullptr,
             "The vertices the edit may move, handles included; every other vertex stays fixed.",
             [](auto& s) -> auto& { return s.support; })
          .required()
          .about("support"),
      list_key<S>("/handles", handle_keys(),
                  "Handle regions inside the support, each moved as a whole by a 9-dof transform; a handle never "
                  "moved holds its part of the surface in place.",
                  [](auto& s) -> auto& { return s.handles; })
          .required()
          .about("handles", "/select"),
      key<S>("/k", schema_integer(1, 3), 3,
             "Order of Δ^k p = 0: 1 membrane (least area), 2 thin plate (least bending), 3 least curvature variation.",
             [](auto& s) -> auto& { return s.options.k; })
          .about("k"),
      group_key<S>("/continuity",
                   "Boundary smoothness c in [0, k-1], blended continuously (C^0 hinged .. C^(k-1) clamped); each "
                   "defaults to k-1."),
      key<S>("/continuity/outer", schema_number(0, 2), nullptr, "At the support's boundary with the fixed surface.",
             [](auto& s) -> auto& { return s.options.outer_continuity; })
          .about("outer_continuity"),
      key<S>("/continuity/inner", schema_number(0, 2), nullptr, "At the handles' boundaries.",
             [](auto& s) -> auto& { return s.options.inner_continuity; })
          .about("inner_continuity"),
      enum_key<S>("/laplacian", kLaplacians, "cotan",
                  "cotan: the paper's operator (eq. 4), cotangent weights with mixed Voronoi areas on the surface "
                  "at setup, negative weights of non-Delaunay edges kept; the same operator as CGAL's fair and "
                  "libigl's harmonic. cotan_positive: the same with negative weights set to zero, a graph Laplacian "
                  "with a discrete maximum principle (for k = 1 each free vertex stays in the convex hull of its "
                  "neighbours), at the cost of the paper's energy and of linear precision on non-Delaunay "
                  "triangles. uniform: 1/valence. anisotropic: standard cotangent weights on the support's conformal "
                  "map scaled to equal diameters, so an elongated support bends with even slope (needs a "
                  "disk-shaped support).",
                  [](auto& s) -> auto& { return s.options.laplacian; })
          .about("laplacian"),
      key<S>("/detail", schema_boolean(), true,
             "Multiresolution: edit the support's smooth base (its BCM fairing) and carry the surface detail along "
             "as displacements in the base's local frames. false: the support becomes the plain BCM surface.",
             [](auto& s) -> auto& { return s.options.detail; }),
  }};
}

void BcmStep::check(ScriptChecks& checks) const {
  const int k = options.k;
  for (const auto& [side, c] : {std::pair<const char*, double>{"outer", options.outer_continuity},
                                std::pair<const char*, double>{"inner", options.inner_continuity}})
    if (c > k - 1)
      checks.fail(pointer + "/continuity/" + side,
                  "must be at most k - 1 = " + std::to_string(k - 1) + " for k = " + std::to_string(k) + " (C^" +
                      std::to_string(k - 1) + " is the smoothest boundary Δ^k can hold), found " + format_number(c));
  std::vector<std::string> names;
  for (std::size_t j = 0; j < handles.size(); ++j) {
    if (std::find(names.begin(), names.end(), handles[j].name) != names.end())
      checks.fail(pointer + "/handles/" + std::to_string(j) + "/name",
                  "editor '" + name + "' already has a handle named '" + handles[j].name + "'");
    names.push_back(handles[j].name);
  }
  checks.editor_handles[name] = names;
  check_vertex_selection(support);
  for (const HandleSpec& handle : handles) check_vertex_selection(handle.select);
}

void BcmStep::run(Scene& scene, StepContext& ctx) const {
  require_surface_mesh(scene.mesh, "bcm");
  const nlohmann::ordered_json baked = bake_stack(scene, ctx.pointer);
  const auto positions = scene.mesh.positions();
  const std::vector<std::uint32_t> support_vertices = select_vertices(support, positions);
  std::vector<BcmHandle> picked;
  for (const HandleSpec& handle : handles) picked.push_back({handle.name, select_vertices(handle.select, positions)});
  auto editor =
      make_surface_editor(scene.mesh, bcm_precompute(scene.mesh, support_vertices, picked, options, ctx.progress));
  report(editor->bcm, support_vertices.size(), ctx);
  ctx.stats["baked_lattices"] = baked;
  warn_baked(scene, baked, ctx);
  scene.editors[name] = std::move(editor);
}

void BcmStep::report(const BcmData& bcm, std::size_t support_size, StepContext& ctx) const {
  const BcmStats& s = bcm.stats;
  const BcmOptions& used = bcm.options;
  const std::string laplacian = name_of(kLaplacians, options.laplacian);
  ctx.stats["editor"] = name;
  ctx.stats["k"] = used.k;
  ctx.stats["laplacian"] = laplacian;
  ctx.stats["continuity"] = {{"outer", used.outer_continuity}, {"inner", used.inner_continuity}};
  ctx.stats["detail"] = used.detail;
  ctx.stats["support_vertices"] = support_size;
  ctx.stats["free_vertices"] = s.free_vertices;
  ctx.stats["handle_vertices"] = s.handle_vertices;
  ctx.stats["fixed_vertices"] = s.fixed_vertices;
  ctx.stats["handles"] = handles.size();
  ctx.stats["solver"] = s.solver;
  ctx.stats["symmetric"] = s.symmetric;
  ctx.stats["system_nonzeros"] = s.system_nonzeros;
  ctx.stats["factor_nonzeros"] = s.factor_nonzeros;
  ctx.stats["regions_ms"] = s.regions_ms;
  ctx.stats["laplacian_ms"] = s.laplacian_ms;
  ctx.stats["system_ms"] = s.system_ms;
  ctx.stats["factorization_ms"] = s.factor_ms;
  ctx.stats["basis_ms"] = s.basis_ms;
  ctx.stats["detail_ms"] = s.detail_ms;
  ctx.summary = "bcm '" + name + "': k=" + std::to_string(used.k) + " " + laplacian +
                (used.detail ? " with detail" : "") + ", " + format_count(s.free_vertices) + " free / " +
                format_count(s.handle_vertices) + " handle / " + format_count(s.fixed_vertices) +
                " fixed vertices; factorized in " + format_ms(s.factor_ms) + " (" + s.solver + "), basis in " +
                format_ms(s.basis_ms);
}

}  // namespace

const OpInfo& bcm_op() {
  static const OpDecl<BcmStep> op{
      "bcm",
      "Sets up a boundary-constraint modeling editor (Botsch & Kobbelt): the support bends as the solution of "
      "Δ^k p = 0 between the fixed surface around it and its handles, which transform steps then move. Bakes the "
      "warp stack into the mesh first; factorizes and precomputes the handles' basis functions once.",
      bcm_keys()};
  return op;
}

}  // namespace ffd
