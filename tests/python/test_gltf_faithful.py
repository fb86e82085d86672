"""Every glTF of the corpus (gltf_corpus.py) through `ffdtool run`, unmoved and moved, as
.gltf (external buffer) and .glb:

- the output's JSON is the input's, but for what the deformation changed: the POSITION
  and NORMAL accessors' data and bounds, the buffers' URIs and lengths, and what a split
  instance appends;
- Khronos' glTF-Validator finds no error in the output that it does not find in the input;
- assimp (Debian's assimp-utils), an independent reader, loads the output as it loads
  the input;
- unmoved, the positions are the input's bit for bit; moved, every POSITION accessor's
  min and max are its data's bounds.
"""
import base64
import copy
import json
import os
import shutil
import struct
import subprocess

import numpy as np
import pytest

import gltf_corpus

HERE = os.path.dirname(os.path.abspath(__file__))
VALIDATOR = os.path.join(HERE, "..", "gltf", "validate.js")
LATTICE = {"op": "lattice", "name": "L", "basis": "bspline", "degree": 3,
           "box": {"fit": "aabb", "padding": 0.05}, "cells": [6, 6, 6]}
SCRIPTS = {
    "unmoved": {"version": 1, "steps": [LATTICE]},
    "moved": {"version": 1, "steps": [LATTICE, {"op": "move", "lattice": "L", "points": [
        {"index": [2, 3, 3], "by": [0.5, 1.5, -0.8]}]}]},
}
CASES = [c.__name__ for c in gltf_corpus.CASES]


@pytest.fixture(scope="module")
def corpus(tmp_path_factory, bunny):
    folder = tmp_path_factory.mktemp("corpus")
    gltf_corpus.write_corpus(str(folder), bunny)
    return folder


def load(path):
    """A glTF's JSON and its buffers' bytes (GLB BIN chunk, data URIs, files beside it)."""
    raw = open(path, "rb").read()
    bin_chunk = None
    if raw[:4] == b"glTF":
        n = struct.unpack_from("<I", raw, 12)[0]
        doc = json.loads(raw[20:20 + n])
        if len(raw) > 28 + n:
            m = struct.unpack_from("<I", raw, 20 + n)[0]
            bin_chunk = raw[28 + n:28 + n + m]
    else:
        doc = json.loads(raw)
    buffers = []
    for i, b in enumerate(doc.get("buffers", [])):
        uri = b.get("uri")
        if uri is None and (bin_chunk is None or i > 0):  # a meshopt fallback buffer
            data = b"\0" * b["byteLength"]
        elif uri is None:
            data = bin_chunk
        elif uri.startswith("data:"):
            data = base64.b64decode(uri.split(",", 1)[1])
        else:
            data = open(os.path.join(os.path.dirname(path), uri), "rb").read()
        buffers.append(data[:b["byteLength"]])
    return doc, buffers


def vec3(doc, buffers, index):
    """Accessor `index` (float VEC3) as an (n, 3) array, sparse values substituted."""
    a = doc["accessors"][index]
    out = np.zeros((a["count"], 3), dtype=np.float32)
    if "bufferView" in a:
        v = doc["bufferViews"][a["bufferView"]]
        stride = v.get("byteStride", 12)
        start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        out[:] = np.ndarray((a["count"], 3), np.float32, buffers[v["buffer"]], start, (stride, 4))
    if "sparse" in a:
        s = a["sparse"]
        iv, vv = doc["bufferViews"][s["indices"]["bufferView"]], doc["bufferViews"][s["values"]["bufferView"]]
        types = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32}
        idx = np.frombuffer(buffers[iv["buffer"]], types[s["indices"]["componentType"]], s["count"],
                            iv.get("byteOffset", 0) + s["indices"].get("byteOffset", 0))
        val = np.frombuffer(buffers[vv["buffer"]], np.float32, 3 * s["count"],
                            vv.get("byteOffset", 0) + s["values"].get("byteOffset", 0))
        out[idx] = val.reshape(-1, 3)
    return out


def deformed_accessors(doc, meshes):
    """The POSITION and NORMAL accessors of the first `meshes` meshes' primitives."""
    return {p["attributes"][k] for m in doc.get("meshes", [])[:meshes] for p in m["primitives"]
            for k in ("POSITION", "NORMAL") if k in p["attributes"]}


def draco_accessors(doc):
    """The accessors of Draco-compressed primitives, which a read gives views of their own."""
    return {a for m in doc.get("meshes", []) for p in m["primitives"]
            if "KHR_draco_mesh_compression" in p.get("extensions", {})
            for a in list(p["attributes"].values()) + [p.get("indices", -1)] if a >= 0}


