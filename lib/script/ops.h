// The op table: each script op's check (before any work) and run (on the scene).
// Adding an op: write its two functions in an ops_*.cpp file, list it in op_table()
// (ops.cpp), and add its schema (schema.cpp).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "script/scene.h"
#include "script/script_checks.h"

namespace ffd {

struct Op {
  const char* name;
  /// Cross-step checks on the schema-checked step (names, index ranges, files).
  void (*check)(ScriptChecks& checks, const nlohmann::json& step, const std::string& pointer);
  /// Does the step. Throws InputError for what only the mesh reveals (an empty pick).
  void (*run)(Scene& scene, const nlohmann::json& step, StepContext& ctx);
};

const std::vector<Op>& op_table();
/// The op called `name` (the schema guarantees it exists).
const Op& find_op(const std::string& name);

// FFD ops (ops_ffd.cpp)
void check_lattice(ScriptChecks&, const nlohmann::json&, const std::string&);
void run_lattice(Scene&, const nlohmann::json&, StepContext&);
void check_move(ScriptChecks&, const nlohmann::json&, const std::string&);
void run_move(Scene&, const nlohmann::json&, StepContext&);
void check_drag(ScriptChecks&, const nlohmann::json&, const std::string&);
void run_drag(Scene&, const nlohmann::json&, StepContext&);
// Adaptive remeshing (ops_remesh.cpp)
void check_remesh(ScriptChecks&, const nlohmann::json&, const std::string&);
void run_remesh(Scene&, const nlohmann::json&, StepContext&);
// Boundary-constraint modeling ops (ops_bcm.cpp)
void check_bcm(ScriptChecks&, const nlohmann::json&, const std::string&);
void run_bcm(Scene&, const nlohmann::json&, StepContext&);
void check_transform(ScriptChecks&, const nlohmann::json&, const std::string&);
void run_transform(Scene&, const nlohmann::json&, StepContext&);
// Output ops (ops_save.cpp)
void check_save(ScriptChecks&, const nlohmann::json&, const std::string&);
void run_save(Scene&, const nlohmann::json&, StepContext&);

/// A transform step's save pattern for frame i: each "{i}" replaced by i.
std::string frame_path(const std::string& pattern, std::size_t i);

/// Writes the scene's current mesh to `relative` (inside the output folder) as a staged
/// file committed at the end of the run, with `options` (Scene::write_options() and
/// any replacement colours); returns the bytes written.
std::size_t stage_mesh(Scene& scene, const std::string& relative, const WriteOptions& options);
/// The same with the scene's own write options.
inline std::size_t stage_mesh(Scene& scene, const std::string& relative) {
  return stage_mesh(scene, relative, scene.write_options());
}

}  // namespace ffd
