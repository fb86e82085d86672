#!/usr/bin/python3
"""pygem_rbf_timing.py PYGEM_SOURCE [FFDTOOL]: set-up and evaluation time, PyGeM's RBF against ffdtool's rbf op.

Times, in one run and on the same points, PyGeM's own RBF (loaded from PYGEM_SOURCE/pygem
as pygem_rbf_compare.py does) and `ffdtool run` with an rbf step and a move step, for
1,000 control points and 100,000 points uniform in [0,1]^3 (numpy default_rng, seed 7;
the control points are a separate uniform draw, their targets the control points plus
uniform(-0.05, 0.05)):
  case A: gaussian_spline, radius 0.1;  case B: thin_plate_spline, radius 0.5, k 2.
The Gaussian's radius is the control points' spacing (1000^(-1/3)): at 0.5 its system has
condition number ~1e21, which ffdtool refuses as singular and PyGeM solves without a word.
PyGeM: set-up is RBF(X, Y, ...) (its weights solve), evaluation is rbf(points) (which, in
PyGeM, solves for the weights again before evaluating); wall is the two together.
Each is timed with time.perf_counter and numpy uses whatever BLAS/LAPACK it is linked to.
ffdtool: set-up is the rbf step's ms in the --stats JSON (the system's LU factorization),
evaluation the move step's (one solve with that factor, then every point, with its
Jacobian); wall is the whole process (reading the ASCII PLY cloud, writing OBJ included).
ffdtool runs with --threads 1 and with its default (all cores). Every figure is the best
of 3 runs, each column on its own. The table gives PyGeM/ffdtool ratios and the largest
|ffdtool - PyGeM| over the cloud's bounding-box diagonal.
"""
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pygem_rbf_compare import ROOT, load_pygem_rbf, obj_vertices  # noqa: E402

N_POINTS, N_CONTROL, SEED, REPEATS = 100_000, 1_000, 7, 3
CASES = [("A", "gaussian_spline", 0.1, 2), ("B", "thin_plate_spline", 0.5, 2)]


def make_data():
    """The evaluation points, the control points and their targets."""
    rng = np.random.default_rng(SEED)
    points = rng.uniform(0, 1, (N_POINTS, 3))
    X = rng.uniform(0, 1, (N_CONTROL, 3))
    return points, X, X + rng.uniform(-0.05, 0.05, X.shape)


def write_inputs(tmp, points, X, Y):
    """points.ply (ASCII, vertices only), x.txt and y.txt in tmp."""
    with open(os.path.join(tmp, "points.ply"), "w") as f:
        f.write(f"ply\nformat ascii 1.0\nelement vertex {len(points)}\n"
                "property double x\nproperty double y\nproperty double z\nend_header\n")
        np.savetxt(f, points, fmt="%.17g")
    np.savetxt(os.path.join(tmp, "x.txt"), X, fmt="%.17g")
    np.savetxt(os.path.join(tmp, "y.txt"), Y, fmt="%.17g")


def time_pygem(rbf_class, points, X, Y, kernel, radius, k):
    """(set-up ms, evaluation ms, wall s) best of REPEATS, and PyGeM's moved points."""
    extra = {"k": k} if kernel in ("thin_plate_spline", "polyharmonic_spline") else None
    runs = []
    for _ in range(REPEATS):
        with np.errstate(divide="ignore", invalid="ignore"):  # PyGeM's log(0) at the control points
            t0 = time.perf_counter()
            rbf = rbf_class(X, Y, func=kernel, radius=radius, extra_parameter=extra)
            t1 = time.perf_counter()
            moved = rbf(points)
            t2 = time.perf_counter()
        runs.append(((t1 - t0) * 1e3, (t2 - t1) * 1e3, t2 - t0))
        del rbf
    return tuple(np.min(runs, axis=0)), moved


def time_ffdtool(ffdtool, tmp, kernel, radius, k, threads):
    """(set-up ms, evaluation ms, wall s) best of REPEATS, the threads used, the moved points."""
    script, out, stats = (os.path.join(tmp, name) for name in ("s.json", "out.obj", "stats.json"))
    with open(script, "w") as f:
        json.dump({"version": 1, "steps": [
            {"op": "rbf", "name": "R", "kernel": kernel, "radius": radius, "k": k, "points": {"file": "x.txt"}},
            {"op": "move", "lattice": "R", "positions": {"file": "y.txt"}}]}, f)
    cmd = [ffdtool, "run", os.path.join(tmp, "points.ply"), script, "-o", out, "--stats", stats, "--quiet"]
    cmd += ["--threads", str(threads)] if threads else []
    runs = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True)
        wall = time.perf_counter() - t0
        with open(stats) as f:
            report = json.load(f)
        runs.append((report["steps"][0]["ms"], report["steps"][1]["ms"], wall))
    return tuple(np.min(runs, axis=0)), report["threads"], obj_vertices(out)


def row(case, kernel, tool, threads, times, ratios="", agreement=""):
    return (f"{case:<2} {kernel:<18} {tool:<8} {threads:>7} {times[0]:>10.1f} {times[1]:>10.1f} {times[2]:>7.2f}"
            f" {ratios:>22} {agreement:>12}")


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    rbf_class = load_pygem_rbf(argv[1])
    ffdtool = argv[2] if len(argv) > 2 else os.path.join(ROOT, "build", "apps", "ffdtool", "ffdtool")
    points, X, Y = make_data()
    diag = np.linalg.norm(points.max(0) - points.min(0))
    print(f"{N_CONTROL} control points x {N_POINTS} points, best of {REPEATS}; "
          f"ratios are PyGeM/ffdtool (set-up, evaluation, wall)")
    print(f"{'':2} {'kernel':<18} {'tool':<8} {'threads':>7} {'set-up ms':>10} {'eval ms':>10} {'wall s':>7}"
          f" {'PyGeM/ffdtool':>22} {'max|d|/diag':>12}")
    with tempfile.TemporaryDirectory() as tmp:
        write_inputs(tmp, points, X, Y)
        for case, kernel, radius, k in CASES:
            pygem, expected = time_pygem(rbf_class, points, X, Y, kernel, radius, k)
            print(row(case, kernel, "PyGeM", "-", pygem))
            for threads in (1, 0):
                times, used, moved = time_ffdtool(ffdtool, tmp, kernel, radius, k, threads)
                ratios = " ".join(f"{p / t:6.2f}" for p, t in zip(pygem, times))
                error = np.abs(moved - expected).max() / diag
                print(row(case, kernel, "ffdtool", used, times, ratios, f"{error:.2e}"), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