def without_extensions(doc, names):
    """`doc` with extensions `names` removed from the declarations, primitives, views and buffers."""
    d = copy.deepcopy(doc)
    for key in ("extensionsUsed", "extensionsRequired"):
        if key in d:
            d[key] = [e for e in d[key] if e not in names]
            if not d[key]:
                del d[key]
    items = [p for m in d.get("meshes", []) for p in m["primitives"]] + d.get("bufferViews", []) + d.get("buffers", [])
    for item in items:
        for name in names:
            item.get("extensions", {}).pop(name, None)
        if item.get("extensions") == {}:
            del item["extensions"]
    return d


def stripped(doc, source, decoded=()):
    """`doc` without what a deformation may change, against its `source` document: the
    deformed accessors' data, views, types and bounds (every accessor of a Draco primitive),
    the buffers' URIs and lengths, what was appended, the `decoded` extensions, and which
    copy of a mesh a split node draws (the copy must be its mesh but for POSITION and
    NORMAL). A decoded meshopt file's buffers are repacked: then which buffer a view is in,
    and where, and the buffers themselves go too."""
    d = without_extensions(doc, decoded)
    counts = {k: len(source.get(k, [])) for k in ("accessors", "bufferViews", "meshes", "buffers")}
    for node, original in zip(d.get("nodes", []), source.get("nodes", [])):
        if node.get("mesh", -1) >= counts["meshes"]:
            copy_of = copy.deepcopy(d["meshes"][node["mesh"]])
            for p, q in zip(copy_of["primitives"], source["meshes"][original["mesh"]]["primitives"]):
                for k in ("POSITION", "NORMAL"):
                    if k in q["attributes"]:
                        p["attributes"][k] = q["attributes"][k]
            assert copy_of == source["meshes"][original["mesh"]]
            node["mesh"] = original["mesh"]
    for i in deformed_accessors(source, counts["meshes"]) | draco_accessors(source):
        for k in ("min", "max", "bufferView", "byteOffset", "sparse", "componentType", "normalized"):
            d["accessors"][i].pop(k, None)
    for k in ("accessors", "bufferViews", "meshes"):
        if k in d:
            d[k] = d[k][:counts[k]]
    for b in d.get("buffers", []):
        b.pop("uri", None)
        b.pop("byteLength", None)
    if "EXT_meshopt_compression" in decoded:
        for v in d.get("bufferViews", []):
            v.pop("buffer", None)
            v.pop("byteOffset", None)
        d.pop("buffers", None)
    return d


def assert_repacked(doc, buffers, binary):
    """A decoded meshopt file written back holds only what its views cover (no compressed
    stream, no fallback without data), and a GLB has one buffer, its BIN chunk."""
    assert all("uri" in b or (binary and i == 0) for i, b in enumerate(doc["buffers"]))
    if binary:
        assert len(doc["buffers"]) == 1
    views = doc["bufferViews"]
    assert sum(len(b) for b in buffers) <= sum(v["byteLength"] + 7 for v in views)
    for v in views:
        assert v["byteOffset"] % 4 == 0 and v["byteOffset"] + v["byteLength"] <= len(buffers[v["buffer"]])


class Validator:
    """One glTF-Validator process for the module's files (validate.js --serve: a node start
    costs about 0.2 s, a file about 0.02), and each file's errors once: the corpus's inputs
    are held against by the outputs of every motion and extension."""

    def __init__(self):
        self.process = subprocess.Popen(["node", VALIDATOR, "--serve"], stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, text=True)
        self.known = {}

    def errors(self, path):
        path = str(path)
        if path not in self.known:
            self.process.stdin.write(path + "\n")
            self.process.stdin.flush()
            line = self.process.stdout.readline()
            assert line, "glTF-Validator (scripts/setup.sh installs it) ended without a report on " + path
            report = json.loads(line)
            assert "error" not in report, "glTF-Validator: " + report.get("error", "")
            self.known[path] = {(m["code"], m.get("pointer", ""))
                                for m in report["issues"]["messages"] if m["severity"] == 0}
        return self.known[path]

    def close(self):
        self.process.stdin.close()
        self.process.wait()


@pytest.fixture(scope="module")
def validator():
    v = Validator()
    yield v
    v.close()


def assimp_loads(path):
    if not shutil.which("assimp"):
        pytest.skip("assimp is not installed (scripts/setup.sh installs assimp-utils)")
    return subprocess.run(["assimp", "info", str(path)], capture_output=True).returncode == 0


