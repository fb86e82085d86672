"""A PLY's every vertex and face property through `ffdtool run`, held against meshio's PLY
reader (Debian's python3-meshio), an implementation independent of ffdtool's.

The bunny is written here as a PLY with what scanners and exporters add (RGBA, a
confidence, an object id per vertex; a quality per face), moved by a lattice, and read
back: every property but the positions must be the input's, value for value and in its
type, and the positions the float32 of what the same run writes as OBJ.
"""
import json
import os

import meshio
import numpy as np
import pytest

import gltf_corpus

FORMATS = ["binary_little_endian", "binary_big_endian", "ascii"]


def bunny_arrays(path):
    points, faces = gltf_corpus.bunny(path)
    return points, faces.astype(np.int32)


def write_ply(path, fmt, points, faces, vertex_props, face_props):
    """A PLY of `fmt` written with numpy alone: vertex x y z float and `vertex_props`,
    face vertex_indices (uchar, int) and `face_props` ({name: array})."""
    n, m = len(points), len(faces)
    order = ">" if fmt == "binary_big_endian" else "<"
    vdtype = [("x", "f4"), ("y", "f4"), ("z", "f4")] + [(k, v.dtype.str[1:]) for k, v in vertex_props.items()]
    fdtype = [("count", "u1"), ("indices", "i4", (3,))] + [(k, v.dtype.str[1:]) for k, v in face_props.items()]
    names = {"f4": "float", "f8": "double", "u1": "uchar", "i4": "int", "i2": "short"}
    header = ["ply", "format %s 1.0" % fmt, "comment ffdtool test", "element vertex %d" % n]
    header += ["property %s %s" % (names[t], k) for k, t in vdtype]
    header += ["element face %d" % m, "property list uchar int vertex_indices"]
    header += ["property %s %s" % (names[t], k) for k, t in fdtype[2:]]
    header += ["end_header"]
    v = np.zeros(n, dtype=[(k, order + t) for k, t in vdtype])
    for k, c in zip("xyz", points.T):
        v[k] = c
    for k, a in vertex_props.items():
        v[k] = a
    f = np.zeros(m, dtype=[(k, order + t, *shape) for k, t, *shape in fdtype])
    f["count"] = 3
    f["indices"] = faces
    for k, a in face_props.items():
        f[k] = a
    with open(path, "wb") as out:
        out.write(("\n".join(header) + "\n").encode())
        if fmt != "ascii":
            out.write(v.tobytes())
            out.write(f.tobytes())
            return
        for row in v:
            out.write((" ".join(repr(x.item()) for x in row) + "\n").encode())
        for row in f:
            out.write(("3 %d %d %d " % tuple(row["indices"]) +
                       " ".join(repr(row[k].item()) for k in face_props) + "\n").encode())


def obj_points(path):
    with open(path) as f:
        return np.array([[float(x) for x in line.split()[1:4]] for line in f if line.startswith("v ")])


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_moved_bunny_keeps_every_other_property(fmt, tmp_path, bunny, run_cli):
    points, faces = bunny_arrays(bunny)
    rng = np.random.default_rng(7)
    n, m = len(points), len(faces)
    vertex_props = {
        "red": rng.integers(0, 256, n).astype(np.uint8),
        "green": rng.integers(0, 256, n).astype(np.uint8),
        "blue": rng.integers(0, 256, n).astype(np.uint8),
        "alpha": rng.integers(0, 256, n).astype(np.uint8),
        "confidence": rng.random(n).astype(np.float32),
        "object_id": rng.integers(-5, 5, n).astype(np.int32),
    }
    # meshio 5.0 reads face properties beside the index list in ASCII files only (its
    # binary reader takes a face row for the list alone), so binary files have none.
    face_props = {"quality": rng.random(m), "label": rng.integers(-300, 300, m).astype(np.int32)}
    if fmt != "ascii":
        face_props = {}
    source = tmp_path / "bunny.ply"
    write_ply(source, fmt, points, faces, vertex_props, face_props)

    script = tmp_path / "move.json"
    script.write_text(json.dumps({"version": 1, "steps": [
        {"op": "lattice", "name": "L", "basis": "bspline", "degree": 3,
         "box": {"fit": "aabb", "padding": 0.05}, "cells": [5, 5, 5]},
        {"op": "move", "lattice": "L", "points": [{"index": [2, 3, 2], "by": [0.4, 0.9, -0.3]}]}]}))
    for out in ["out.ply", "out.obj"]:
        done = run_cli("run", source, script, "-o", tmp_path / out, "--quiet")
        assert done.returncode == 0, done.stderr

    before, after = meshio.read(source), meshio.read(tmp_path / "out.ply")
    assert sorted(after.point_data) == sorted(before.point_data) == sorted(vertex_props)
    for name, values in before.point_data.items():
        assert after.point_data[name].dtype == values.dtype, name
        np.testing.assert_array_equal(after.point_data[name], values, err_msg=name)
    np.testing.assert_array_equal(after.cells_dict["triangle"], before.cells_dict["triangle"])
    assert sorted(after.cell_data) == sorted(face_props)
    for name in face_props:
        np.testing.assert_array_equal(after.cell_data[name][0], before.cell_data[name][0], err_msg=name)
    moved = obj_points(tmp_path / "out.obj")
    assert np.abs(moved - points).max() > 0.1  # the lattice did move the bunny
    np.testing.assert_array_equal(after.points, moved.astype(np.float32))
    assert after.points.dtype == np.float32  # the file's own coordinate type


def test_identity_gives_a_binary_ply_back_byte_for_byte(tmp_path, bunny, run_cli):
    points, faces = bunny_arrays(bunny)
    n = len(points)
    source = tmp_path / "bunny.ply"
    write_ply(source, "binary_little_endian", points, faces,
              {"intensity": np.arange(n, dtype=np.float64)}, {})
    script = tmp_path / "identity.json"
    script.write_text(json.dumps({"version": 1, "steps": [
        {"op": "lattice", "name": "L", "basis": "bernstein", "degree": 2,
         "box": {"fit": "aabb", "padding": 0.05}, "cells": [1, 1, 1]}]}))
    done = run_cli("run", source, script, "-o", tmp_path / "out.ply", "--quiet")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out.ply").read_bytes() == source.read_bytes()
