// The boundary-constraint modeling ops (Botsch & Kobbelt): bcm sets an editor up on the
// (baked) surface, transform moves one of its handles through one or many poses.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bcm/bcm_editor.h"
#include "common/errors.h"
#include "common/numbers.h"
#include "common/timer.h"
#include "mesh/file_normals.h"
#include "mesh/vertex_normals.h"
#include "script/ops.h"
#include "script/transform.h"

namespace ffd {

void BcmEditorDelete::operator()(BcmEditor* editor) const { delete editor; }

namespace {

using json = nlohmann::json;

std::string quoted_list(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", '" : "'") + names[i] + "'";
  return out;
}

// A surface edit acts on the deformed surface: freeze the warp stack into it first.
nlohmann::ordered_json bake_stack(Scene& scene, const std::string& pointer) {
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  if (scene.stack.size() == 0) return names;
  for (const std::string& name : scene.stack.bake(scene.mesh)) {
    scene.baked[name] = pointer;
    scene.lattices.erase(name);
    names.push_back(name);
  }
  return names;
}

void warn_baked(Scene& scene, const nlohmann::ordered_json& baked, const StepContext& ctx) {
  if (baked.empty()) return;
  std::vector<std::string> names;
  for (const auto& name : baked) names.push_back(name.get<std::string>());
  scene.warnings.push_back(ctx.pointer + ": " + (names.size() == 1 ? "lattice " : "lattices ") + quoted_list(names) +
                           (names.size() == 1 ? " was" : " were") +
                           " frozen into the mesh for this surface edit; later steps cannot move " +
                           (names.size() == 1 ? "it" : "them"));
}

LaplacianKind laplacian_kind(const std::string& name) {
  if (name == "uniform") return LaplacianKind::Uniform;
  if (name == "anisotropic") return LaplacianKind::Anisotropic;
  return LaplacianKind::Cotan;
}


std::string ms_text(double ms) {
  char buf[32];
  std::snprintf(buf, sizeof buf, ms < 1 ? "%.3f ms" : "%.1f ms", ms);
  return buf;
}

// The rotation by the least angle taking unit vector a to unit vector b (identity when
// either is zero; a half turn about an axis normal to a when they are opposite).
Eigen::Matrix3d rotation_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (!(a.squaredNorm() > 0) || !(b.squaredNorm() > 0)) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d u = a.normalized(), v = b.normalized();
  const Eigen::Vector3d axis = u.cross(v);
  const double c = u.dot(v);
  if (c < -1 + 1e-12) {  // opposite: half a turn about any axis normal to u
    const Eigen::Vector3d w = (std::abs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(u).normalized();
    return 2 * w * w.transpose() - Eigen::Matrix3d::Identity();
  }
  // Rodrigues: R = I + [axis]× + [axis]×² / (1 + c), with |axis| = sin θ.
  Eigen::Matrix3d k;
  k << 0, -axis.z(), axis.y(), axis.z(), 0, -axis.x(), -axis.y(), axis.x(), 0;
  return Eigen::Matrix3d::Identity() + k + k * k / (1 + c);
}

// After an edit: fresh (angle-weighted) normals at the vertices whose faces moved, and
// the file normals there turned by the same rotation as their vertex normal, so that a
// mesh's own normals (OBJ vn) follow the surface. Vertices elsewhere keep theirs.
void refresh_normals(Scene& scene, const BcmEditor& editor, Eigen::Matrix3Xd& fresh) {
  Mesh& mesh = scene.mesh;
  compute_vertex_normals(mesh, mesh.positions(), fresh);
  const std::vector<std::uint32_t>& ids = editor.normal_vertices();
  auto normals = mesh.normals();
  auto rest_normals = mesh.rest_normals();
  if (mesh.has_file_normals()) {
    std::vector<std::int32_t> slot(mesh.num_vertices(), -1);
    std::vector<Eigen::Matrix3d> turn(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
      slot[ids[i]] = static_cast<std::int32_t>(i);
      turn[i] = rotation_between(normals.col(ids[i]), fresh.col(ids[i]));
    }
    bake_file_normals(mesh, [&](std::uint32_t v, const Eigen::Vector3d& n) -> Eigen::Vector3d {
      return slot[v] < 0 ? n : Eigen::Vector3d(turn[static_cast<std::size_t>(slot[v])] * n);
    });
  }
  for (std::uint32_t v : ids) normals.col(v) = rest_normals.col(v) = fresh.col(v);
}

}  // namespace

std::string frame_path(const std::string& pattern, std::size_t i) {
  std::string out;
  for (std::size_t at = 0; at < pattern.size();) {
    if (pattern.compare(at, 3, "{i}") == 0) {
      out += std::to_string(i);
      at += 3;
    } else {
      out += pattern[at++];
    }
  }
  return out;
}

