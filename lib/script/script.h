// Loading a script: JSON syntax, the schema, then the rules that span steps. Everything
// that can be checked without the mesh is checked here, before any work.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace ffd {

struct Script {
  std::string path;        // as given, for messages
  std::string folder;      // selection files are relative to it
  nlohmann::json resolved; // the script with every default filled in
};

/// Parses and checks script text. \throw InputError "path: /json/pointer: what" for
/// invalid JSON (with line and column), schema violations, a lattice used before it is
/// created or created twice, a lattice too small to have movable points, a move of a point
/// out of range or not movable (naming the movable range), an unreadable selection file,
/// or a save path without a mesh extension.
Script parse_script(const std::string& text, const std::string& path);

/// Reads the file at `path` and parses it. \throw InputError if it cannot be read.
Script load_script(const std::string& path);

}  // namespace ffd
