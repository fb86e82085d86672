"""The volume suite's mesh and its meshio baseline (apps/ffdbench/bench_volume.cpp).

    /usr/bin/python3 scripts/bench_volume_meshio.py FOLDER N

Makes a tetrahedral mesh of the unit cube on an N^3 grid of nodes (each grid cube split
into Kuhn's six tetrahedra, all positively oriented; N = 100: 1M nodes, 5.8M tets), the
nodes jittered a little so no coordinate is round, and writes it with meshio as
FOLDER/tets.vtu (binary, base64 without compression), FOLDER/tets_zlib.vtu (meshio's
default binary VTU: zlib blocks), FOLDER/tets.msh (MSH 4.1 binary) and FOLDER/tets.su2
(ASCII). Then, per file, times meshio reading it and writing it back (its points and
cells) in the same format, and prints one JSON object:
{"nodes": ..., "cells": ..., "meshio": {"vtu": {"file": ..., "read_ms": ..., "write_ms": ..., "bytes": ...}, ...}}.
"""
import json
import os
import sys
import time

import meshio
import numpy as np

# name -> (file, meshio's writer options)
FORMATS = {"vtu": ("tets.vtu", {"file_format": "vtu", "binary": True, "compression": None}),
           "vtu_zlib": ("tets_zlib.vtu", {"file_format": "vtu", "binary": True, "compression": "zlib"}),
           "msh": ("tets.msh", {"file_format": "gmsh", "binary": True}),
           "su2": ("tets.su2", {"file_format": "su2"})}


def tet_grid(n):
    g = np.arange(n)
    x, y, z = np.meshgrid(g, g, g, indexing="ij")
    rng = np.random.default_rng(1)
    points = np.stack([x.ravel(order="F"), y.ravel(order="F"), z.ravel(order="F")], axis=1) / (n - 1)
    points += rng.uniform(-0.1, 0.1, points.shape) / (n - 1)
    c = np.arange(n - 1)
    i, j, k = np.meshgrid(c, c, c, indexing="ij")
    base = (i + n * (j + n * k)).ravel()
    corner = [base + dx + n * (dy + n * dz) for dz in (0, 1) for dy in (0, 1) for dx in (0, 1)]
    kuhn = [(0, 1, 3, 7), (0, 1, 7, 5), (0, 4, 5, 7), (0, 2, 6, 7), (0, 3, 2, 7), (0, 6, 4, 7)]
    tets = np.concatenate([np.stack([corner[a], corner[b], corner[c_], corner[d]], axis=1) for a, b, c_, d in kuhn])
    p = points[tets]
    flip = np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) < 0
    tets[flip, 2], tets[flip, 3] = tets[flip, 3], tets[flip, 2].copy()
    return points, tets


def main():
    folder, n = sys.argv[1], int(sys.argv[2])
    points, tets = tet_grid(n)
    mesh = meshio.Mesh(points, [("tetra", tets.astype(np.int64))])
    result = {"nodes": len(points), "cells": len(tets), "meshio": {}}
    for name, (file, options) in FORMATS.items():
        path = os.path.join(folder, file)
        out = os.path.join(folder, "meshio_out_" + file)
        meshio.write(path, mesh, **options)
        os.sync()  # the file on disk before timing, as ffdbench does before each ffdtool run
        start = time.perf_counter()
        read = meshio.read(path)
        middle = time.perf_counter()
        # Points and cells only: meshio 7.0 cannot write back the MSH 4.1 it read (its
        # entities' tags go missing), and the other formats carry nothing more here.
        meshio.write(out, meshio.Mesh(read.points, read.cells), **options)
        end = time.perf_counter()
        result["meshio"][name] = {"file": file, "read_ms": 1e3 * (middle - start), "write_ms": 1e3 * (end - middle),
                                  "bytes": os.path.getsize(path)}
        os.remove(out)
    print(json.dumps(result))


if __name__ == "__main__":
    main()
