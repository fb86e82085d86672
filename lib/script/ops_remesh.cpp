// The remesh op: adaptive refinement and decimation (Gain & Dodgson section 4).
#include <cmath>

#include "common/errors.h"
#include "common/numbers.h"
#include "remesh/adaptive_remesher.h"
#include "script/ops.h"

namespace ffd {

void check_remesh(ScriptChecks& checks, const nlohmann::json& step, const std::string& p) {
  if (!(step["theta_min_deg"].get<double>() < step["theta_max_deg"].get<double>()))
    checks.fail(p + "/theta_min_deg", "must be below theta_max_deg, or refinement and decimation would undo each other");
  if (step["l_max"].is_number() && !(step["l_max"].get<double>() > 0))
    checks.fail(p + "/l_max", "must be a positive length or \"auto\"");
  if ((step.contains("tolerance") || step.contains("tolerance_min")) && step["trigger"] != "midpoint")
    checks.fail(p + "/tolerance", "a distance tolerance goes with \"trigger\": \"midpoint\"");
  if (step.contains("tolerance_min") && !step.contains("tolerance"))
    checks.fail(p + "/tolerance_min", "give tolerance too");
  if (step.contains("tolerance") && !(step["tolerance"].get<double>() > 0))
    checks.fail(p + "/tolerance", "must be a positive length");
  if (step.contains("tolerance_min") && !(step["tolerance_min"].get<double>() < step["tolerance"].get<double>()))
    checks.fail(p + "/tolerance_min", "must be below tolerance, or refinement and decimation would undo each other");
  if (step["l_max"] == "auto" && checks.lattices.empty())
    checks.fail(p + "/l_max", "\"auto\" takes the smallest lattice cell, but no lattice is created before this step");
}

void run_remesh(Scene& scene, const nlohmann::json& step, StepContext& ctx) {
  RemeshOptions options;
  options.theta_max_deg = step["theta_max_deg"];
  options.theta_min_deg = step["theta_min_deg"];
  if (step["l_max"].is_number()) options.l_max = step["l_max"].get<double>();
  options.max_level = step["max_level"];
  options.trigger = step["trigger"] == "midpoint" ? RemeshTrigger::Midpoint : RemeshTrigger::Normal;
  options.longest_edge_first = step["split"] == "longest";
  if (step.contains("tolerance")) options.tolerance = step["tolerance"].get<double>();
  if (step.contains("tolerance_min")) options.tolerance_min = step["tolerance_min"].get<double>();
  RemeshStats stats;
  try {
    stats = adaptive_remesh(scene.mesh, scene.stack, options);
  } catch (const InputError& e) {
    throw InputError(scene.script_path + ": " + ctx.pointer + "/l_max: " + e.what());
  }
  ctx.stats["l_max"] = stats.l_max;
  ctx.stats["trigger"] = step["trigger"];
  ctx.stats["split"] = step["split"];
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

}  // namespace ffd
