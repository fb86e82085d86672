#include "script/schema_markdown.h"

#include <sstream>

#include "common/numbers.h"
#include "script/op.h"
#include "script/schema.h"

namespace ffd {
namespace {

using json = nlohmann::json;

std::string cell(std::string text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string number_text(const json& v) { return v.is_number_integer() ? v.dump() : format_number(v.get<double>()); }

std::string range_text(const json& s) {
  const bool lo = s.contains("minimum"), hi = s.contains("maximum");
  if (lo && hi) return " in [" + number_text(s["minimum"]) + ", " + number_text(s["maximum"]) + "]";
  if (lo) return " ≥ " + number_text(s["minimum"]);
  if (hi) return " ≤ " + number_text(s["maximum"]);
  return "";
}

// What a value's schema asks for, in a few words.
std::string type_text(const json& s) {
  if (s.contains("$ref")) {
    const std::string ref = s["$ref"].get<std::string>();
    const std::string name = ref.substr(ref.rfind('/') + 1);
    return "[" + name + "](#" + name + ")";
  }
  if (s.contains("const")) return "`" + s["const"].dump() + "`";
  if (s.contains("enum")) {
    std::string out;
    for (const json& word : s["enum"]) out += (out.empty() ? "`" : " or `") + word.dump() + "`";
    return out;
  }
  if (s.contains("oneOf")) {
    std::string out;
    for (const json& branch : s["oneOf"]) out += (out.empty() ? "" : " or ") + type_text(branch);
    return out;
  }
  const std::string type = s.value("type", "");
  if (type == "array") {
    const bool fixed = s.contains("minItems") && s.contains("maxItems") && s["minItems"] == s["maxItems"];
    const std::string items = s.contains("items") ? type_text(s["items"]) : "values";
    return fixed ? s["minItems"].dump() + " × " + items : "list of " + items;
  }
  if (type == "number" || type == "integer") return type + range_text(s);
  if (type == "string") return s.contains("minLength") ? "non-empty string" : "string";
  if (type == "boolean") return "true or false";
  return type.empty() ? "value" : type;
}

void key_rows(const TableInfo& table, const std::string& prefix, std::ostringstream& os) {
  for (const KeyInfo& key : table.keys) {
    std::string name = key.path.substr(1);
    for (char& c : name)
      if (c == '/') c = '.';
    name = prefix + name;
    const std::string type = key.group ? "object" : key.items ? "list of objects" : type_text(key.schema);
    os << "| `" << name << "`" << (key.required ? " (required)" : "") << " | " << cell(type) << " | "
       << (key.default_value.is_null() ? "" : "`" + cell(key.default_value.dump()) + "`") << " | " << cell(key.doc)
       << " |\n";
    if (key.items) key_rows(*key.items, name + "[].", os);
  }
}

// "Give exactly one of: `points`, or `select` with `transform`." (`lead` starts it).
std::string alternatives_text(const TableInfo& table, const std::string& lead) {
  std::string out;
  for (const auto& group : table.alternatives) {
    std::string keys;
    for (std::size_t i = 0; i < group.size(); ++i) keys += (i ? " with `" : "`") + group[i] + "`";
    out += (out.empty() ? "" : ", or ") + keys;
  }
  return out.empty() ? out : lead + " exactly one of: " + out + ".\n";
}

void op_section(const OpInfo& op, std::ostringstream& os) {
  os << "### `" << op.name() << "`\n\n" << op.doc() << "\n\n";
  os << "| key | type | default | meaning |\n|---|---|---|---|\n";
  key_rows(op.keys(), "", os);
  os << "\n" << alternatives_text(op.keys(), "Give");
  for (const KeyInfo& key : op.keys().keys)
    if (key.items) os << alternatives_text(*key.items, "Each of `" + key.path.substr(1) + "` has");
  os << "\n";
}

// A table of an object schema's properties, each line starting with `indent`.
void property_table(const json& object, const std::string& indent, std::ostringstream& os) {
  os << indent << "| key | type | default | meaning |\n" << indent << "|---|---|---|---|\n";
  for (auto it = object["properties"].begin(); it != object["properties"].end(); ++it)
    os << indent << "| `" << it.key() << "` | " << cell(type_text(it.value())) << " | "
       << (it.value().contains("default") ? "`" + cell(it.value()["default"].dump()) + "`" : "") << " | "
       << cell(it.value().value("description", "")) << " |\n";
  os << "\n";
}

void type_section(const std::string& name, const json& def, std::ostringstream& os) {
  os << "### " << name << "\n\n" << def.value("description", "") << "\n\n";
  if (def.contains("properties")) property_table(def, "", os);
  if (!def.contains("oneOf")) return;
  for (const json& branch : def["oneOf"]) {
    if (!branch.contains("properties")) {
      os << "- " << type_text(branch) << "\n";
      continue;
    }
    os << "- **" << branch.value("title", "") << "**:\n\n";
    property_table(branch, "  ", os);
  }
  os << "\n";
}

}  // namespace

std::string script_reference_markdown() {
  std::ostringstream os;
  const json& schema = script_schema();
  os << "# ffdtool script reference\n\n"
     << "Generated by `ffdtool schema --markdown` from the op tables (`lib/script/op_*.cpp`); do not edit it by "
        "hand. A test checks that it is current.\n\n"
     << schema["description"].get<std::string>() << " A script is `{\"version\": 1, \"steps\": [...]}`; each step "
     << "is an object whose `op` names one of the ops below. Keys with a default may be left out; `ffdtool validate "
        "--resolved` prints a script with every default filled in.\n\n";
  os << "Besides `version`, `steps` and `description`, a script may set `allow_inverted`: "
     << schema["properties"]["allow_inverted"]["description"].get<std::string>() << "\n\n## Ops\n\n";
  for (const OpInfo* op : op_table()) op_section(*op, os);
  os << "## Types\n\nThe shared grammar the ops' keys refer to.\n\n";
  for (const char* name : {"vec3", "index3", "selection", "selection_part", "transform", "box"})
    type_section(name, schema["$defs"][name], os);
  return os.str();
}

}  // namespace ffd
