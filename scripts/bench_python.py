#!/usr/bin/python3
"""bench_python.py --points F --mesh M --script S --ffdtool T [--pygem SRC] [--repeats N]:
the Python module's side of `ffdbench --suite python`, which runs it and prints the table.

Prints one JSON object on stdout, every time a median of --repeats runs after a warm-up
(time.perf_counter):
- "module": ffdtool's d(points, out=) and d(points) on the first tenth and all of F's
  points (raw float64, n x 3, written by ffdbench, which times the C++ kernel,
  warp_points, on the same points), for a cubic B-spline lattice of 4^3 cells and a
  Bernstein lattice of degree 3
  (4^3 points) on the box [0,1]^3, each with one point moved by (0.1, 0.1, 0.1), with
  1 and 2 threads;
- "call_overhead_us": one call of d(x, out=) on a single point, in microseconds;
- "pygem": PyGeM's FFD (its source at SRC; Debian's numpy and scipy) with 4^3 control
  points on the same box and the same move, on the same points, and the largest
  |ffdtool - PyGeM| (absent without --pygem);
- "run": ffdtool.run(mesh, S) on mesh M read beforehand, against `ffdtool run M S -o OUT`
  as a process (wall time, and its stats' read, steps and write), 1 and 2 threads.
The module comes from PYTHONPATH (ffdbench sets it to the build's python folder).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

try:
    import ffdtool
except ImportError:  # bench_users_pygem.py imports this file for its PyGeM helpers alone
    ffdtool = None

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pygem_rbf_compare import load_pygem_modules  # noqa: E402

BOX = {"min": [0, 0, 0], "max": [1, 1, 1]}
MOVE = [0.1, 0.1, 0.1]


def median_ms(repeats, fn):
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t0) * 1e3)
    return float(np.median(times))


def lattices():
    bspline = ffdtool.BSplineLattice(None, cells=[4, 4, 4], degree=3, box=BOX)
    bspline.move([2, 2, 2], by=MOVE)
    bernstein = ffdtool.BernsteinLattice(None, cells=[3, 3, 3], box=BOX)
    bernstein.move([1, 1, 1], by=MOVE)
    return {"bspline": bspline, "bernstein": bernstein}


def load_pygem_ffd(source):
    """PyGeM's FFD class from source/pygem (as pygem_rbf_compare.py loads its RBF)."""
    return load_pygem_modules(source, ("deformation", "utils", "ffd")).FFD


def pygem_moved_ffd(source):
    """PyGeM's FFD with 4^3 control points on the box [0,1]^3 and point [1,1,1] moved by
    MOVE: the suite's Bernstein lattice. PyGeM's mu are fractions of the box's length,
    which is 1 here, so they are MOVE itself."""
    ffd = load_pygem_ffd(source)([4, 4, 4])
    ffd.box_origin = np.array(BOX["min"], dtype=float)
    ffd.box_length = np.array(BOX["max"], dtype=float) - ffd.box_origin
    ffd.array_mu_x[1, 1, 1], ffd.array_mu_y[1, 1, 1], ffd.array_mu_z[1, 1, 1] = MOVE
    return ffd


def module_rows(points, repeats):
    """d(x, out=...) as ffdbench times the kernel (into the same array each time), and
    d(x) into a new array each call."""
    rows = []
    for kind, d in lattices().items():
        for n in (len(points) // 10, len(points)):
            x = points[:n]
            out = np.empty_like(x)
            for threads in (1, 2):
                rows.append({"kind": kind, "points": n, "threads": threads,
                             "ms": median_ms(repeats, lambda: d(x, threads=threads, out=out)),
                             "new_array_ms": median_ms(repeats, lambda: d(x, threads=threads))})
    return rows


def call_overhead_us(calls=5000):
    """What one d(x, out=...) call on one point costs, in microseconds: the binding's own
    work (arguments, GIL, lock, the check for written points) beside the kernel's."""
    d = lattices()["bspline"]
    x = np.full((1, 3), 0.5)
    out = np.empty_like(x)
    d(x, out=out)
    t0 = time.perf_counter()
    for _ in range(calls):
        d(x, out=out)
    return (time.perf_counter() - t0) / calls * 1e6


def pygem_rows(points, source, repeats):
    ffd = pygem_moved_ffd(source)
    bernstein = lattices()["bernstein"]
    rows = []
    for n in (100_000, len(points)):
        x = points[:n]
        ms = median_ms(max(1, repeats // 2), lambda: ffd(x))
        rows.append({"points": n, "ms": ms, "max_abs_difference": float(np.abs(ffd(x) - bernstein(x)).max())})
    return rows


def run_rows(args):
    mesh = ffdtool.read(args.mesh)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out, stats_file = os.path.join(tmp, "out.obj"), os.path.join(tmp, "stats.json")
        for threads in (1, 2):
            memory_ms = median_ms(args.repeats, lambda: ffdtool.run(mesh, args.script, threads=threads))
            cli = [args.ffdtool, "run", args.mesh, args.script, "-o", out, "--stats", stats_file, "--quiet",
                   "--threads", str(threads)]
            cli_ms = median_ms(args.repeats, lambda: subprocess.run(cli, check=True))
            stats = json.load(open(stats_file))
            rows.append({"threads": threads, "run_in_memory_ms": memory_ms, "cli_process_ms": cli_ms,
                         "cli_read_ms": stats["input"]["read_ms"], "cli_steps_ms": stats["totals"]["steps_ms"],
                         "cli_write_ms": stats["output"]["write_ms"]})
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for name in ("--points", "--mesh", "--script", "--ffdtool"):
        parser.add_argument(name, required=True)
    parser.add_argument("--pygem", default="")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    points = np.fromfile(args.points, dtype=np.float64).reshape(-1, 3)
    result = {"module": module_rows(points, args.repeats), "call_overhead_us": call_overhead_us()}
    if args.pygem:
        result["pygem"] = pygem_rows(points, args.pygem, args.repeats)
    result["run"] = run_rows(args)
    json.dump(result, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
