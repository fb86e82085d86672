#include "script/step_keys.h"

#include <cmath>

namespace ffd {
namespace {

using json = nlohmann::json;

std::vector<std::string> segments(const std::string& path) {
  std::vector<std::string> out;
  std::size_t at = 1;
  while (at <= path.size()) {
    const std::size_t next = path.find('/', at);
    out.push_back(path.substr(at, next == std::string::npos ? std::string::npos : next - at));
    if (next == std::string::npos) break;
    at = next + 1;
  }
  return out;
}

json empty_object_schema() {
  return {{"type", "object"}, {"additionalProperties", false}, {"properties", json::object()}};
}

// The schema of one key's value: its own fragment, a group, or a list of objects.
json value_schema(const KeyInfo& key) {
  json s;
  if (key.group)
    s = empty_object_schema();
  else if (key.items)
    s = {{"type", "array"}, {"minItems", 1}, {"items", object_schema(*key.items)}};
  else
    s = key.schema;
  if (!key.doc.empty()) s["description"] = key.doc;
  if (!key.default_value.is_null()) s["default"] = key.default_value;
  return s;
}

}  // namespace

json object_schema(const TableInfo& table) {
  json root = empty_object_schema();
  for (const KeyInfo& key : table.keys) {
    const std::vector<std::string> parts = segments(key.path);
    json* parent = &root;
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) parent = &(*parent)["properties"][parts[i]];
    json& slot = (*parent)["properties"][parts.back()];
    json value = value_schema(key);
    if (slot.is_object() && slot.contains("properties")) value["properties"] = slot["properties"];
    slot = value;
    if (key.required) (*parent)["required"].push_back(parts.back());
  }
  if (!table.alternatives.empty()) {
    json one_of = json::array();
    for (const auto& group : table.alternatives) one_of.push_back({{"required", group}});
    root["oneOf"] = one_of;
  }
  return root;
}

std::string key_of(const TableInfo& table, const Subject& subject) {
  if (subject.argument.empty()) return "";
  for (const KeyInfo& key : table.keys)
    if (key.argument == subject.argument)
      return subject.element == Subject::kWhole
                 ? key.path
                 : key.path + "/" + std::to_string(subject.element) + key.element_suffix;
  return "";
}

// A bound as JSON: whole numbers as integers, so messages say "at least 0", not "0.0".
json bound(double v) {
  if (v == std::floor(v) && std::abs(v) < 1e15) return static_cast<long long>(v);
  return v;
}

json schema_number(std::optional<double> min, std::optional<double> max) {
  json s = {{"type", "number"}};
  if (min) s["minimum"] = bound(*min);
  if (max) s["maximum"] = bound(*max);
  return s;
}

json schema_integer(std::optional<long> min, std::optional<long> max) {
  json s = {{"type", "integer"}};
  if (min) s["minimum"] = *min;
  if (max) s["maximum"] = *max;
  return s;
}

json schema_text() { return {{"type", "string"}, {"minLength", 1}}; }
json schema_boolean() { return {{"type", "boolean"}}; }
json schema_ref(const std::string& type) { return {{"$ref", "#/$defs/" + type}}; }

}  // namespace ffd
