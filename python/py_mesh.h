// ffdtool.Mesh: a mesh whose vertices are a numpy view of its memory.
#pragma once

#include "py_module.h"

namespace ffd::py {

/// The mesh a run starts from: a copy of `source`'s, taken as a file read now would be.
/// A run's result has its deformation baked in (rest := current, file normals carried);
/// a mesh whose vertices were written in place gets them as its rest positions and its
/// normals recomputed.
Mesh run_input(const PyMesh& source);

}  // namespace ffd::py