@pytest.mark.parametrize("ext", [".gltf", ".glb"])
@pytest.mark.parametrize("motion", sorted(SCRIPTS))
@pytest.mark.parametrize("case", CASES)
def test_written_back_with_nothing_lost(case, motion, ext, corpus, tmp_path, run_cli, validator):
    source = corpus / (case + ext)
    script = tmp_path / "script.json"
    script.write_text(json.dumps(SCRIPTS[motion]))
    out = tmp_path / ("out" + ext)
    done = run_cli("run", source, script, "-o", out)
    assert done.returncode == 0, done.stderr
    if case == "wrong_bounds":
        assert "min and max are not its values' bounds" in done.stderr

    src_doc, src_buf = load(source)
    out_doc, out_buf = load(out)
    assert stripped(out_doc, src_doc) == stripped(src_doc, src_doc)

    for m in out_doc["meshes"]:
        for p in m["primitives"]:
            pos = p["attributes"]["POSITION"]
            values = vec3(out_doc, out_buf, pos)
            if motion == "unmoved" or pos >= len(src_doc["accessors"]):
                continue
            a = out_doc["accessors"][pos]
            assert a["min"] == values.min(axis=0).astype(np.float64).tolist()
            assert a["max"] == values.max(axis=0).astype(np.float64).tolist()
    moved = [not np.array_equal(vec3(src_doc, src_buf, i), vec3(out_doc, out_buf, i))
             for i in deformed_accessors(src_doc, len(src_doc["meshes"]))]
    assert any(moved) == (motion == "moved")
    if case == "instances" and motion == "moved":
        assert len(out_doc["meshes"]) == 2  # the instances no longer agree: one was split off

    assert validator.errors(out) <= validator.errors(source)
    if assimp_loads(source):
        assert assimp_loads(out)


# The bunny in each compressed coding, by the libraries' own encoders (make_gltf_corpus),
# against the same bunny plain: what the extension becomes in the output, and how close
# the decoded geometry must come to the plain file's (Draco lossy and the quantization
# round positions to 14 bits of the bunny's 10-unit extent).
CODINGS = {"draco": ("KHR_draco_mesh_compression", 0.0), "draco_lossy": ("KHR_draco_mesh_compression", 5e-3),
           "meshopt": ("EXT_meshopt_compression", 0.0), "quantized": (None, 5e-3)}


@pytest.fixture(scope="module")
def compressed(tmp_path_factory, bunny):
    folder = tmp_path_factory.mktemp("compressed")
    subprocess.run([os.environ["FFD_GLTF_CORPUS"], bunny, str(folder)], check=True)
    return folder


def obj_vertices(path):
    with open(path) as f:
        return np.array([[float(x) for x in line.split()[1:4]] for line in f if line.startswith("v ")])


def farthest_apart(a, b):
    """The larger of the two directed distances from a point of one set to the other set."""
    from scipy.spatial import cKDTree
    return max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max())


@pytest.mark.parametrize("ext", [".gltf", ".glb"])
@pytest.mark.parametrize("motion", sorted(SCRIPTS))
@pytest.mark.parametrize("coding", sorted(CODINGS))
def test_compressed_files_are_read_and_written_plain(coding, motion, ext, compressed, tmp_path, run_cli, validator):
    extension, tolerance = CODINGS[coding]
    script = tmp_path / "script.json"
    script.write_text(json.dumps(SCRIPTS[motion]))
    for name in ("plain", coding):
        for out in (name + ext, name + ".obj"):
            done = run_cli("run", compressed / ("bunny_" + name + ext), script, "-o", tmp_path / out)
            assert done.returncode == 0, done.stderr
    if extension:
        assert extension + " is decoded on read" in done.stderr
    assert farthest_apart(obj_vertices(tmp_path / (coding + ".obj")), obj_vertices(tmp_path / "plain.obj")) <= tolerance

    source, out = compressed / ("bunny_" + coding + ext), tmp_path / (coding + ext)
    src_doc, _ = load(source)
    out_doc, out_buf = load(out)
    decoded = (extension,) if extension else ()
    assert stripped(out_doc, src_doc, decoded) == stripped(src_doc, src_doc, decoded)
    if coding == "meshopt":
        assert_repacked(out_doc, out_buf, ext == ".glb")
    if coding != "quantized":  # float data: the file's own bytes, read here, are the run's
        plain_doc, plain_buf = load(tmp_path / ("plain" + ext))
        def positions(d, b):
            return vec3(d, b, d["meshes"][0]["primitives"][0]["attributes"]["POSITION"])
        assert farthest_apart(positions(out_doc, out_buf), positions(plain_doc, plain_buf)) <= tolerance
    assert "extensions" not in json.dumps(without_extensions(out_doc, ["KHR_mesh_quantization"]))
    position = out_doc["accessors"][out_doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    if coding == "quantized":  # what the deformation left is the file's; what it moved is float
        assert position["componentType"] == (5126 if motion == "moved" else 5123)
    assert validator.errors(out) <= validator.errors(source)
    if assimp_loads(source):
        assert assimp_loads(out)
