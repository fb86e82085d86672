// Script parsing: every error names the JSON pointer and what was expected; defaults are
// filled in; the schema is well-formed and agrees with the op table.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "common/errors.h"
#include "script/op.h"
#include "script/schema.h"
#include "script/schema_check.h"
#include "script/script.h"
#include "test_meshes.h"

namespace ffd {
namespace {

using json = nlohmann::json;

// A script whose steps are `steps` (a JSON array's inside).
std::string with_steps(const std::string& steps) { return R"({"version": 1, "steps": [)" + steps + "]}"; }

const char* kBodyLattice = R"({"op": "lattice", "name": "body", "cells": [6, 6, 6]})";

// Expects parse_script to throw InputError "s.json: <pointer>: ..." mentioning every part.
void expect_script_error(const std::string& text, const std::string& pointer,
                         const std::vector<std::string>& parts, const std::string& path = "s.json") {
  try {
    parse_script(text, path);
  } catch (const InputError& e) {
    const std::string what = e.what();
    const std::string prefix = path + ": " + pointer + ": ";
    EXPECT_EQ(what.rfind(prefix, 0), 0u) << "message '" << what << "' does not start with '" << prefix << "'";
    for (const std::string& part : parts)
      EXPECT_NE(what.find(part), std::string::npos) << "message '" << what << "' does not mention '" << part << "'";
    EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
    return;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw something other than InputError: " << e.what() << "\nfor: " << text;
    return;
  }
  ADD_FAILURE() << "accepted an invalid script (expected an error at " << pointer << "): " << text;
}

TEST(ScriptParse, AcceptsTheDemoScript) {
  const Script script = load_script(test::data("demo.json"));
  ASSERT_EQ(script.resolved["steps"].size(), 4u);
  EXPECT_EQ(script.resolved["steps"][0]["op"], "lattice");
}

TEST(ScriptParse, UnknownOrMissingOp) {
  expect_script_error(with_steps(R"({"op": "frobnicate"})"), "/steps/0/op",
                      {"unknown op", "\"frobnicate\"", "lattice", "move", "drag", "save"});
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": 3})"), "/steps/1/op", {"unknown op", "3"});
  expect_script_error(with_steps(R"({"name": "body", "cells": [6, 6, 6]})"), "/steps/0",
                      {"missing key 'op'", "lattice", "save"});
  // An "op" key in a selection or a box (fuzz_run found these) names no op: the message
  // names the keys the object may have.
  expect_script_error(with_steps(R"({"op": "bcm", "name": "e", "support": {"op": "x"},
      "handles": [{"name": "h", "select": {"near": [0, 0, 1]}}]})"),
                      "/steps/0/support", {"expected an object with 'indices'", "'sphere'", "found an object"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "a", "cells": [4, 4, 4], "box": {"op": "x"}})"),
                      "/steps/0/box", {"expected one of the keys", "'fit'"});
}

TEST(ScriptParse, UnknownKeysNameTheKeyAndTheAllowedOnes) {
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": [6, 6, 6], "colour": 1})"),
                      "/steps/0/colour", {"unknown key 'colour'", "'name'", "'basis'", "'cells'", "'box'"});
  expect_script_error(R"({"version": 1, "steps": [], "author": "me"})", "/author", {"unknown key 'author'", "'steps'"});
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body",
      "points": [{"index": [3, 3, 3], "by": [0, 0, 1], "weight": 2}]})"),
                      "/steps/1/points/0/weight", {"unknown key 'weight'", "'index'", "'by'", "'to'"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": [6, 6, 6],
      "box": {"fit": "aabb", "pading": 0.1}})"),
                      "/steps/0/box/pading", {"unknown key 'pading'", "'padding'"});
}