void check_bcm(ScriptChecks& checks, const json& step, const std::string& p) {
  const std::string name = step["name"];
  const int k = step["k"];
  if (step.contains("continuity"))
    for (const char* side : {"outer", "inner"}) {
      if (!step["continuity"].contains(side)) continue;
      const double c = step["continuity"][side];
      if (c > k - 1)
        checks.fail(p + "/continuity/" + side, "must be at most k - 1 = " + std::to_string(k - 1) + " for k = " +
                                                   std::to_string(k) + " (C^" + std::to_string(k - 1) +
                                                   " is the smoothest boundary Δ^k can hold), found " +
                                                   format_number(c));
    }
  checks.check_selection_files(step["support"], p + "/support");
  std::vector<std::string> names;
  for (std::size_t j = 0; j < step["handles"].size(); ++j) {
    const json& handle = step["handles"][j];
    const std::string at = p + "/handles/" + std::to_string(j);
    const std::string handle_name = handle["name"];
    if (std::find(names.begin(), names.end(), handle_name) != names.end())
      checks.fail(at + "/name", "editor '" + name + "' already has a handle named '" + handle_name + "'");
    names.push_back(handle_name);
    checks.check_selection_files(handle["select"], at + "/select");
  }
  checks.editors.insert(name);
  checks.editor_handles[name] = names;
}

void run_bcm(Scene& scene, const json& step, StepContext& ctx) {
  const std::string name = step["name"];
  const nlohmann::ordered_json baked = bake_stack(scene, ctx.pointer);
  const auto positions = scene.mesh.positions();
  const std::vector<std::uint32_t> support =
      select_vertices(step["support"], positions, scene.selection_context(ctx.pointer + "/support"));
  std::vector<BcmHandle> handles;
  for (std::size_t j = 0; j < step["handles"].size(); ++j) {
    const json& handle = step["handles"][j];
    const std::string at = ctx.pointer + "/handles/" + std::to_string(j) + "/select";
    handles.push_back({handle["name"], select_vertices(handle["select"], positions, scene.selection_context(at))});
  }
  BcmOptions options;
  options.k = step["k"];
  if (step.contains("continuity")) {
    options.outer_continuity = step["continuity"].value("outer", -1.0);
    options.inner_continuity = step["continuity"].value("inner", -1.0);
  }
  options.laplacian = laplacian_kind(step["laplacian"]);
  options.detail = step["detail"];

  std::unique_ptr<BcmEditor, BcmEditorDelete> editor;
  try {
    editor.reset(new BcmEditor(scene.mesh, support, handles, options));
  } catch (const BcmInputError& e) {
    throw InputError(scene.script_path + ": " + ctx.pointer + e.key() + ": " + e.what());
  }
  const BcmEditor::Stats& s = editor->stats();
  const BcmOptions& used = editor->options();
  ctx.stats["editor"] = name;
  ctx.stats["k"] = used.k;
  ctx.stats["laplacian"] = step["laplacian"];
  ctx.stats["continuity"] = {{"outer", used.outer_continuity}, {"inner", used.inner_continuity}};
  ctx.stats["detail"] = used.detail;
  ctx.stats["support_vertices"] = support.size();
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
  ctx.stats["baked_lattices"] = baked;
  ctx.summary = "bcm '" + name + "': k=" + std::to_string(used.k) + " " + step["laplacian"].get<std::string>() +
                (used.detail ? " with detail" : "") + ", " + format_count(s.free_vertices) + " free / " +
                format_count(s.handle_vertices) + " handle / " + format_count(s.fixed_vertices) +
                " fixed vertices; factorized in " + ms_text(s.factor_ms) + " (" + s.solver + "), basis in " +
                ms_text(s.basis_ms);
  warn_baked(scene, baked, ctx);
  scene.editors[name] = std::move(editor);
}

