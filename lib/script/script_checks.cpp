#include "script/script_checks.h"

#include <filesystem>

#include "common/errors.h"
#include "mesh/mesh_io.h"
#include "script/op.h"
#include "render/png_io.h"

namespace ffd {

void ScriptChecks::fail(const std::string& pointer, const std::string& what) const {
  throw InputError(At{path_ + ": " + pointer}, what);
}

void ScriptChecks::check_output_path(const OutputFile& file, const std::string& pointer) const {
  const std::string& path = file.path;
  if (file.picture && !has_png_extension(path)) fail(pointer, "'" + path + "': a preview is a PNG picture (.png)");
  if (!file.picture) {
    try {
      mesh_format(path);
    } catch (const InputError&) {
      fail(pointer, "'" + path + "' has no mesh extension (.obj, .off, .ply, .stl, .gltf, .glb)");
    }
  }
  const std::filesystem::path p(path);
  for (const auto& part : p)
    if (part == "..") fail(pointer, "output paths stay inside the output folder ('..' is not allowed)");
  if (p.is_absolute()) fail(pointer, "output paths are relative to the output folder");
}

const LatticeSpec& ScriptChecks::lattice_of(const std::string& name, const std::string& pointer) const {
  auto it = lattices.find(name);
  if (it == lattices.end()) {
    if (octrees.count(name)) fail(pointer, "lattice '" + name + "' is an octree lattice; this step needs a B-spline or Bernstein lattice");
    fail(pointer, "no lattice named '" + name + "' is created before this step");
  }
  return it->second;
}

int ScriptChecks::octree_levels(const std::string& name) const {
  auto it = octrees.find(name);
  if (it == octrees.end()) return -1;
  auto local = octree_local_levels.find(name);
  return it->second + (local == octree_local_levels.end() ? 0 : local->second);
}

int ScriptChecks::check_lattice_level(const std::string& name, const std::optional<int>& level,
                                      const std::string& pointer) const {
  const int levels = octree_levels(name);
  if (levels < 0) {
    lattice_of(name, pointer + "/lattice");
    if (level) fail(pointer + "/level", "level is for octree lattices");
  } else if (level && *level > levels) {
    fail(pointer + "/level", "lattice '" + name + "' has levels 0 to " + std::to_string(levels));
  }
  return levels;
}

void ScriptChecks::check_new_lattice(const std::string& name, const std::string& pointer) const {
  if (lattices.count(name) || octrees.count(name)) fail(pointer, "a lattice named '" + name + "' already exists");
}

}  // namespace ffd
