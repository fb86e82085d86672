// Ops: what a script's steps can do. Each op is declared once, in its own file
// lib/script/op_NAME.cpp, by a typed step (a struct deriving from Step that holds the
// options its algorithm takes) and the key table that fills it (step_keys.h). From that
// declaration come the step's parser, its part of the JSON Schema, `validate --resolved`'s
// defaults, its section of `ffdtool schema --markdown`, and the placing of errors.
//
// Adding an op is one new file plus one registration line:
// 1. lib/script/op_NAME.cpp (CMake picks up lib/script/op_*.cpp) defining
//      const OpInfo& NAME_op() { static const OpDecl<NameStep> op{"NAME", "doc", table}; return op; }
// 2. the line FFD_OP(NAME_op) in lib/script/op_list.h.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "script/scene.h"
#include "script/script_checks.h"
#include "script/step_keys.h"

namespace ffd {

class OpInfo;

/// A file a step will write: its path relative to the output folder, the key that names
/// it (for messages), and whether it is a picture (a PNG) or a matrix (Matrix Market,
/// .mtx) rather than a mesh.
struct OutputFile {
  std::string key;   // "/path", "/save"
  std::string path;  // "sub/frame_3.obj"
  bool picture = false;
  bool matrix = false;
};

/// A parsed step: the op's typed options, checked and defaulted at load time. Its run
/// never sees JSON.
class Step {
public:
  virtual ~Step() = default;
  /// Checks that span steps (names created before use, index ranges against a lattice's
  /// shape) and rules between keys; `checks.fail(key, ...)` places them.
  virtual void check(ScriptChecks& checks) const {}
  /// The files the step will write, checked before any work.
  virtual std::vector<OutputFile> outputs() const { return {}; }
  /// Whether the step reads the mesh's vertex normals or writes them out (in a picture or
  /// a format that holds them whatever the input): a run none of whose steps and outputs
  /// do skips them (Mesh::normals_deferred). Ops that only move vertices say no.
  virtual bool needs_vertex_normals() const { return true; }
  /// Does the step. Errors it raises without a place are placed by the runner: at the key
  /// the op table gives their subject, or at the step.
  virtual void run(Scene& scene, StepContext& ctx) const = 0;

  const OpInfo* op = nullptr;
  std::string pointer;  // "/steps/3"
};

/// An op's declaration, as the script layer sees it.
class OpInfo {
public:
  virtual ~OpInfo() = default;
  const std::string& name() const { return name_; }
  const std::string& doc() const { return doc_; }
  /// The keys of a step, `op` excluded.
  const TableInfo& keys() const { return keys_; }
  /// The op's JSON Schema: an object with "op": name and the table's keys.
  nlohmann::json schema() const;
  /// A schema-checked step with its defaults filled in, parsed into a typed step.
  virtual std::unique_ptr<Step> parse(const nlohmann::json& step, const ScriptPlace& place) const = 0;
  /// Each key's value in a default-constructed typed step, as JSON, in key order (null
  /// for keys without a default).
  virtual std::vector<nlohmann::json> default_values() const = 0;

protected:
  OpInfo(std::string name, std::string doc, TableInfo keys)
      : name_(std::move(name)), doc_(std::move(doc)), keys_(std::move(keys)) {}

private:
  std::string name_, doc_;
  TableInfo keys_;
};

/// The declaration of an op whose typed step is `S` (default-constructible, deriving from
/// Step), filled by `table`.
template <class S>
class OpDecl final : public OpInfo {
public:
  OpDecl(std::string name, std::string doc, KeyTable<S> table)
      : OpInfo(std::move(name), std::move(doc), table.info()), table_(std::move(table)) {}

  std::unique_ptr<Step> parse(const nlohmann::json& step, const ScriptPlace& place) const override {
    auto typed = std::make_unique<S>();
    table_.read(step, *typed, place);
    typed->op = this;
    typed->pointer = place.pointer;
    return typed;
  }
  std::vector<nlohmann::json> default_values() const override {
    const S fresh{};
    std::vector<nlohmann::json> out;
    for (const Key<S>& k : table_.keys) out.push_back(k.write ? k.write(fresh) : nlohmann::json());
    return out;
  }

private:
  KeyTable<S> table_;
};

/// Every op, in the order of op_list.h.
const std::vector<const OpInfo*>& op_table();
/// The op called `name`, or null.
const OpInfo* find_op(const std::string& name);

}  // namespace ffd