TEST(ScriptParse, WrongTypesSayWhatWasExpected) {
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": 6})"), "/steps/0/cells",
                      {"expected an array of 3 integers", "found 6"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": [6, 6]})"), "/steps/0/cells",
                      {"expected an array of 3 integers", "found an array of 2"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": [6, 6.5, 6]})"),
                      "/steps/0/cells/1", {"expected an integer", "6.5"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": [6, 6, 0]})"), "/steps/0/cells/2",
                      {"at least 1"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": [6, 6, 6], "basis": "nurbs"})"),
                      "/steps/0/basis", {"one of", "\"bspline\"", "\"bernstein\"", "\"nurbs\""});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": [6, 6, 6], "degree": 4})"),
                      "/steps/0/degree", {"at most 3"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "", "cells": [6, 6, 6]})"), "/steps/0/name",
                      {"empty"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": [6, 6, 6],
      "box": {"fit": "aabb", "padding": -0.1}})"),
                      "/steps/0/box/padding", {"at least 0"});
  expect_script_error(with_steps(R"({"op": "save", "path": 3})"), "/steps/0/path", {"expected a string"});
  expect_script_error(R"({"version": 2, "steps": []})", "/version", {"expected 1", "found 2"});
  expect_script_error(R"({"version": 1})", "/", {"missing key 'steps'"});
  expect_script_error(R"([1, 2])", "/", {"expected an object"});
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body",
      "points": [{"index": [3, 3, 3], "by": [0, "up", 1]}]})"),
                      "/steps/1/points/0/by/1", {"expected a number", "\"up\""});
}

TEST(ScriptParse, LatticeShapeAndIndexChecks) {
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "cells": [6, 3, 6]})"), "/steps/0/cells/1",
                      {"degree-3", "at least 4 cells"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "degree": 2, "cells": [6, 6, 2]})"),
                      "/steps/0/cells/2", {"degree-2", "at least 3 cells"});
  const std::string move = R"(, {"op": "move", "lattice": "body", "points": [{"index": [2, 2, 2], "by": [0, 0, 1]},
                                  {"index": )";
  // Out of range and not movable (the influenced zone): both name the movable range.
  expect_script_error(with_steps(std::string(kBodyLattice) + move + R"([9, 3, 3], "by": [0, 0, 1]}]})"),
                      "/steps/1/points/1/index", {"[9,3,3]", "i in [2, 4], j in [2, 4], k in [2, 4]"});
  expect_script_error(with_steps(std::string(kBodyLattice) + move + R"([3, 1, 3], "to": [0, 0, 1]}]})"),
                      "/steps/1/points/1/index", {"[3,1,3]", "not movable", "i in [2, 4]"});
  expect_script_error(with_steps(std::string(kBodyLattice) + move + R"([3, 3, -1], "to": [0, 0, 1]}]})"),
                      "/steps/1/points/1/index", {"not movable"});
  // Bernstein: every point of the (cells + 1)^3 grid may move; beyond it may not.
  const char* bernstein = R"({"op": "lattice", "name": "body", "basis": "bernstein", "cells": [3, 2, 4]})";
  EXPECT_NO_THROW(parse_script(with_steps(std::string(bernstein) + move + R"([0, 2, 4], "to": [0, 0, 1]}]})"), "s.json"));
  expect_script_error(with_steps(std::string(bernstein) + move + R"([0, 3, 4], "to": [0, 0, 1]}]})"),
                      "/steps/1/points/1/index", {"i in [0, 3], j in [0, 2], k in [0, 4]"});
  // Quadratic and linear B-splines have their own movable ranges.
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "degree": 2, "cells": [5, 5, 5]})" + move +
                                 R"([0, 2, 2], "to": [0, 0, 1]}]})"),
                      "/steps/1/points/1/index", {"[0,2,2]", "i in [1, 3], j in [1, 3], k in [1, 3]"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "body", "degree": 1, "cells": [5, 5, 5]})" + move +
                                 R"([5, 2, 2], "to": [0, 0, 1]}]})"),
                      "/steps/1/points/1/index", {"i in [1, 4]"});
  // Giving both 'by' and 'to', or neither.
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body",
      "points": [{"index": [3, 3, 3], "by": [0, 0, 1], "to": [0, 0, 1]}]})"),
                      "/steps/1/points/0", {"only one of", "'by'", "'to'"});
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body",
      "points": [{"index": [3, 3, 3]}]})"),
                      "/steps/1/points/0", {"'by'", "'to'"});
}

