// ffdtool._ffdtool: the compiled half of the Python package ffdtool (python/ffdtool/
// __init__.py holds the other: scripts as dicts, stats as dicts, the deformer classes'
// keyword arguments, scipy's sparse matrices).
#include "py_module.h"

PYBIND11_MODULE(_ffdtool, m) {
  m.doc() = "ffdtool's meshes, scripts and deformers on numpy arrays (the compiled part; import ffdtool).";
  ffd::py::bind_errors(m);
  ffd::py::bind_mesh(m);
  ffd::py::bind_run(m);
  ffd::py::bind_deformers(m);
}
