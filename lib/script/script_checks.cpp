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
  if (file.matrix && std::filesystem::path(path).extension() != ".mtx")
    fail(pointer, "'" + path + "': sensitivities are a Matrix Market file (.mtx)");
  if (!file.picture && !file.matrix) {
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

const DeformerShape& ScriptChecks::deformer_of(const std::string& name, const std::string& pointer) const {
  auto it = deformers.find(name);
  if (it == deformers.end()) fail(pointer, "no lattice named '" + name + "' is created before this step");
  return it->second;
}

int ScriptChecks::check_lattice_level(const std::string& name, const std::optional<int>& level,
                                      const std::string& pointer) const {
  const DeformerShape& shape = deformer_of(name, pointer + "/lattice");
  if (!shape.has_levels && level) fail(pointer + "/level", "level is for octree lattices");
  if (level && *level > shape.levels)
    fail(pointer + "/level", "lattice '" + name + "' has levels 0 to " + std::to_string(shape.levels));
  return level.value_or(shape.levels);
}

void ScriptChecks::check_point_index(const DeformerShape& shape, int level, const PointIndex& index,
                                     const std::string& pointer) const {
  if (const std::optional<std::string> form = index_form_problem(index, shape.grid, shape.noun)) fail(pointer, *form);
  if (const std::optional<std::string> movable = shape.unmovable(level, index))
    fail(pointer, "point " + index.text() + " is not movable (movable: " + *movable + ")");
}

void ScriptChecks::check_new_lattice(const std::string& name, const std::string& pointer) const {
  if (deformers.count(name)) fail(pointer, "a lattice named '" + name + "' already exists");
}

}  // namespace ffd
