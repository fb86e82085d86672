// The transform op: poses a bcm editor's handle, once (`transform`) or as a sequence of
// frames (`frames`, each saved with a `{i}` pattern), each pose one small dense product.
#include <omp.h>

#include <cmath>

#include "common/numbers.h"
#include "common/thread_choice.h"
#include "common/timer.h"
#include "mesh/file_normals.h"
#include "mesh/vertex_normals.h"
#include "script/op.h"
#include "script/output_files.h"
#include "script/surface_edits.h"

namespace ffd {
namespace {

struct TransformStep final : Step {
  std::string editor;
  std::optional<std::string> handle;
  std::optional<Transform> transform;
  std::vector<Transform> frames;
  std::optional<std::string> save;

  void check(ScriptChecks& checks) const override;
  std::vector<OutputFile> outputs() const override;
  void run(Scene& scene, StepContext& ctx) const override;
  SurfaceEditor& editor_to_pose(Scene& scene) const;
  void report(const SurfaceEditor& target, std::size_t h, double update_ms, const nlohmann::ordered_json& saved,
              StepContext& ctx) const;
  std::size_t frame_count() const { return frames.empty() ? 1 : frames.size(); }
};

KeyTable<TransformStep> transform_keys() {
  using S = TransformStep;
  const nlohmann::json frame_list = {{"type", "array"}, {"minItems", 1}, {"items", schema_ref("transform")}};
  return {{key<S>("/editor", schema_text(), nullptr, "Name of a bcm editor set up earlier.",
                  [](auto& s) -> auto& { return s.editor; })
               .required()
               .about("editor"),
           key<S>("/handle", schema_text(), nullptr, "Name of the editor's handle; may be left out when it has only one.",
                  [](auto& s) -> auto& { return s.handle; }),
           key<S>("/transform", schema_ref("transform"), nullptr, "The handle's pose.",
                  [](auto& s) -> auto& { return s.transform; }),
           key<S>("/frames", frame_list, nullptr, "Poses applied in order; the handle keeps the last.",
                  [](auto& s) -> auto& { return s.frames; }),
           key<S>("/save", schema_text(), nullptr,
                  "Writes the mesh after every frame, '{i}' replaced by the frame's index (0-based); relative to the "
                  "output folder.",
                  [](auto& s) -> auto& { return s.save; })},
          {{"transform"}, {"frames"}}};
}

void TransformStep::check(ScriptChecks& checks) const {
  const auto it = checks.editor_handles.find(editor);
  if (it == checks.editor_handles.end())
    checks.fail(pointer + "/editor", "no bcm editor named '" + editor + "' is set up before this step");
  const std::vector<std::string>& handles = it->second;
  if (handle) {
    if (std::find(handles.begin(), handles.end(), *handle) == handles.end())
      checks.fail(pointer + "/handle", "editor '" + editor + "' has no handle named '" + *handle +
                                           "' (its handles: " + quoted_list(handles) + ")");
  } else if (handles.size() > 1) {
    checks.fail(pointer, "missing key 'handle': editor '" + editor + "' has " + std::to_string(handles.size()) +
                             " handles (" + quoted_list(handles) + ")");
  }
  if (save && frame_count() > 1 && save->find("{i}") == std::string::npos)
    checks.fail(pointer + "/save", "'" + *save + "' has no '{i}', so all " + std::to_string(frame_count()) +
                                       " frames would be saved to the same file");
}

std::vector<OutputFile> TransformStep::outputs() const {
  std::vector<OutputFile> out;
  if (save)
    for (std::size_t f = 0; f < frame_count(); ++f) out.push_back({"/save", frame_path(*save, f)});
  return out;
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
void refresh_normals(Scene& scene, const SurfaceEditor& editor, Eigen::Matrix3Xd& fresh) {
  Mesh& mesh = scene.mesh;
  compute_vertex_normals(mesh, mesh.positions(), fresh);
  const std::vector<std::uint32_t>& ids = editor.normal_vertices;
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

// The editor, after checking that no step since its setup changed what it holds.
SurfaceEditor& TransformStep::editor_to_pose(Scene& scene) const {
  SurfaceEditor& target = *scene.editors.at(editor);
  if (scene.mesh.topology_version() != target.topology_version)
    throw InputError("a step after editor '" + editor +
                         "' was set up changed the mesh's connectivity (remeshing), so its vertex sets no longer "
                         "apply; set the editor up again with a bcm step after that step",
                     {"editor"});
  return target;
}

void TransformStep::run(Scene& scene, StepContext& ctx) const {
  SurfaceEditor& target = editor_to_pose(scene);
  const nlohmann::ordered_json baked = bake_stack(scene, ctx.pointer);
  const long changed = target.changed_vertex(scene.mesh.positions());
  if (changed >= 0)
    throw InputError("vertex " + std::to_string(changed) + ", which editor '" + editor +
                         "' holds or moves, was moved by a step after the editor was set up; set the editor up "
                         "again with a bcm step after that step",
                     {"editor"});
  const std::size_t h = handle ? bcm_handle_index(target.bcm, *handle) : 0;
  const std::vector<Transform> poses = frames.empty() ? std::vector<Transform>{*transform} : frames;
  Eigen::Matrix3Xd fresh(3, static_cast<Eigen::Index>(scene.mesh.num_vertices()));
  double update_ms = 0, save_ms = 0;
  ThreadChoice threads(omp_get_max_threads());
  std::size_t bytes = 0;
  nlohmann::ordered_json saved = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    // A pose relative to setup: x -> c + R·S·(x − c) + translate, c the handle's centroid
    // at setup unless given.
    const Transform& t = poses[i];
    const Eigen::Vector3d center = t.center ? *t.center : target.bcm.centroid.at(h);
    const Eigen::Matrix3d linear = t.linear();
    bcm_set_pose(target.bcm, h, linear, center + t.translate - linear * center);
    Stopwatch clock;
    const int team = threads.next();
    bcm_pose(target.bcm, scene.mesh.positions(), team);
    const double ms = clock.ms();
    threads.record(team, ms);
    update_ms += ms;
    if (save) {
      Stopwatch save_clock;
      refresh_normals(scene, target, fresh);
      const std::string path = frame_path(*save, i);
      bytes += stage_mesh(scene, path);
      saved.push_back(path);
      save_ms += save_clock.ms();
    }
    if (ctx.progress) ctx.progress(static_cast<double>(i + 1) / static_cast<double>(poses.size()));  // frame i of n
  }
  if (!save) refresh_normals(scene, target, fresh);
  // No warp is left (the stack was baked), so the edit is the rest state too.
  auto positions = scene.mesh.positions();
  auto rest = scene.mesh.rest_positions();
  for (std::uint32_t v : target.moved) rest.col(v) = positions.col(v);
  target.remember(positions);
  report(target, h, update_ms, saved, ctx);
  ctx.stats["frames_on_one_thread"] = threads.single_runs();
  ctx.stats["saved_bytes"] = bytes;
  ctx.stats["save_ms"] = save_ms;
  ctx.stats["baked_lattices"] = baked;
  warn_baked(scene, baked, ctx);
}

void TransformStep::report(const SurfaceEditor& target, std::size_t h, double update_ms,
                           const nlohmann::ordered_json& saved, StepContext& ctx) const {
  const std::size_t count = frame_count();
  const double per_frame = update_ms / static_cast<double>(count);
  ctx.stats["editor"] = editor;
  ctx.stats["handle"] = target.bcm.names.at(h);
  ctx.stats["frames"] = count;
  ctx.stats["vertices_moved"] = target.moved.size();
  ctx.stats["frame_ms"] = per_frame;  // mean per frame
  ctx.stats["update_ms"] = update_ms;
  ctx.stats["saved"] = saved;
  ctx.summary = "transform '" + editor + "' handle '" + target.bcm.names.at(h) + "': " + format_count(count) +
                (count == 1 ? " frame, " : " frames, ") + format_ms(per_frame) + " per frame, " +
                format_count(target.moved.size()) + " vertices moved" +
                (saved.empty() ? std::string()
                               : ", saved " + saved.front().get<std::string>() +
                                     (saved.size() > 1 ? " .. " + saved.back().get<std::string>() : std::string()));
}

}  // namespace

const OpInfo& transform_op() {
  static const OpDecl<TransformStep> op{
      "transform",
      "Moves a handle of a bcm editor: one pose (`transform`) or a sequence (`frames`), each costing one small dense "
      "product. A pose is relative to where the handle was when the editor was set up; `center` defaults to the "
      "handle's centroid then.",
      transform_keys()};
  return op;
}

}  // namespace ffd
