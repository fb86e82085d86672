// The op tables are the one declaration of every op: the schema's keys and defaults, the
// typed steps' defaults, `validate --resolved` and the Markdown reference must all agree
// with them. And every error type an op can raise below lib/script reaches the user
// with its file, its JSON pointer and its exit code.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <map>
#include <set>
#include <string>

#include "common/errors.h"
#include "script/op.h"
#include "script/runner.h"
#include "script/schema.h"
#include "script/schema_check.h"
#include "script/schema_markdown.h"
#include "script/script.h"
#include "test_meshes.h"

namespace ffd {
namespace {

using json = nlohmann::json;
using test::data;
using test::quoted;
using test::read_file;
using test::run_tool;
using test::temp_folder;
using test::write_file;

// One minimal step per op: only its required keys (and one alternative), in op_list.h's
// order, so that each names what the steps before it created. A new op adds its own.
// The lattice is an octree one (basis is the one key beyond the required), so that
// subdivide has its lattice too; move, drag and remesh take either kind.
const std::map<std::string, json>& minimal_steps() {
  static const std::map<std::string, json> steps = {
      {"lattice", {{"op", "lattice"}, {"name", "body"}, {"basis", "octree"}}},
      {"move", {{"op", "move"}, {"lattice", "body"}, {"points", {{{"index", {2, 2, 2}}, {"by", {0, 0, 0.1}}}}}}},
      {"drag", {{"op", "drag"}, {"lattice", "body"}, {"points", {{{"vertex", 0}, {"to", {0, 0, 0}}}}}}},
      {"subdivide", {{"op", "subdivide"}, {"lattice", "body"}, {"cells", {{"indices", {{1, 1, 1}}}}}}},
      {"rbf", {{"op", "rbf"}, {"name", "morph"}, {"points", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}}},
      {"idw", {{"op", "idw"}, {"name", "spread"}, {"points", {{0, 0, 0}, {1, 0, 0}}}}},
      {"cage", {{"op", "cage"}, {"name", "shell"}, {"cage", "cage.obj"}}},  // kTetrahedron, beside the script
      {"remesh", {{"op", "remesh"}}},
      {"save", {{"op", "save"}, {"path", "mid.obj"}}},
      {"bcm",
       {{"op", "bcm"},
        {"name", "ear"},
        {"support", {{"indices", {0, 1, 2}}}},
        {"handles", {{{"name", "tip"}, {"select", {{"indices", {0}}}}}}}}},
      {"transform", {{"op", "transform"}, {"editor", "ear"}, {"transform", json::object()}}},
  };
  return steps;
}

// The cage of the minimal cage step: a closed, outward tetrahedron.
const char* const kTetrahedron = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";

// The op's schema under $defs (its name, or "<op>_step").
const json& op_schema(const OpInfo& op) {
  const json& defs = script_schema()["$defs"];
  return defs.contains(op.name() + "_step") ? defs[op.name() + "_step"] : defs[op.name()];
}

// Key paths of an object schema: nested objects by path, list items as "<list>[]/<key>".
void schema_paths(const json& object, const std::string& prefix, std::set<std::string>& out) {
  for (auto it = object["properties"].begin(); it != object["properties"].end(); ++it) {
    const std::string path = prefix + "/" + it.key();
    if (path == "/op") continue;
    out.insert(path);
    const json& value = it.value();
    if (value.contains("properties")) schema_paths(value, path, out);
    if (value.value("type", "") == "array" && value["items"].contains("properties"))
      schema_paths(value["items"], path + "[]", out);
  }
}

void table_paths(const TableInfo& table, const std::string& prefix, std::set<std::string>& out) {
  for (const KeyInfo& key : table.keys) {
    out.insert(prefix + key.path);
    if (key.items) table_paths(*key.items, prefix + key.path + "[]", out);
  }
}

// The schema of the key at `path` ("/continuity/outer") inside an object schema.
const json& schema_of_key(const json& object, const std::string& path) {
  const json* at = &object;
  std::size_t from = 1;
  while (from <= path.size()) {
    const std::size_t to = std::min(path.find('/', from), path.size());
    at = &(*at)["properties"][path.substr(from, to - from)];
    from = to + 1;
  }
  return *at;
}

// A key's name in the reference: "continuity.outer".
std::string reference_name(const std::string& path) {
  std::string name = path.substr(1);
  for (char& c : name)
    if (c == '/') c = '.';
  return name;
}

TEST(OpTables, EveryOpHasAMinimalStepHere) {
  for (const OpInfo* op : op_table())
    EXPECT_TRUE(minimal_steps().count(op->name())) << "add a minimal '" << op->name() << "' step to minimal_steps()";
}

TEST(OpTables, SchemaKeysAreTheTableKeys) {
  for (const OpInfo* op : op_table()) {
    std::set<std::string> in_schema, in_table;
    schema_paths(op_schema(*op), "", in_schema);
    table_paths(op->keys(), "", in_table);
    EXPECT_EQ(in_schema, in_table) << op->name();
    EXPECT_EQ(op_schema(*op)["properties"]["op"]["const"], op->name());
    EXPECT_EQ(op_schema(*op)["required"][0], "op") << op->name();
  }
}

TEST(OpTables, SchemaDefaultsAreTheTypedStepsDefaults) {
  std::size_t defaults = 0;
  for (const OpInfo* op : op_table()) {
    const std::vector<KeyInfo>& keys = op->keys().keys;
    const std::vector<json> fresh = op->default_values();
    ASSERT_EQ(fresh.size(), keys.size()) << op->name();
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const json& in_schema = schema_of_key(op_schema(*op), keys[i].path);
      EXPECT_EQ(in_schema.value("default", json()), keys[i].default_value) << op->name() << keys[i].path;
      if (keys[i].default_value.is_null()) {
        EXPECT_TRUE(fresh[i].is_null()) << op->name() << keys[i].path << ": no default, yet the step writes one";
        continue;
      }
      ++defaults;
      EXPECT_EQ(fresh[i], keys[i].default_value)
          << op->name() << keys[i].path << ": the schema's default is " << keys[i].default_value.dump()
          << ", a default-constructed step holds " << fresh[i].dump();
    }
  }
  EXPECT_GE(defaults, 12u);
}

// The grammar's own defaults (a transform's, a fitted box's) are those of the typed values.
TEST(OpTables, GrammarDefaultsAreTheTypedValuesDefaults) {
  const json& defs = script_schema()["$defs"];
  const Transform identity;
  EXPECT_EQ(defs["transform"]["properties"]["translate"]["default"], write_value(Eigen::Vector3d(identity.translate)));
  EXPECT_EQ(defs["transform"]["properties"]["scale"]["default"].get<double>(), identity.scale[0]);
  EXPECT_EQ(identity.scale, Eigen::Vector3d::Ones());
  std::size_t fits = 0;
  for (const json& branch : defs["box"]["oneOf"])
    if (branch["properties"].contains("padding")) {
      EXPECT_EQ(branch["properties"]["padding"]["default"].get<double>(), BoxSpec{}.padding);
      ++fits;
    }
  EXPECT_EQ(fits, 1u);
}

// `ffdtool validate --resolved` on a script of minimal steps fills in exactly the table's
// defaults, and nothing for keys without one.
TEST(OpTables, ValidateResolvedFillsTheTableDefaults) {
  json script = {{"version", 1}, {"steps", json::array()}};
  for (const OpInfo* op : op_table()) script["steps"].push_back(minimal_steps().at(op->name()));
  const std::string dir = temp_folder("op_tables_resolved");
  write_file(dir + "/s.json", script.dump());
  write_file(dir + "/cage.obj", kTetrahedron);
  std::string out, err;
  ASSERT_EQ(run_tool("validate --resolved " + quoted(dir + "/s.json"), &out, &err), 0) << err;
  const json resolved = json::parse(out);
  for (std::size_t i = 0; i < op_table().size(); ++i) {
    const OpInfo& op = *op_table()[i];
    const json& step = resolved["steps"][i];
    const json& given = script["steps"][i];
    for (const KeyInfo& key : op.keys().keys) {
      if (key.group) continue;
      const json::json_pointer at(key.path);
      if (given.contains(at)) {  // as given, plus the grammar's own defaults inside it
        if (given.at(at).is_object())
          for (auto it = given.at(at).begin(); it != given.at(at).end(); ++it)
            EXPECT_EQ(step.at(at)[it.key()], it.value()) << op.name() << key.path;
        else
          EXPECT_EQ(step.at(at), given.at(at)) << op.name() << key.path;
      } else if (key.default_value.is_null()) {
        EXPECT_FALSE(step.contains(at)) << op.name() << key.path << " has no default but was filled in";
      } else {
        ASSERT_TRUE(step.contains(at)) << op.name() << key.path << " was not filled in";
        EXPECT_EQ(step.at(at), key.default_value) << op.name() << key.path;
      }
    }
  }
}

TEST(OpTables, TheCheckedInReferenceIsCurrent) {
  const std::string checked_in = read_file(std::string(FFD_SOURCE_DIR) + "/docs/script-reference.md");
  ASSERT_FALSE(checked_in.empty()) << "docs/script-reference.md is missing";
  EXPECT_EQ(checked_in, script_reference_markdown())
      << "docs/script-reference.md is stale: run `ffdtool schema --markdown > docs/script-reference.md`";
  std::string out;
  ASSERT_EQ(run_tool("schema --markdown", &out), 0);
  EXPECT_EQ(out, checked_in);
  for (const OpInfo* op : op_table()) {
    EXPECT_NE(out.find("### `" + op->name() + "`"), std::string::npos) << op->name();
    for (const KeyInfo& key : op->keys().keys)
      EXPECT_NE(out.find("| `" + reference_name(key.path) + "`"), std::string::npos) << op->name() << key.path;
  }
}

}  // namespace
}  // namespace ffd