TEST(ScriptParse, LatticeNamesMustBeCreatedOnceBeforeUse) {
  expect_script_error(with_steps(R"({"op": "move", "lattice": "body", "points": [{"index": [3, 3, 3], "by": [0, 0, 1]}]},)" +
                                 std::string(kBodyLattice)),
                      "/steps/0/lattice", {"no lattice named 'body'"});
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": "drag", "lattice": "head",
      "points": [{"at": [0, 0, 0], "to": [0, 0, 1]}]})"),
                      "/steps/1/lattice", {"no lattice named 'head'"});
  expect_script_error(with_steps(std::string(kBodyLattice) + ", " + kBodyLattice), "/steps/1/name",
                      {"'body' already exists"});
}

TEST(ScriptParse, SelectionsNeedExactlyOneKind) {
  const std::string head = std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body", "transform": {"scale": 2}, "select": )";
  // Two kinds in one selection object.
  try {
    parse_script(with_steps(head + R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "box": {"min": [0, 0, 0], "max": [1, 1, 1]}}})"),
                 "s.json");
    ADD_FAILURE() << "a selection with two kinds was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("s.json: /steps/1/select", 0), 0u) << what;
    EXPECT_TRUE(what.find("box") != std::string::npos && what.find("sphere") != std::string::npos) << what;
  }
  // None at all.
  expect_script_error(with_steps(head + "{}}"), "/steps/1/select",
                      {"expected", "'indices'", "'sphere'", "'box'", "'near'", "'file'"});
  expect_script_error(with_steps(head + "[{}]}"), "/steps/1/select/0",
                      {"expected one of the keys", "'indices'", "'sphere'", "'box'", "'near'", "'file'"});
  expect_script_error(with_steps(head + "[]}"), "/steps/1/select", {});
  // A union (list) of kinds is fine.
  EXPECT_NO_THROW(parse_script(
      with_steps(head + R"([{"near": [0, 0, 0]}, {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}]})"), "s.json"));
  // Inside a kind, the keys are checked too.
  expect_script_error(with_steps(head + R"({"sphere": {"center": [0, 0, 0]}}})"), "/steps/1/select/sphere",
                      {"missing key 'radius'"});
  // move needs either points or select + transform.
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body"})"), "/steps/1",
                      {"'points'", "'select'"});
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body", "select": {"near": [0, 0, 0]}})"),
                      "/steps/1", {"'transform'"});
}

TEST(ScriptParse, SelectionFilesMustExistAndParse) {
  const std::string dir = test::temp_folder("script_selection");
  const std::string step = std::string(kBodyLattice) +
                           R"(, {"op": "lattice", "name": "head", "cells": [4, 4, 4], "box": {"fit": "aabb", "select": {"file": ")";
  expect_script_error(with_steps(step + R"(missing.txt"}}})"), "/steps/1/box/select/file",
                      {"no such selection file", "missing.txt"}, dir + "/s.json");
  test::write_file(dir + "/bad.txt", "1\n2\nthree\n");
  try {
    parse_script(with_steps(step + R"(bad.txt"}}})"), dir + "/s.json");
    ADD_FAILURE() << "a malformed selection file was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(dir + "/bad.txt:3:", 0), 0u) << e.what();
  }
  test::write_file(dir + "/good.txt", "# head vertices\n1\n2\n\n3\n");
  EXPECT_NO_THROW(parse_script(with_steps(step + R"(good.txt"}}})"), dir + "/s.json"));
}

