#include "script/scene.h"

#include "common/errors.h"

namespace ffd {

WriteOptions Scene::write_options() const {
  WriteOptions options;
  if (stack.size() > 0)
    options.transform_normal = [this](std::uint32_t v, const Eigen::Vector3d& n) {
      return stack.transform_normal(mesh, v, n);
    };
  return options;
}

Lattice& Scene::lattice(const std::string& name) {
  auto b = baked.find(name);
  if (b != baked.end())
    throw InputError("lattice '" + name + "' was frozen into the mesh by the surface edit at " + b->second +
                         "; create a new lattice to deform further",
                     {"lattice"});
  return *lattices.at(name);
}

}  // namespace ffd
