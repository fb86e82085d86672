#!/usr/bin/python3
"""Writes the outputs that every speed change must keep byte for byte (issue #25).

Runs a fixed set of scripts (cubic B-spline and Bernstein lattice moves, an octree
lattice moved at each of its levels 0-5, and boundary-constraint modeling with detail,
one pose and 200 frames)
on the bundled bunny, CGAL's elephant, the shared meshes, a 100k-vertex UV sphere with
normals (OBJ) and a 100k-point cloud (binary PLY), each with --threads 1 and 2, into
OUT/<mesh>/<job>/t<threads>/. Two such folders are the same when `diff -r` finds nothing
and `ffdtool compare --recursive --tolerance 0` says same.

Usage: scripts/speed_goldens.py FFDTOOL OUT [--meshes DIR]
"""
import argparse
import json
import math
import os
import pathlib
import subprocess
import sys
import tarfile

ROOT = pathlib.Path(__file__).resolve().parent.parent


def sphere_obj(path, rings=250, segments=400):
    """A UV sphere of (rings - 1) * segments + 2 vertices with unit normals (vn)."""
    if path.exists():
        return
    verts = [(0.0, 1.0, 0.0)]
    for r in range(1, rings):
        phi = math.pi * r / rings
        for s in range(segments):
            theta = 2 * math.pi * s / segments
            verts.append((math.sin(phi) * math.cos(theta), math.cos(phi), math.sin(phi) * math.sin(theta)))
    verts.append((0.0, -1.0, 0.0))
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in verts]
    lines += [f"vn {x!r} {y!r} {z!r}" for x, y, z in verts]
    ring = lambda r, s: 2 + (r - 1) * segments + s % segments  # 1-based
    for s in range(segments):
        lines.append(f"f 1//1 {ring(1, s + 1)}//{ring(1, s + 1)} {ring(1, s)}//{ring(1, s)}")
    for r in range(1, rings - 1):
        for s in range(segments):
            a, b, c, d = ring(r, s), ring(r, s + 1), ring(r + 1, s + 1), ring(r + 1, s)
            lines.append(f"f {a}//{a} {b}//{b} {c}//{c} {d}//{d}")
    last = len(verts)
    for s in range(segments):
        a, b = ring(rings - 1, s), ring(rings - 1, s + 1)
        lines.append(f"f {a}//{a} {b}//{b} {last}//{last}")
    path.write_text("\n".join(lines) + "\n")


def cloud_ply(path, count=100_000):
    """`count` points in [0, 1]^3 from a fixed linear congruential sequence (binary PLY)."""
    if path.exists():
        return
    import struct
    state, values = 12345, []
    for _ in range(3 * count):
        state = (6364136223846793005 * state + 1442695040888963407) % 2**64
        values.append((state >> 11) / 2**53)
    header = f"ply\nformat binary_little_endian 1.0\nelement vertex {count}\n"
    header += "property double x\nproperty double y\nproperty double z\nend_header\n"
    path.write_bytes(header.encode() + struct.pack(f"<{3 * count}d", *values))


def cgal_elephant(cache):
    path = cache / "elephant.off"
    if not path.exists():
        with tarfile.open("/usr/share/doc/libcgal-dev/data.tar.gz") as tar:
            path.write_bytes(tar.extractfile("data/meshes/elephant.off").read())
    return path


