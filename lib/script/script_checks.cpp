#include "script/script_checks.h"

#include <filesystem>

#include "common/errors.h"
#include "mesh/mesh_io.h"
#include "script/selection.h"
#include "warp/bspline_lattice.h"

namespace ffd {

void LatticeShape::movable_span(int axis, int& lo, int& hi) const {
  if (basis == "bernstein") {
    lo = 0;
    hi = cells[axis];
  } else {
    BSplineLattice::movable_span(degree, cells[axis], lo, hi);
  }
}

std::string LatticeShape::movable_text() const {
  static const char* names = "ijk";
  std::string s;
  for (int a = 0; a < 3; ++a) {
    int lo, hi;
    movable_span(a, lo, hi);
    s += (a ? ", " : "") + std::string(1, names[a]) + " in [" + std::to_string(lo) + ", " +
         std::to_string(hi) + "]";
  }
  return s;
}

void ScriptChecks::fail(const std::string& pointer, const std::string& what) const {
  throw InputError(path_ + ": " + pointer + ": " + what);
}

void ScriptChecks::check_selection_files(const nlohmann::json& selection, const std::string& pointer) const {
  const auto one = [&](const nlohmann::json& part, const std::string& p) {
    if (!part.contains("file")) return;
    std::string file = part["file"].get<std::string>();
    if (!file.empty() && file[0] != '/' && !folder_.empty()) file = folder_ + "/" + file;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) fail(p + "/file", "no such selection file '" + file + "'");
    read_index_file(file);  // throws with the file's line on a malformed entry
  };
  if (selection.is_array())
    for (std::size_t i = 0; i < selection.size(); ++i) one(selection[i], pointer + "/" + std::to_string(i));
  else
    one(selection, pointer);
}

void ScriptChecks::check_output_path(const std::string& path, const std::string& pointer) const {
  try {
    mesh_format(path);
  } catch (const InputError&) {
    fail(pointer, "'" + path + "' has no mesh extension (.obj, .off, .ply, .stl)");
  }
  const std::filesystem::path p(path);
  for (const auto& part : p)
    if (part == "..") fail(pointer, "output paths stay inside the output folder ('..' is not allowed)");
  if (p.is_absolute()) fail(pointer, "output paths are relative to the output folder");
}

const LatticeShape& ScriptChecks::lattice_of(const nlohmann::json& step, const std::string& pointer) const {
  const std::string name = step["lattice"];
  auto it = lattices.find(name);
  if (it == lattices.end())
    fail(pointer + "/lattice", "no lattice named '" + name + "' is created before this step");
  return it->second;
}

}  // namespace ffd
