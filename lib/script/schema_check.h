// Checking a JSON document against the script schema, with JSON-pointer error places.
//
// Covers the part of JSON Schema the script schema uses: $ref into $defs, type, const,
// enum, minimum, maximum, minLength, minItems, maxItems, items, required, properties,
// additionalProperties: false, default, and oneOf. A oneOf picks its branch the way a
// reader would: by the `op` constant, by the value's type, or by which required keys are
// present, and then reports the errors of that branch, so a message points at the key
// that is wrong instead of saying that no alternative matched.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace ffd {

struct SchemaError {
  std::string path;     // JSON pointer, "" for the document itself
  std::string message;  // what was expected and what was found
};

/// Checks `doc` against `schema` (whose $refs resolve against `schema` itself). Returns the
/// first error. When `resolved` is given it receives `doc` with every default filled in.
std::optional<SchemaError> check_schema(const nlohmann::json& schema, const nlohmann::json& doc,
                                        nlohmann::json* resolved);

}  // namespace ffd
