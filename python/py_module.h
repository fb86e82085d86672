// The pieces of the Python module `ffdtool._ffdtool`, each binding one part of the
// library (module.cpp puts them together).
#pragma once

#include <memory>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "script/scene.h"

namespace ffd::py {

namespace pb = pybind11;

/// A mesh as Python holds it: the scene a run left (its warp stack carries the file's
/// normals when it is written, as the CLI does) or a scene holding only a mesh read or
/// made from arrays. Arrays handed out view scene->mesh, which never changes its vertex
/// count: a run makes a new PyMesh.
struct PyMesh {
  std::shared_ptr<Scene> scene;
  std::string file;  // the file it was read from, or ""
};

/// Sets the OpenMP thread count of the calling thread for a scope (0: leave it), and
/// puts the old one back.
class ThreadScope {
public:
  explicit ThreadScope(int threads);
  ~ThreadScope();
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;

private:
  int old_ = 0;
};

void bind_errors(pb::module_& m);
void bind_mesh(pb::module_& m);
void bind_run(pb::module_& m);
void bind_deformers(pb::module_& m);

}  // namespace ffd::py
