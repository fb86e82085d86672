#include "script/schema_check.h"

#include <algorithm>

namespace ffd {
namespace {

using json = nlohmann::json;

class Checker {
public:
  explicit Checker(const json& root) : root_(root) {}

  std::optional<SchemaError> check(const json& schema, const json& value, const std::string& path,
                                   json& out) const {
    const json& s = deref(schema);
    out = value;
    if (s.contains("oneOf")) {
      if (auto e = check_one_of(s, value, path, out)) return e;
      if (!s.contains("type") && !s.contains("properties")) return std::nullopt;
    }
    if (s.contains("const") && value != s["const"])
      return error(path, "expected " + s["const"].dump() + ", found " + show(value));
    if (s.contains("enum")) {
      const json& options = s["enum"];
      if (std::find(options.begin(), options.end(), value) == options.end())
        return error(path, "expected " + describe(s) + ", found " + show(value));
    }
    if (s.contains("type") && !type_ok(s["type"].get<std::string>(), value))
      return error(path, "expected " + describe(s) + ", found " + show(value));
    if (value.is_number()) {
      const double x = value.get<double>();
      if (s.contains("minimum") && x < s["minimum"].get<double>())
        return error(path, "must be at least " + s["minimum"].dump() + ", found " + value.dump());
      if (s.contains("maximum") && x > s["maximum"].get<double>())
        return error(path, "must be at most " + s["maximum"].dump() + ", found " + value.dump());
    }
    if (value.is_string() && s.contains("minLength") &&
        value.get<std::string>().size() < s["minLength"].get<std::size_t>())
      return error(path, "must not be empty");
    if (value.is_array()) return check_array(s, value, path, out);
    if (value.is_object() && (s.contains("properties") || s.contains("required")))
      return check_object(s, value, path, out);
    return std::nullopt;
  }

private:
  const json& deref(const json& schema) const {
    if (!schema.contains("$ref")) return schema;
    const std::string ref = schema["$ref"].get<std::string>();  // "#/$defs/name"
    return deref(root_.at(json::json_pointer(ref.substr(1))));
  }

  static SchemaError make(const std::string& path, const std::string& message) { return {path, message}; }
  static std::optional<SchemaError> error(const std::string& path, const std::string& message) {
    return make(path, message);
  }

  static bool type_ok(const std::string& type, const json& v) {
    if (type == "object") return v.is_object();
    if (type == "array") return v.is_array();
    if (type == "string") return v.is_string();
    if (type == "boolean") return v.is_boolean();
    if (type == "integer") return v.is_number_integer();
    if (type == "number") return v.is_number();
    return false;
  }

  static std::string show(const json& v) {
    if (v.is_object()) return "an object";
    if (v.is_array()) return "an array of " + std::to_string(v.size());
    if (v.is_string()) return "\"" + v.get<std::string>() + "\"";
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    if (v.is_null()) return "null";
    return v.dump();
  }

  // What a schema asks for, in words: "an array of 3 integers", "one of \"aabb\", \"obb\"".
  std::string describe(const json& schema, bool plural = false) const {
    const json& s = deref(schema);
    if (s.contains("const")) return s["const"].dump();
    if (s.contains("enum")) {
      std::string out = "one of ";
      for (std::size_t i = 0; i < s["enum"].size(); ++i) out += (i ? ", " : "") + s["enum"][i].dump();
      return out;
    }
    if (s.contains("oneOf")) {
      std::string out;
      const json& branches = s["oneOf"];
      for (std::size_t i = 0; i < branches.size(); ++i)
        out += (i == 0 ? "" : i + 1 == branches.size() ? " or " : ", ") + describe(branches[i], plural);
      return out;
    }
    const std::string type = s.value("type", "");
    if (type == "array") {
      std::string count;
      if (s.contains("minItems") && s.contains("maxItems") && s["minItems"] == s["maxItems"])
        count = s["minItems"].dump() + " ";
      return std::string(plural ? "arrays" : "an array") + " of " + count +
             (s.contains("items") ? describe(s["items"], true) : "values");
    }
    if (type == "object" && s.contains("required") && !s["required"].empty() && s.contains("title"))
      return "an object with '" + s["required"][0].get<std::string>() + "'";
    if (type == "integer") return plural ? "integers" : "an integer";
    if (type == "number") return plural ? "numbers" : "a number";
    if (type == "string") return plural ? "strings" : "a string";
    if (type == "boolean") return plural ? "booleans" : "true or false";
    if (type == "object") return plural ? "objects" : "an object";
    return "a value";
  }

  // Does `value` carry the marks that select this branch of a oneOf?
  bool discriminates(const json& branch, const json& value) const {
    const json& s = deref(branch);
    if (s.contains("type") && !type_ok(s["type"].get<std::string>(), value)) return false;
    if (s.contains("oneOf") && !s.contains("type")) {
      for (const json& b : s["oneOf"])
        if (discriminates(b, value)) return true;
      return false;
    }
    if (!value.is_object()) return true;
    if (s.contains("properties") && s["properties"].contains("op") && s["properties"]["op"].contains("const"))
      return value.contains("op") && value["op"] == s["properties"]["op"]["const"];
    if (s.contains("required"))
      for (const json& key : s["required"])
        if (!value.contains(key.get<std::string>()) && key != "op") return false;
    return true;
  }

  static std::string key_list(const json& keys) {
    std::string out;
    for (std::size_t i = 0; i < keys.size(); ++i)
      out += (i == 0 ? "" : i + 1 == keys.size() ? " or " : ", ") + std::string("'") +
             keys[i].get<std::string>() + "'";
    return out;
  }