void check_transform(ScriptChecks& checks, const json& step, const std::string& p) {
  const std::string name = step["editor"];
  if (!checks.editors.count(name)) checks.fail(p + "/editor", "no bcm editor named '" + name + "' is set up before this step");
  const std::vector<std::string>& handles = checks.editor_handles[name];
  if (step.contains("handle")) {
    const std::string handle = step["handle"];
    if (std::find(handles.begin(), handles.end(), handle) == handles.end())
      checks.fail(p + "/handle", "editor '" + name + "' has no handle named '" + handle + "' (its handles: " +
                                     quoted_list(handles) + ")");
  } else if (handles.size() > 1) {
    checks.fail(p, "missing key 'handle': editor '" + name + "' has " + std::to_string(handles.size()) +
                       " handles (" + quoted_list(handles) + ")");
  }
  Transform t;
  if (step.contains("transform") && !parse_transform(step["transform"], t))
    checks.fail(p + "/transform/rotate/axis", "the rotation axis is zero");
  std::size_t frames = 1;
  if (step.contains("frames")) {
    frames = step["frames"].size();
    for (std::size_t i = 0; i < frames; ++i)
      if (!parse_transform(step["frames"][i], t))
        checks.fail(p + "/frames/" + std::to_string(i) + "/rotate/axis", "the rotation axis is zero");
  }
  if (step.contains("save")) {
    const std::string pattern = step["save"];
    checks.check_output_path(pattern, p + "/save");
    if (frames > 1 && pattern.find("{i}") == std::string::npos)
      checks.fail(p + "/save", "'" + pattern + "' has no '{i}', so all " + std::to_string(frames) +
                                   " frames would be saved to the same file");
  }
}

void run_transform(Scene& scene, const json& step, StepContext& ctx) {
  const std::string name = step["editor"];
  BcmEditor& editor = *scene.editors.at(name);
  const std::string place = scene.script_path + ": " + ctx.pointer + "/editor: ";
  if (scene.mesh.topology_version() != editor.topology_version())
    throw InputError(place + "a step after editor '" + name +
                     "' was set up changed the mesh's connectivity (remeshing), so its vertex sets no longer "
                     "apply; set the editor up again with a bcm step after that step");
  const nlohmann::ordered_json baked = bake_stack(scene, ctx.pointer);
  const long changed = editor.changed_vertex(scene.mesh.positions());
  if (changed >= 0)
    throw InputError(place + "vertex " + std::to_string(changed) + ", which editor '" + name +
                     "' holds or moves, was moved by a step after the editor was set up; set the editor up "
                     "again with a bcm step after that step");
  const std::size_t h = step.contains("handle") ? editor.handle_index(step["handle"]) : 0;

  std::vector<const json*> frames;
  if (step.contains("frames"))
    for (const json& frame : step["frames"]) frames.push_back(&frame);
  else
    frames.push_back(&step["transform"]);
  const std::string pattern = step.value("save", "");
  Eigen::Matrix3Xd fresh(3, static_cast<Eigen::Index>(scene.mesh.num_vertices()));
  double update_ms = 0, save_ms = 0;
  std::size_t bytes = 0;
  nlohmann::ordered_json saved = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    Transform t;
    parse_transform(*frames[i], t);  // checked before the run
    // A pose relative to setup: x -> c + R·S·(x − c) + translate, c the handle's centroid
    // at setup unless given.
    const Eigen::Vector3d center = t.center ? *t.center : editor.handle_centroid(h);
    const Eigen::Matrix3d linear = t.linear();
    editor.set_pose(h, linear, center + t.translate - linear * center);
    Stopwatch clock;
    editor.update(scene.mesh.positions());
    update_ms += clock.ms();
    if (!pattern.empty()) {
      Stopwatch save_clock;
      refresh_normals(scene, editor, fresh);
      const std::string path = frame_path(pattern, i);
      bytes += stage_mesh(scene, path);
      saved.push_back(path);
      save_ms += save_clock.ms();
    }
  }
  if (pattern.empty()) refresh_normals(scene, editor, fresh);
  // No warp is left (the stack was baked), so the edit is the rest state too.
  auto positions = scene.mesh.positions();
  auto rest = scene.mesh.rest_positions();
  for (std::uint32_t v : editor.moved_vertices()) rest.col(v) = positions.col(v);
  editor.remember(positions);

  const double per_frame = update_ms / static_cast<double>(frames.size());
  ctx.stats["editor"] = name;
  ctx.stats["handle"] = editor.handle_name(h);
  ctx.stats["frames"] = frames.size();
  ctx.stats["vertices_moved"] = editor.moved_vertices().size();
  ctx.stats["frame_ms"] = per_frame;  // mean per frame
  ctx.stats["update_ms"] = update_ms;
  ctx.stats["saved"] = saved;
  ctx.stats["saved_bytes"] = bytes;
  ctx.stats["save_ms"] = save_ms;
  ctx.stats["baked_lattices"] = baked;
  ctx.summary = "transform '" + name + "' handle '" + editor.handle_name(h) + "': " + format_count(frames.size()) +
                (frames.size() == 1 ? " frame, " : " frames, ") + ms_text(per_frame) + " per frame, " +
                format_count(editor.moved_vertices().size()) + " vertices moved" +
                (saved.empty() ? std::string()
                               : ", saved " + saved.front().get<std::string>() +
                                     (saved.size() > 1 ? " .. " + saved.back().get<std::string>() : std::string()));
  warn_baked(scene, baked, ctx);
}

}  // namespace ffd
