#include "script/scene.h"

#include "common/errors.h"
#include "mesh/volume_mesh.h"

namespace ffd {

WriteOptions Scene::write_options() const {
  WriteOptions options;
  if (stack.size() > 0)
    options.transform_normal = [this](std::uint32_t v, const Eigen::Vector3d& n) {
      return stack.transform_normal(mesh, v, n);
    };
  return options;
}

namespace {

void check_not_baked(const Scene& scene, const std::string& name) {
  auto b = scene.baked.find(name);
  if (b != scene.baked.end())
    throw InputError("lattice '" + name + "' was frozen into the mesh by the surface edit at " + b->second +
                         "; create a new lattice to deform further",
                     {"lattice"});
}

}  // namespace

Deformer& Scene::deformer(const std::string& name) {
  check_not_baked(*this, name);
  return *deformers.at(name);
}

void require_surface_mesh(const Mesh& mesh, const std::string& op) {
  const VolumeSource* volume = mesh.volume_source();
  if (!volume) return;
  throw InputError(op + " acts on surface meshes, and " + mesh.source() + " is a " + volume_format_name(volume->format) +
                   " volume mesh: its nodes move with the space warps (lattice, rbf, idw, cage, drag, move), but " + op +
                   " would change or need a surface it does not have");
}

}  // namespace ffd
