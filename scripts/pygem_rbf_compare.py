#!/usr/bin/python3
"""pygem_rbf_compare.py PYGEM_SOURCE [FFDTOOL]: ffdtool's rbf op against PyGeM's RBF.

Runs PyGeM's own RBF (its source tree, PYGEM_SOURCE/pygem; Debian's python3-numpy,
python3-scipy and python3-matplotlib, which its import needs) and `ffdtool run` on the
bundled bunny with the same 40 control points and targets, for every PyGeM kernel, and
prints the largest vertex difference over the bounding box's diagonal. Nothing is
installed: PyGeM is loaded from the folder given (its package imports only what these
modules need).
"""
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import types

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
KERNELS = [("gaussian_spline", 4, 2), ("multi_quadratic_biharmonic_spline", 1, 2),
           ("inv_multi_quadratic_biharmonic_spline", 2, 2), ("thin_plate_spline", 3, 2),
           ("beckert_wendland_c2_basis", 9, 2), ("polyharmonic_spline", 5, 3), ("polyharmonic_spline", 5, 2)]


def load_pygem_modules(source, names):
    """PyGeM's modules `names` (in order) from source/pygem, without its package __init__
    (CAD readers); returns the last."""
    pkg = types.ModuleType("pygem")
    pkg.__path__ = [os.path.join(source, "pygem")]
    sys.modules["pygem"] = pkg
    for name in names:
        spec = importlib.util.spec_from_file_location("pygem." + name, os.path.join(source, "pygem", name + ".py"))
        module = importlib.util.module_from_spec(spec)
        sys.modules["pygem." + name] = module
        spec.loader.exec_module(module)
        if name == "deformation":  # `from pygem import Deformation`
            pkg.Deformation = module.Deformation
    return module


def load_pygem_rbf(source):
    """PyGeM's RBF class from source/pygem."""
    return load_pygem_modules(source, ("deformation", "rbf_factory", "rbf")).RBF


def obj_vertices(path):
    with open(path) as f:
        return np.array([[float(t) for t in line.split()[1:4]] for line in f if line.startswith("v ")])


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    rbf_class = load_pygem_rbf(argv[1])
    ffdtool = argv[2] if len(argv) > 2 else os.path.join(ROOT, "build", "apps", "ffdtool", "ffdtool")
    bunny = os.path.join(ROOT, "test_data", "bunny.obj")
    V = obj_vertices(bunny)
    diag = np.linalg.norm(V.max(0) - V.min(0))
    X = V[list(range(0, len(V), 46))[:40]]
    Y = X + np.random.default_rng(1).uniform(-0.3, 0.3, X.shape)
    with tempfile.TemporaryDirectory() as tmp:
        np.savetxt(os.path.join(tmp, "x.txt"), X, fmt="%.17g")
        np.savetxt(os.path.join(tmp, "y.txt"), Y, fmt="%.17g")
        for name, radius, k in KERNELS:
            extra = {"k": k} if name in ("thin_plate_spline", "polyharmonic_spline") else None
            with np.errstate(divide="ignore", invalid="ignore"):  # PyGeM's log(0) at the control points
                expected = rbf_class(X, Y, func=name, radius=radius, extra_parameter=extra)(V)
            script = os.path.join(tmp, "s.json")
            with open(script, "w") as f:
                json.dump({"version": 1, "steps": [
                    {"op": "rbf", "name": "R", "kernel": name, "radius": radius, "k": k, "points": {"file": "x.txt"}},
                    {"op": "move", "lattice": "R", "positions": {"file": "y.txt"}}]}, f)
            out = os.path.join(tmp, "out.obj")
            subprocess.run([ffdtool, "run", bunny, script, "-o", out, "--quiet"], check=True)
            error = np.abs(obj_vertices(out) - expected).max() / diag
            print(f"{name} (radius {radius}, k {k}): max |ffdtool - PyGeM| / diagonal = {error:.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
