// Loading a script: JSON syntax, the schema, then each step parsed into its op's typed
// step and checked against the steps before it. Everything that can be checked without
// the mesh is checked here, before any work.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "script/op.h"

namespace ffd {

struct Script {
  std::string path;         // as given, for messages
  std::string folder;       // selection files are relative to it
  nlohmann::json resolved;  // the script with every default filled in
  std::vector<std::unique_ptr<Step>> steps;
  bool allow_inverted = false;  // a volume mesh's result may have inverted cells
};

/// Parses and checks script text. \throw InputError "path: /json/pointer: what" for
/// invalid JSON (with line and column), schema violations, a lattice used before it is
/// created or created twice, a lattice too small to have movable points, a move of a point
/// out of range or not movable (naming the movable range), an unreadable selection file,
/// or an output path without a mesh extension or outside the output folder.
Script parse_script(const std::string& text, const std::string& path);

/// Reads the file at `path` and parses it. \throw InputError if it cannot be read.
Script load_script(const std::string& path);

}  // namespace ffd