  std::optional<SchemaError> check_one_of(const json& s, const json& value, const std::string& path,
                                          json& out) const {
    const json& branches = s["oneOf"];
    std::vector<std::size_t> candidates;
    for (std::size_t i = 0; i < branches.size(); ++i)
      if (discriminates(branches[i], value)) candidates.push_back(i);
    // Key-group alternatives inside an object schema (`oneOf` of bare `required` lists).
    const bool key_groups = std::all_of(branches.begin(), branches.end(), [](const json& b) {
      return b.size() == 1 && b.contains("required");
    });
    if (key_groups) {
      if (candidates.size() == 1) return std::nullopt;
      std::vector<std::string> groups;
      for (const json& b : branches) groups.push_back(key_list(b["required"]));
      std::string alternatives;
      for (std::size_t i = 0; i < groups.size(); ++i)
        alternatives += (i == 0 ? "" : i + 1 == groups.size() ? ", or " : ", ") + groups[i];
      return error(path, candidates.empty() ? "expected " + alternatives
                                            : "give only one of " + alternatives);
    }
    const bool by_op = std::all_of(branches.begin(), branches.end(), [this](const json& b) {
      const json& d = deref(b);
      return d.contains("properties") && d["properties"].contains("op");
    });
    if (candidates.empty() && by_op && value.is_object() && !value.contains("op")) {
      std::string ops;
      for (std::size_t i = 0; i < branches.size(); ++i)
        ops += (i ? ", " : "") + deref(branches[i])["properties"]["op"]["const"].get<std::string>();
      return error(path, "missing key 'op' (one of: " + ops + ")");
    }
    if (candidates.empty()) {
      // Only a choice between ops names them; a selection or a box with an "op" key
      // is refused below for its keys.
      if (by_op && value.is_object() && value.contains("op")) {
        std::string ops;
        for (std::size_t i = 0; i < branches.size(); ++i)
          ops += (i ? ", " : "") + deref(branches[i])["properties"]["op"]["const"].get<std::string>();
        return error(path + "/op", "unknown op " + show(value["op"]) + " (expected one of: " + ops + ")");
      }
      if (value.is_object()) {
        std::vector<std::string> keys;
        for (const json& b : branches) {
          const json& d = deref(b);
          if (d.contains("required") && !d["required"].empty()) keys.push_back(d["required"][0]);
        }
        if (!keys.empty()) return error(path, "expected one of the keys " + key_list(json(keys)));
      }
      return error(path, "expected " + describe(s) + ", found " + show(value));
    }
    if (candidates.size() > 1) {
      std::optional<SchemaError> first;
      std::size_t passing = 0;
      json passed;
      for (std::size_t i : candidates) {
        json tmp;
        auto e = check(branches[i], value, path, tmp);
        if (!e) {
          ++passing;
          passed = tmp;
        } else if (!first) {
          first = e;
        }
      }
      if (passing == 1) {
        out = passed;
        return std::nullopt;
      }
      if (passing == 0) return first;
      return error(path, "ambiguous: matches several of " + describe(s));
    }
    return check(branches[candidates[0]], value, path, out);
  }

  std::optional<SchemaError> check_array(const json& s, const json& value, const std::string& path,
                                         json& out) const {
    if (s.contains("minItems") && value.size() < s["minItems"].get<std::size_t>())
      return error(path, "expected " + describe(s) + ", found " + show(value));
    if (s.contains("maxItems") && value.size() > s["maxItems"].get<std::size_t>())
      return error(path, "expected " + describe(s) + ", found " + show(value));
    if (s.contains("items"))
      for (std::size_t i = 0; i < value.size(); ++i)
        if (auto e = check(s["items"], value[i], path + "/" + std::to_string(i), out[i])) return e;
    return std::nullopt;
  }

  std::optional<SchemaError> check_object(const json& s, const json& value, const std::string& path,
                                          json& out) const {
    static const json kEmpty = json::object();
    const json& props = s.contains("properties") ? s["properties"] : kEmpty;
    if (s.value("additionalProperties", true) == false)
      for (auto it = value.begin(); it != value.end(); ++it)
        if (!props.contains(it.key())) {
          std::vector<std::string> known;
          for (auto p = props.begin(); p != props.end(); ++p) known.push_back(p.key());
          return error(path + "/" + it.key(),
                       "unknown key '" + it.key() + "' (expected " + key_list(json(known)) + ")");
        }
    if (s.contains("required"))
      for (const json& key : s["required"])
        if (!value.contains(key.get<std::string>()))
          return error(path, "missing key '" + key.get<std::string>() + "'");
    for (auto p = props.begin(); p != props.end(); ++p) {
      const std::string child = path + "/" + p.key();
      if (value.contains(p.key())) {
        if (auto e = check(p.value(), value[p.key()], child, out[p.key()])) return e;
      } else {
        const json& ps = deref(p.value());
        const json* def = p.value().contains("default") ? &p.value()["default"]
                          : ps.contains("default")      ? &ps["default"]
                                                        : nullptr;
        if (def)
          if (auto e = check(p.value(), *def, child, out[p.key()])) return e;
      }
    }
    return std::nullopt;
  }

  const json& root_;
};

}  // namespace

std::optional<SchemaError> check_schema(const nlohmann::json& schema, const nlohmann::json& doc,
                                        nlohmann::json* resolved) {
  Checker checker(schema);
  nlohmann::json out;
  auto e = checker.check(schema, doc, "", out);
  if (resolved && !e) *resolved = std::move(out);
  return e;
}

}  // namespace ffd