def info(ffdtool, mesh):
    out = subprocess.run([ffdtool, "info", "--json", str(mesh)], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def jobs(box_min, box_max):
    """The scripts, from the mesh's bounding box."""
    centre = [(a + b) / 2 for a, b in zip(box_min, box_max)]
    size = max(b - a for a, b in zip(box_min, box_max))
    by = [0.05 * size, 0.08 * size, -0.03 * size]
    near = lambda f: [a + f * (b - a) for a, b in zip(box_min, box_max)]

    def lattice(basis, extra, fit="aabb"):
        return [{"op": "lattice", "name": "L", "basis": basis, "box": {"fit": fit, "padding": 0.05}, **extra},
                {"op": "move", "lattice": "L", "select": {"near": centre}, "transform": {"translate": by}}]

    octree = [{"op": "lattice", "name": "L", "basis": "octree", "box": {"fit": "obb", "padding": 0.02},
               "levels": 5, "cc_steps": 2}]
    for level, f in enumerate([0.0, 0.3, 0.6, 0.45, 0.55, 0.5]):
        octree.append({"op": "move", "lattice": "L", "level": level, "select": {"near": near(f)},
                       "transform": {"translate": [0.01 * size, -0.01 * size, 0.005 * size]}})
        if level == 2:
            octree.append({"op": "save", "path": "level2.ply"})
    return {
        "bspline": lattice("bspline", {"degree": 3, "cells": [4, 4, 4]}),
        # A rotated box: box coordinates then mix all three axes, so an evaluation that
        # orders their products differently gives other bits (an axis-aligned box hides it).
        "bspline_obb": lattice("bspline", {"degree": 3, "cells": [5, 4, 6]}, "obb")
        + [{"op": "move", "lattice": "L", "select": {"near": near(0.4)}, "transform": {"translate": by}}],
        # Two stacked lattices: moving the lower one re-evaluates the upper one on a list of
        # ids (the other path of a lattice's evaluation).
        "bspline_stack": lattice("bspline", {"degree": 3, "cells": [5, 4, 6]}, "obb")[:1]
        + [{"op": "lattice", "name": "U", "basis": "bspline", "degree": 2, "cells": [6, 6, 6],
            "box": {"fit": "obb", "padding": 0.1}}]
        + [{"op": "move", "lattice": name, "select": {"near": near(f)}, "transform": {"translate": by}}
           for name, f in (("U", 0.5), ("L", 0.4), ("U", 0.6))],
        "bernstein": lattice("bernstein", {"cells": [3, 3, 3]}),
        "octree": octree,
    }


def run(ffdtool, mesh, steps, folder, threads, suffix):
    folder.mkdir(parents=True, exist_ok=True)
    script = folder / "script.json"
    script.write_text(json.dumps({"version": 1, "steps": steps}, indent=1))
    subprocess.run([ffdtool, "run", str(mesh), str(script), "-o", str(folder / f"out{suffix}"),
                    "--threads", str(threads), "--quiet", "--progress", "none"], check=True)
    script.unlink()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("ffdtool")
    parser.add_argument("out", type=pathlib.Path)
    parser.add_argument("--meshes", type=pathlib.Path, default=ROOT.parent / "shared" / "meshes")
    args = parser.parse_args()
    cache = ROOT / ".cache" / "speed_goldens"
    cache.mkdir(parents=True, exist_ok=True)
    sphere_obj(cache / "sphere_100k.obj")
    cloud_ply(cache / "cloud_100k.ply")
    meshes = [ROOT / "test_data" / "bunny.obj", cgal_elephant(cache), cache / "sphere_100k.obj",
              cache / "cloud_100k.ply"] + sorted(args.meshes.glob("*.off"))
    for mesh in meshes:
        about = info(args.ffdtool, mesh)
        scripts = jobs(about["bbox_min"], about["bbox_max"])
        if about["faces"] == 0:
            del scripts["octree"]  # a point cloud: the lattices' move steps only
        for name, steps in scripts.items():
            for threads in (1, 2):
                run(args.ffdtool, mesh, steps, args.out / mesh.stem / name / f"t{threads}", threads, mesh.suffix)
    bcm = json.loads((ROOT / "test_data" / "bcm_bunny.json").read_text())["steps"]
    # A sequence of poses: its frames choose their thread count as they go (ThreadChoice).
    frames = [bcm[0], {"op": "transform", "editor": "back", "handle": "hump",
                       "frames": [{"translate": [0, 0.01 * i, 0.005 * i]} for i in range(200)]}]
    for name, steps in (("bcm", bcm), ("bcm_frames", frames)):
        for threads in (1, 2):
            run(args.ffdtool, ROOT / "test_data" / "bunny.obj", steps, args.out / "bunny" / name / f"t{threads}",
                threads, ".obj")
    print(f"speed goldens: {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
