#!/usr/bin/python3
"""bench_users_pygem.py --points F --out O --pygem SRC [--repeats N]: PyGeM's side of
`ffdbench --suite users` (its cloud_move_step row), which runs it and compares.

F holds n x 3 float64 points (raw, written by ffdbench, which also writes them as the
binary PLY `ffdtool run` reads). Times PyGeM's FFD (its source at SRC; Debian's numpy and
scipy) with the python suite's Bernstein lattice (bench_python.pygem_moved_ffd: 4^3
control points on [0,1]^3, point [1,1,1] moved by 0.1 on each axis) on all of them, the
median of N runs after a warm-up, writes the deformed points to O (raw float64, n x 3) for
ffdbench to compare with ffdtool's output, and prints {"points": n, "ms": median} on stdout.
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_python import median_ms, pygem_moved_ffd  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for name in ("--points", "--out", "--pygem"):
        parser.add_argument(name, required=True)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    points = np.fromfile(args.points, dtype=np.float64).reshape(-1, 3)
    ffd = pygem_moved_ffd(args.pygem)
    ms = median_ms(max(1, args.repeats), lambda: ffd(points))
    np.ascontiguousarray(ffd(points), dtype=np.float64).tofile(args.out)
    json.dump({"points": len(points), "ms": ms}, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
