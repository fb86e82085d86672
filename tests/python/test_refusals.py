"""What ffdtool cannot read is refused by name: one error line naming the file and the
reason, exit code 2, and no output file. One file per class of refusal, written here:

- glTF 1.0 (JSON that says so, JSON with 1.0's dictionaries, the KHR_binary_glTF container);
- UTF-16 and UTF-32 text (with and without a byte-order mark) in every text format;
- non-finite coordinates in every format, named by line, element or accessor;
- a count larger than the file can back (no "out of memory").
"""
import base64
import json
import struct

import pytest

SCRIPT = {"version": 1, "steps": [{"op": "lattice", "name": "L", "basis": "bernstein", "degree": 1,
                                   "box": {"fit": "aabb", "padding": 0.1}, "cells": [1, 1, 1]}]}
OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
OFF = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
PLY = ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 {z}\n0 1 0\n3 0 1 2\n")
STL = ("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 {z}\nvertex 0 1 0\nendloop\n"
       "endfacet\nendsolid t\n")


def gltf(z=0.0, **accessor):
    data = struct.pack("<9f", 0, 0, 0, 1, 0, z, 0, 1, 0)
    acc = {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}
    acc.update(accessor)
    return json.dumps({
        "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "accessors": [acc],
        "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
        "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode(),
                     "byteLength": len(data)}]})


def glb(text):
    body = text.encode() + b" " * (-len(text) % 4)
    return struct.pack("<4sII", b"glTF", 2, 20 + len(body)) + struct.pack("<I4s", len(body), b"JSON") + body


CASES = {
    # name: (file name, bytes, words the error must hold)
    "gltf1_asset": ("old.gltf", json.dumps({"asset": {"version": "1.0"}, "meshes": {"m": {"primitives": []}}}),
                    ["glTF 1.0 is not supported"]),
    "gltf1_dictionaries": ("old.gltf", json.dumps({"meshes": {}, "accessors": {}, "nodes": {}}),
                           ["glTF 1.0 is not supported"]),
    "gltf1_binary": ("old.glb", b"glTF" + struct.pack("<III", 1, 32, 12) + b"\0\0\0\0" + b'{"asset":{}}',
                     ["glTF 1.0 is not supported"]),
    "utf16_obj": ("wide.obj", OBJ.encode("utf-16"), ["UTF-16LE text is not supported"]),
    "utf16be_off_no_bom": ("wide.off", OFF.encode("utf-16-be"), ["UTF-16BE text is not supported"]),
    "utf32_ply": ("wide.ply", PLY.format(z=0).encode("utf-32"), ["UTF-32LE text is not supported"]),
    "utf16_stl": ("wide.stl", STL.format(z=0).encode("utf-16"), ["UTF-16LE text is not supported"]),
    "utf16_gltf": ("wide.gltf", gltf().encode("utf-16"), ["UTF-16LE text is not supported"]),
    "inf_obj": ("inf.obj", OBJ.replace("v 1 0 0", "v 1 0 inf"), ["inf.obj:2:", "not a finite number"]),
    "nan_off": ("nan.off", OFF.replace("1 0 0\n", "1 0 nan\n"), ["nan.off:4:", "not a finite number"]),
    "inf_ply": ("inf.ply", PLY.format(z="inf"), ["inf.ply:11:", "vertex 1", "not finite"]),
    "nan_stl": ("nan.stl", STL.format(z="nan"), ["nan.stl:5:", "not a finite number"]),
    "inf_gltf": ("inf.gltf", gltf(z=float("inf")), ["accessor 0 (POSITION", "element 1 is not finite"]),
    "inf_glb": ("inf.glb", glb(gltf(z=float("inf"))), ["accessor 0 (POSITION", "element 1 is not finite"]),
    "huge_count_gltf": ("huge.gltf", json.dumps({
        "asset": {"version": "2.0"}, "nodes": [{"mesh": 0}],
        "accessors": [{"componentType": 5126, "count": 100000000000, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]}),
        ["accessor 0", "more than the file's 0 bytes of buffers can back"]),
    "huge_count_off": ("huge.off", "OFF\n4000000000 1 0\n0 0 0\n", ["huge.off:2:", "more than the file's"]),
    "huge_count_ply": ("huge.ply", PLY.format(z=0).replace("vertex 3", "vertex 4000000000"),
                       ["huge.ply:3:", "promises 4000000000"]),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_refused_by_name(case, tmp_path, run_cli):
    name, content, words = CASES[case]
    source = tmp_path / name
    source.write_bytes(content if isinstance(content, bytes) else content.encode())
    script = tmp_path / "script.json"
    script.write_text(json.dumps(SCRIPT))
    out = tmp_path / "out.obj"
    for args in (["info", source], ["run", source, script, "-o", out]):
        done = run_cli(*args)
        assert done.returncode == 2, (args[0], done.stderr)
        lines = done.stderr.strip().split("\n")
        assert len(lines) == 1 and lines[0].startswith("ffdtool: error: ") and name in lines[0], done.stderr
        for w in words:
            assert w in lines[0], (w, lines[0])
    assert not out.exists()


def test_a_utf8_byte_order_mark_is_read_past(tmp_path, run_cli):
    source = tmp_path / "bom.obj"
    source.write_bytes(b"\xef\xbb\xbf" + OBJ.encode())
    done = run_cli("info", source)
    assert done.returncode == 0, done.stderr
