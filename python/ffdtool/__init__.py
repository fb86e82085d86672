"""ffdtool: free-form deformation of meshes, on numpy arrays.

The same library as the ffdtool command: its readers and writers, its scripts and its
deformers, with the CLI's numbers bit for bit. Vertices and control points are numpy
views of ffdtool's memory; kernels run without the GIL.

    import ffdtool, numpy as np
    mesh = ffdtool.read("bunny.obj")
    lat = ffdtool.BSplineLattice(mesh, cells=[4, 4, 4])
    lat.move([3, 3, 3], by=[0, 0, 0.01])
    moved = lat(mesh.vertices)                 # (n, 3), any points
    out, stats = ffdtool.run(mesh, {"version": 1, "steps": [...]})
    out.write("out.ply")

Errors raise ffdtool.InputError, TopologyError, SolverError or IoError; str() is the
CLI's one line, with .message and .place (a file and line, or a JSON pointer).
"""
import json as _json
import os as _os
import warnings as _warnings

import numpy as _np

from ._ffdtool import Error, InputError, IoError, Mesh, SolverError, TopologyError, read
from . import _ffdtool

__all__ = ["Mesh", "read", "run", "Deformer", "BSplineLattice", "BernsteinLattice", "OctreeLattice", "RBF", "IDW",
           "Cage", "Error", "InputError", "TopologyError", "SolverError", "IoError", "FfdWarning"]


class FfdWarning(UserWarning):
    """A warning of a run (the stats' "warnings"): something kept, dropped or approximated."""


def _jsonable(value):
    if isinstance(value, _np.ndarray):
        return value.tolist()
    if isinstance(value, _np.generic):
        return value.item()
    if isinstance(value, _os.PathLike):
        return _os.fspath(value)
    raise TypeError(f"{type(value).__name__} is not a JSON value")


def _dumps(value):
    return _json.dumps(value, default=_jsonable)


def _script_args(script):
    """(text, path) for _run: text "" means read the file at path."""
    if isinstance(script, dict):
        return _dumps(script), "script"
    if isinstance(script, _os.PathLike):
        return "", _os.fspath(script)
    if isinstance(script, str):
        return (script, "script") if script.lstrip().startswith("{") else ("", script)
    raise TypeError("script: expected a dict, a JSON string or a path, got " + type(script).__name__)


def run(mesh, script, threads=None, save_folder=None, quiet=True):
    """Runs a script's steps on a mesh, as `ffdtool run` does, without writing the mesh.

    Parameters:
        mesh: a Mesh (left unchanged: the run works on a copy) or a mesh file's path.
        script: a dict, JSON text, or a script file's path (its folder is where its
            relative files are; for a dict or text, the current folder).
        threads: OpenMP threads for this run (None: OpenMP's default). The result is
            the same bytes for any count.
        save_folder: where `save` steps' paths are relative to (None: the current folder).
            Their files are put in place only when every step succeeded.
        quiet: False prints each step's line on stderr, as the CLI does.

    Returns:
        (Mesh, stats): the deformed mesh (write() writes what the CLI would), and the
        stats as a dict, the same keys as the CLI's stats.json (the output names no
        file). Each of the stats' warnings is also issued as an FfdWarning.

    Raises:
        InputError (with .place, the script's JSON pointer or the file and line),
        TopologyError, SolverError, IoError.
    """
    text, path = _script_args(script)
    source = _os.fspath(mesh) if isinstance(mesh, (str, _os.PathLike)) else mesh
    if not isinstance(source, (str, Mesh)):
        raise TypeError("mesh: expected an ffdtool.Mesh or a path, got " + type(mesh).__name__)
    folder = "" if save_folder is None else _os.fspath(save_folder)
    out, stats_text = _ffdtool._run(source, text, path, folder, int(threads or 0), bool(quiet))
    stats = _json.loads(stats_text)
    for warning in stats.get("warnings", []):
        _warnings.warn(warning, FfdWarning, stacklevel=2)
    return out, stats


def _csr(arrays):
    """scipy.sparse.csr_matrix when scipy is importable, else (data, indices, indptr, shape)."""
    try:
        from scipy.sparse import csr_matrix
    except ImportError:
        return arrays
    data, indices, indptr, shape = arrays
    return csr_matrix((data, indices, indptr), shape=shape)