TEST(ScriptParse, SavePathsNeedAMeshExtensionAndStayInside) {
  expect_script_error(with_steps(R"({"op": "save", "path": "out.txt"})"), "/steps/0/path",
                      {"'out.txt'", "mesh extension", ".obj"});
  // (A name no folder has: an existing folder is an OpenFOAM polyMesh, and the README's
  // quick start leaves `out/` where a developer may run the tests.)
  expect_script_error(with_steps(R"({"op": "save", "path": "no_such_output"})"), "/steps/0/path", {"mesh extension"});
  expect_script_error(with_steps(R"({"op": "save", "path": "../out.obj"})"), "/steps/0/path", {"'..'"});
  expect_script_error(with_steps(R"({"op": "save", "path": "a/../../out.obj"})"), "/steps/0/path", {"'..'"});
  expect_script_error(with_steps(R"({"op": "save", "path": "/tmp/out.obj"})"), "/steps/0/path", {"relative"});
  expect_script_error(with_steps(R"({"op": "save", "path": ""})"), "/steps/0/path", {"empty"});
  EXPECT_NO_THROW(parse_script(with_steps(R"({"op": "save", "path": "sub/out.OFF"})"), "s.json"));
}

TEST(ScriptParse, InvalidJsonNamesLineAndColumn) {
  try {
    parse_script("{\"version\": 1,\n  \"steps\": [\n    {\"op\": \"save\" \"path\": \"a.obj\"}\n  ]\n}\n", "s.json");
    ADD_FAILURE() << "invalid JSON was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("s.json: invalid JSON: ", 0), 0u) << what;
    EXPECT_NE(what.find("line 3"), std::string::npos) << what;
    EXPECT_NE(what.find("column"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  for (const char* text : {"", "{", "{\"version\": 1,}", "nul"})
    EXPECT_THROW(parse_script(text, "s.json"), InputError) << text;
}

TEST(ScriptParse, DefaultsAreFilledIn) {
  const Script script = parse_script(with_steps(std::string(kBodyLattice) + R"(,
      {"op": "lattice", "name": "b2", "cells": [4, 4, 4], "box": {"fit": "obb"}},
      {"op": "move", "lattice": "body", "select": {"near": [0, 0, 0]}, "transform": {"translate": [0, 1, 0]}},
      {"op": "move", "lattice": "body", "select": {"near": [0, 0, 0]}, "transform": {}})"),
                                     "s.json");
  const json& steps = script.resolved["steps"];
  EXPECT_EQ(steps[0]["basis"], "bspline");
  EXPECT_EQ(steps[0]["degree"], 3);
  EXPECT_EQ(steps[0]["box"]["fit"], "aabb");
  EXPECT_EQ(steps[0]["box"]["padding"], 0.05);
  EXPECT_EQ(steps[1]["box"]["fit"], "obb");
  EXPECT_EQ(steps[1]["box"]["padding"], 0.05);
  EXPECT_EQ(steps[2]["transform"]["scale"], 1);
  EXPECT_EQ(steps[2]["transform"]["translate"], json::array({0, 1, 0}));
  EXPECT_EQ(steps[3]["transform"]["translate"], json::array({0, 0, 0}));
  EXPECT_EQ(steps[3]["transform"]["scale"], 1);
  EXPECT_FALSE(steps[3]["transform"].contains("center")) << "center defaults to the selection's centroid";
  EXPECT_FALSE(steps[3]["transform"].contains("rotate"));
  // Given values are kept as given.
  const Script given = parse_script(
      with_steps(R"({"op": "lattice", "name": "b", "basis": "bernstein", "degree": 2, "cells": [3, 3, 3],
                     "box": {"min": [0, 0, 0], "max": [1, 2, 3]}})"),
      "s.json");
  EXPECT_EQ(given.resolved["steps"][0]["basis"], "bernstein");
  EXPECT_EQ(given.resolved["steps"][0]["degree"], 2);
  EXPECT_EQ(given.resolved["steps"][0]["box"], json::parse(R"({"min": [0, 0, 0], "max": [1, 2, 3]})"));
  // Resolving is idempotent: the resolved script is valid and resolves to itself.
  const Script again = parse_script(script.resolved.dump(), "s.json");
  EXPECT_EQ(again.resolved, script.resolved);
}

// Every "$ref" in `node`, with its JSON pointer.
void collect_refs(const json& node, const std::string& at, std::vector<std::pair<std::string, std::string>>& out) {
  if (node.is_object()) {
    for (auto it = node.begin(); it != node.end(); ++it) {
      if (it.key() == "$ref" && it.value().is_string()) out.emplace_back(at, it.value().get<std::string>());
      collect_refs(it.value(), at + "/" + it.key(), out);
    }
  } else if (node.is_array()) {
    for (std::size_t i = 0; i < node.size(); ++i) collect_refs(node[i], at + "/" + std::to_string(i), out);
  }
}

TEST(ScriptSchema, IsWellFormedAndMatchesTheOpTable) {
  const json& schema = script_schema();
  ASSERT_TRUE(schema.is_object());
  EXPECT_EQ(schema["$schema"], "https://json-schema.org/draft/2020-12/schema");
  EXPECT_EQ(schema["type"], "object");

  std::vector<std::pair<std::string, std::string>> refs;
  collect_refs(schema, "", refs);
  EXPECT_GT(refs.size(), 10u);
  std::set<std::string> used;
  for (const auto& [at, ref] : refs) {
    ASSERT_EQ(ref.rfind("#/", 0), 0u) << at << ": $ref '" << ref << "' is not local";
    const json::json_pointer pointer(ref.substr(1));
    ASSERT_TRUE(schema.contains(pointer)) << at << ": $ref '" << ref << "' resolves to nothing";
    EXPECT_TRUE(schema.at(pointer).is_object()) << at << ": $ref '" << ref << "'";
    used.insert(ref);
  }
  // Every definition is used somewhere.
  for (auto it = schema["$defs"].begin(); it != schema["$defs"].end(); ++it)
    EXPECT_TRUE(used.count("#/$defs/" + it.key())) << "$defs/" << it.key() << " is never used";

  // steps.items.oneOf <-> op_table(), both ways.
  std::set<std::string> schema_ops, table_ops;
  for (const json& branch : schema["properties"]["steps"]["items"]["oneOf"]) {
    const json& def = branch.contains("$ref") ? schema.at(json::json_pointer(branch["$ref"].get<std::string>().substr(1)))
                                              : branch;
    ASSERT_TRUE(def["properties"]["op"].contains("const")) << branch.dump();
    const std::string op = def["properties"]["op"]["const"];
    EXPECT_TRUE(schema_ops.insert(op).second) << "op '" << op << "' twice in the schema";
    // Each op's schema requires 'op' and forbids unknown keys.
    EXPECT_NE(std::find(def["required"].begin(), def["required"].end(), "op"), def["required"].end()) << op;
    EXPECT_EQ(def.value("additionalProperties", true), false) << op;
  }
  for (const OpInfo* op : op_table()) {
    EXPECT_TRUE(table_ops.insert(op->name()).second) << "op '" << op->name() << "' twice in the op table";
    EXPECT_EQ(find_op(op->name()), op) << op->name();
  }
  EXPECT_EQ(schema_ops, table_ops);
  EXPECT_TRUE(schema_ops.count("lattice") && schema_ops.count("move") && schema_ops.count("drag") &&
              schema_ops.count("save"));

  // Every default is valid against its own schema (check_schema on a document holding it).
  std::vector<std::pair<std::string, const json*>> defaults;
  std::function<void(const json&, const std::string&)> walk = [&](const json& node, const std::string& at) {
    if (!node.is_object()) {
      if (node.is_array())
        for (std::size_t i = 0; i < node.size(); ++i) walk(node[i], at + "/" + std::to_string(i));
      return;
    }
    if (node.contains("default")) defaults.emplace_back(at, &node);
    for (auto it = node.begin(); it != node.end(); ++it)
      if (it.key() != "default") walk(it.value(), at + "/" + it.key());
  };
  walk(schema, "");
  EXPECT_GE(defaults.size(), 5u);
  for (const auto& [at, node] : defaults) {
    json sub = *node;
    sub.erase("default");
    json root = schema;
    root["$defs"]["__probe"] = sub;
    const json probe_schema = {{"$ref", "#/$defs/__probe"}};
    root.update(probe_schema);
    root.erase("type");
    root.erase("required");
    root.erase("properties");
    root.erase("additionalProperties");
    const auto error = check_schema(root, (*node)["default"], nullptr);
    EXPECT_FALSE(error) << at << ": default " << (*node)["default"].dump() << " is invalid: "
                        << (error ? error->path + ": " + error->message : "");
  }
}

TEST(ScriptSchema, ChecksTheDemoScriptAndFillsDefaults) {
  const json doc = json::parse(test::read_file(test::data("demo.json")));
  json resolved;
  const auto error = check_schema(script_schema(), doc, &resolved);
  ASSERT_FALSE(error) << error->path << ": " << error->message;
  EXPECT_EQ(resolved["steps"][1]["transform"]["translate"], json::array({0, 1.2, 0}));
  EXPECT_EQ(resolved["steps"][3]["transform"]["scale"], 1);
}

// Point and cell indices are checked with the script, before any mesh is read: their
// form ([i, j, k] on lattices and octrees, a number on scattered points), the movable
// ranges the script decides, and no selection file for control points, with the messages
// and places the run would give.
TEST(ScriptParse, PointAndCellIndicesAreCheckedBeforeAnyMesh) {
  const std::string octree = R"({"op": "lattice", "name": "o", "basis": "octree", "levels": 2})";
  const std::string translate = R"("transform": {"translate": [0.1, 0, 0]}})";
  expect_script_error(with_steps(octree + R"(, {"op": "move", "lattice": "o", "select": {"indices": [3, 4]}, )" + translate),
                      "/steps/1/select/indices/0", {"expected a lattice index [i, j, k]"});
  expect_script_error(with_steps(octree + R"(, {"op": "move", "lattice": "o", "level": 1,
      "select": [{"near": [0, 0, 0]}, {"indices": [[1, 1, 1], [3, 0, 0]]}], )" + translate),
                      "/steps/1/select/1/indices/1", {"point [3,0,0] is not movable", "[0, 2]"});
  EXPECT_NO_THROW(parse_script(with_steps(octree + R"(, {"op": "move", "lattice": "o", "level": 1,
      "select": {"indices": [[0, 1, 2], [2, 2, 2]]}, )" + translate), "s.json"));
  // B-spline: a number for [i, j, k], and a point outside the movable range.
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body",
      "points": [{"index": 7, "by": [0, 0, 1]}]})"),
                      "/steps/1/points/0/index", {"expected a lattice index [i, j, k]"});
  expect_script_error(with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body",
      "select": {"indices": [[3, 3, 3], [0, 3, 3]]}, )" + translate),
                      "/steps/1/select/indices/1", {"point [0,3,3] is not movable", "i in [2, 4]"});
  // Scattered points: [i, j, k] for a number, and a number past the list.
  const std::string idw = R"({"op": "idw", "name": "w", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})";
  expect_script_error(with_steps(idw + R"(, {"op": "move", "lattice": "w", "points": [{"index": [1, 2, 3], "by": [0, 0, 1]}]})"),
                      "/steps/1/points/0/index", {"expected the number of one of its control points (an integer), found [1,2,3]"});
  expect_script_error(with_steps(idw + R"(, {"op": "move", "lattice": "w", "select": {"indices": [0, [1, 2, 3]]}, )" + translate),
                      "/steps/1/select/indices/1", {"expected the number of one of its control points", "[1,2,3]"});
  expect_script_error(with_steps(idw + R"(, {"op": "move", "lattice": "w", "select": {"indices": [3]}, )" + translate),
                      "/steps/1/select/indices/0", {"point 3 is not movable", "control points 0 to 2"});
  EXPECT_NO_THROW(parse_script(with_steps(idw + R"(, {"op": "move", "lattice": "w", "select": {"indices": [0, 2]}, )" + translate), "s.json"));
  // Subdivide's cells: [i, j, k] within the level's 2^level cells per axis.
  expect_script_error(with_steps(octree + R"(, {"op": "subdivide", "lattice": "o", "cells": {"indices": [[0, 0, 0], 5]}})"),
                      "/steps/1/cells/indices/1", {"expected a lattice index [i, j, k]"});
  expect_script_error(with_steps(octree + R"(, {"op": "subdivide", "lattice": "o", "level": 1, "cells": {"indices": [[0, 2, 0]]}})"),
                      "/steps/1/cells/indices/0", {"cell [0,2,0] is not one of the kept cells of level 1", "[0, 1]"});
  EXPECT_NO_THROW(parse_script(with_steps(octree + R"(, {"op": "subdivide", "lattice": "o", "cells": {"indices": [[3, 3, 3]]}})"), "s.json"));
  // Mesh vertex selections take vertex numbers.
  expect_script_error(with_steps(R"({"op": "bcm", "name": "e", "support": {"indices": [0, [1, 2, 3]]},
      "handles": [{"name": "h", "select": {"indices": [0]}}]})"),
                      "/steps/0/support/indices/1", {"expected a vertex index, found a lattice index"});
  expect_script_error(with_steps(R"({"op": "rbf", "name": "r", "points": {"select": {"indices": [[0, 0, 0]]}}})"),
                      "/steps/0/points/select/indices/0", {"expected a vertex index, found a lattice index"});
  expect_script_error(with_steps(R"({"op": "lattice", "name": "b", "cells": [4, 4, 4],
      "box": {"fit": "aabb", "select": [{"near": [0, 0, 0]}, {"indices": [[0, 0, 0]]}]}})"),
                      "/steps/0/box/select/1/indices/0", {"expected a vertex index, found a lattice index"});
}

