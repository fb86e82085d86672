// The script format's JSON Schema (draft 2020-12): the shared grammar and every op's key table.
#pragma once

#include <nlohmann/json.hpp>

namespace ffd {

/// The schema, parsed once.
const nlohmann::json& script_schema();

}  // namespace ffd