class Deformer(_ffdtool.Deformer):
    """A deformer with control points; make one with BSplineLattice, BernsteinLattice,
    OctreeLattice, RBF, IDW or Cage, whose keyword arguments are the script op's keys.

    points(level) is a view of the control points; move, drag and writes into that view
    move them; calling the deformer on (n, 3) points applies it.
    """

    def __init__(self, op, around, label, **keys):
        step = {"op": op, "name": "d"}
        step.update({k: v for k, v in keys.items() if v is not None})
        super().__init__()
        self._make(_dumps(step), around, label)

    def __call__(self, points, jacobians=False, threads=None, out=None):
        """F(points) for (n, 3) float points (input space): an (n, 3) float64 array, and
        with jacobians=True also (n, 3, 3) Jacobians J[i, r, c] = dF_r/dx_c.
        A C-contiguous float64 input is read in place (no copy); `out`, a writable
        C-contiguous (n, 3) float64 array apart from `points`, takes the result instead of
        a new array (no allocation in a loop)."""
        return self._apply(points, bool(jacobians), int(threads or 0), out)

    def weights(self, points, level=None, threads=None):
        """The movable control points' weights w_j(x) at (n, 3) points: an (n, num_points)
        scipy.sparse.csr_matrix (or its (data, indices, indptr, shape) without scipy).
        F(x) - x = W (P - P_rest) for the level's points P."""
        return _csr(self._weights(points, level, int(threads or 0)))

    def sensitivity(self, mesh, level=None, threads=None):
        """dx/dp: the derivative of each vertex of `mesh` (a Mesh or (n, 3) points, input
        space) with respect to the level's movable points, a (3 n, 3 m) CSR matrix, row
        3 v + axis, column 3 k + axis for the k-th movable point (movable() order), as the
        CLI's save writes it."""
        return _csr(self._sensitivity(mesh, level, int(threads or 0)))

    def __repr__(self):
        try:
            return f"<ffdtool.{type(self).__name__} {self.kind}, {self.num_points()} points, {self.num_levels} level(s)>"
        except Error as e:
            return f"<ffdtool.{type(self).__name__}: {e.message}>"


class BSplineLattice(Deformer):
    """A uniform B-spline lattice (the script's lattice op with basis "bspline").

    mesh: a Mesh or (n, 3) points the box is fitted around (or None with an explicit box);
    cells: [l, m, n] knot spans; degree: 1 to 3; box: the script's box (default
    {"fit": "aabb", "padding": 0.05}). The identity outside the box, C^(degree-1) across it.
    """

    def __init__(self, mesh, cells, degree=3, box=None):
        super().__init__("lattice", mesh, "BSplineLattice", basis="bspline", cells=cells, degree=degree, box=box)


class BernsteinLattice(Deformer):
    """Sederberg & Parry's Bézier volume (the lattice op with basis "bernstein"):
    cells are the degrees per axis, box as BSplineLattice's."""

    def __init__(self, mesh, cells, box=None):
        super().__init__("lattice", mesh, "BernsteinLattice", basis="bernstein", cells=cells, box=box)


class OctreeLattice(Deformer):
    """Ono et al.'s multiresolution lattice fitted to a mesh (basis "octree"): levels
    0..levels, cc_steps Catmull-Clark volume subdivisions, box, shrink as in scripts."""

    def __init__(self, mesh, levels=3, cc_steps=2, box=None, shrink=None):
        super().__init__("lattice", mesh, "OctreeLattice", basis="octree", levels=levels, cc_steps=cc_steps, box=box,
                         shrink=shrink)


class RBF(Deformer):
    """PyGeM's RBF: control points `points` (k, 3) at rest, a kernel, its radius and k;
    moves give the targets the map interpolates."""

    def __init__(self, points, kernel="gaussian_spline", radius=0.5, k=2):
        super().__init__("rbf", None, "RBF", points=points, kernel=kernel, radius=radius, k=k)


class IDW(Deformer):
    """Shepard's inverse-distance weighting: x + sum w_i d_i / sum w_i, w_i = |x - x_i|^-power."""

    def __init__(self, points, power=2.0):
        super().__init__("idw", None, "IDW", points=points, power=power)


class Cage(Deformer):
    """A mean-value-coordinates cage: `cage` is a closed, consistently oriented mesh file
    (relative paths from the current folder); its vertices are the control points,
    numbered as in the file. Points are evaluated afresh at every call (no binding)."""

    def __init__(self, cage, coordinates="mean_value"):
        super().__init__("cage", None, "Cage", cage=_os.fspath(cage), coordinates=coordinates)