// A selection file lists mesh vertices: given for control points, the script is refused.
TEST(ScriptParse, ASelectionFileForControlPointsIsRefused) {
  const std::string dir = test::temp_folder("script_selection_file");
  test::write_file(dir + "/sel.txt", "1\n2\n");
  test::write_file(dir + "/s.json", with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body",
      "select": [{"indices": [[3, 3, 3]]}, {"file": "sel.txt"}], "transform": {"translate": [0.1, 0, 0]}})"));
  test::expect_input_error([&] { load_script(dir + "/s.json"); }, dir + "/s.json: /steps/1/select/1: ",
                           {"a selection file lists mesh vertices, not lattice points"});
  test::write_file(dir + "/octree.json", with_steps(R"({"op": "lattice", "name": "o", "basis": "octree", "levels": 1},
      {"op": "subdivide", "lattice": "o", "cells": {"file": "sel.txt"}})"));
  test::expect_input_error([&] { load_script(dir + "/octree.json"); }, dir + "/octree.json: /steps/1/cells: ",
                           {"a selection file lists mesh vertices"});
}

// `ffdtool validate` refuses what no mesh could run: a number for a B-spline lattice's
// [i, j, k], [i, j, k] for an idw deformer's number.
TEST(ScriptParse, ValidateRefusesIndicesOfTheWrongForm) {
  const std::string dir = test::temp_folder("validate_index_form");
  test::write_file(dir + "/bspline.json", with_steps(std::string(kBodyLattice) + R"(, {"op": "move", "lattice": "body",
      "points": [{"index": 3, "by": [0, 0, 1]}]})"));
  std::string out, err;
  EXPECT_EQ(test::run_tool("validate " + test::quoted(dir + "/bspline.json"), &out, &err), 2);
  test::expect_one_error_line(err, {dir + "/bspline.json: /steps/1/points/0/index: expected a lattice index [i, j, k]"});
  EXPECT_EQ(out, "");
  test::write_file(dir + "/idw.json", with_steps(R"({"op": "idw", "name": "w", "points": [[0, 0, 0], [1, 0, 0]]},
      {"op": "move", "lattice": "w", "points": [{"index": [0, 0, 0], "by": [0, 0, 1]}]})"));
  EXPECT_EQ(test::run_tool("validate " + test::quoted(dir + "/idw.json"), &out, &err), 2);
  test::expect_one_error_line(err, {dir + "/idw.json: /steps/1/points/0/index: expected the number of one of its "
                                    "control points (an integer), found [0,0,0]"});
}

}  // namespace
}  // namespace ffd
