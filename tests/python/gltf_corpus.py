"""A glTF 2.0 corpus written per the spec with numpy alone: one file per thing a glTF
writer that re-serializes its model tends to lose (test_gltf_faithful.py runs them).

Every file draws the bunny (test_data/bunny.obj) with POSITION and NORMAL, and adds one
class of content:

- skin_empty_joint: a skinned node whose joint is an empty node `{}`;
- camera_without_zfar: a perspective camera with no zfar (infinite);
- animation_pointer: an animation whose channel targets KHR_animation_pointer;
- named_sampler: a texture whose sampler has a name, an embedded PNG, TEXCOORD_0;
- wrong_bounds: POSITION min and max that are not the data's bounds;
- unknown_extensions: extensions ffdtool does not know, extras, empty objects;
- sparse_morph: a sparse POSITION accessor and a morph target;
- instances: one mesh drawn by two nodes, which a local move splits.

`python3 gltf_corpus.py FOLDER` writes each as FOLDER/NAME.gltf (+ .bin) and NAME.glb.
"""
import base64
import json
import os
import struct
import sys

import numpy as np

# A 1x1 PNG (an opaque red pixel).
PNG = base64.b64decode(
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg==")

FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963


def bunny(path):
    """The bunny's positions (float32) and triangles (uint32) from its OBJ."""
    points, faces = [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if t and t[0] == "v":
                points.append([float(x) for x in t[1:4]])
            elif t and t[0] == "f":
                faces.append([int(c.split("/")[0]) - 1 for c in t[1:4]])
    return np.array(points, dtype=np.float32), np.array(faces, dtype=np.uint32)


def vertex_normals(points, faces):
    p = points.astype(np.float64)
    n = np.zeros_like(p)
    fn = np.cross(p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]])
    for k in range(3):
        np.add.at(n, faces[:, k], fn)
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-30)[:, None]
    return n.astype(np.float32)


class Builder:
    """A glTF document with one buffer, built view by view."""

    def __init__(self):
        self.bin = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": "ffdtool test corpus"},
                    "buffers": [], "bufferViews": [], "accessors": []}

    def view(self, data, target=None):
        self.bin += b"\0" * (-len(self.bin) % 4)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target:
            v["target"] = target
        self.bin += data
        self.doc["bufferViews"].append(v)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, array, kind, component, target=None, bounds=False, **extra):
        a = {"bufferView": self.view(array.tobytes(), target), "componentType": component,
             "count": len(array), "type": kind}
        if bounds:
            flat = array.reshape(len(array), -1)
            a["min"] = [x.item() for x in flat.min(axis=0)]
            a["max"] = [x.item() for x in flat.max(axis=0)]
        a.update(extra)
        self.doc["accessors"].append(a)
        return len(self.doc["accessors"]) - 1

    def gltf(self, bin_name):
        doc = json.loads(json.dumps(self.doc))
        doc["buffers"] = [{"uri": bin_name, "byteLength": len(self.bin)}]
        return json.dumps(doc, indent=1).encode(), bytes(self.bin)

    def glb(self):
        doc = json.loads(json.dumps(self.doc))
        doc["buffers"] = [{"byteLength": len(self.bin)}]
        text = json.dumps(doc).encode()
        text += b" " * (-len(text) % 4)
        data = bytes(self.bin) + b"\0" * (-len(self.bin) % 4)
        body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(data), b"BIN\0") + data
        return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def base_primitive(b, points, faces, **more):
    prim = {"attributes": {"POSITION": b.accessor(points, "VEC3", FLOAT, ARRAY_BUFFER, bounds=True),
                           "NORMAL": b.accessor(vertex_normals(points, faces), "VEC3", FLOAT, ARRAY_BUFFER)},
            "indices": b.accessor(faces.reshape(-1), "SCALAR", UINT, ELEMENT_ARRAY_BUFFER)}
    prim["attributes"].update(more)
    return prim


def one_mesh(b, prim, nodes=None, roots=(0,)):
    b.doc["meshes"] = [{"name": "bunny", "primitives": [prim]}]
    b.doc["nodes"] = nodes or [{"mesh": 0}]
    b.doc["scenes"] = [{"nodes": list(roots)}]
    b.doc["scene"] = 0


def skin_empty_joint(b, points, faces):
    n = len(points)
    joints = np.zeros((n, 4), dtype=np.uint8)
    weights = np.tile(np.array([1, 0, 0, 0], dtype=np.float32), (n, 1))
    prim = base_primitive(b, points, faces, JOINTS_0=b.accessor(joints, "VEC4", UBYTE, ARRAY_BUFFER),
                          WEIGHTS_0=b.accessor(weights, "VEC4", FLOAT, ARRAY_BUFFER))
    one_mesh(b, prim, [{"mesh": 0, "skin": 0}, {"name": "rig", "children": [2]}, {}], roots=(0, 1))
    b.doc["skins"] = [{"joints": [2], "skeleton": 1}]


def camera_without_zfar(b, points, faces):
    one_mesh(b, base_primitive(b, points, faces), [{"children": [1, 2]}, {"mesh": 0}, {"camera": 0, "translation": [0, 5, 30]}])
    b.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}]


def animation_pointer(b, points, faces):
    one_mesh(b, base_primitive(b, points, faces), [{"mesh": 0, "translation": [0, 0, 0]}])
    times = np.array([0, 1], dtype=np.float32)
    values = np.array([[0, 0, 0], [0, 1, 0]], dtype=np.float32)
    b.doc["extensionsUsed"] = ["KHR_animation_pointer"]
    b.doc["animations"] = [{
        "name": "lift",
        "channels": [{"sampler": 0, "target": {
            "path": "pointer", "extensions": {"KHR_animation_pointer": {"pointer": "/nodes/0/translation"}}}}],
        "samplers": [{"input": b.accessor(times, "SCALAR", FLOAT, bounds=True),
                      "output": b.accessor(values, "VEC3", FLOAT), "interpolation": "LINEAR"}]}]


def named_sampler(b, points, faces):
    uv = (points[:, :2] - points[:, :2].min(axis=0)) / np.ptp(points[:, :2], axis=0)
    prim = base_primitive(b, points, faces, TEXCOORD_0=b.accessor(uv.astype(np.float32), "VEC2", FLOAT, ARRAY_BUFFER))
    prim["material"] = 0
    one_mesh(b, prim)
    b.doc["samplers"] = [{"name": "crisp", "magFilter": 9728, "minFilter": 9728, "wrapS": 33071}]
    b.doc["images"] = [{"name": "red", "uri": "data:image/png;base64," + base64.b64encode(PNG).decode()}]
    b.doc["textures"] = [{"name": "fur", "sampler": 0, "source": 0}]
    b.doc["materials"] = [{"name": "fur", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]


def wrong_bounds(b, points, faces):
    prim = base_primitive(b, points, faces)
    a = b.doc["accessors"][prim["attributes"]["POSITION"]]
    a["min"] = [-1.0, -1.0, -1.0]
    a["max"] = [1.0, 1.0, 1.0]
    one_mesh(b, prim)


def unknown_extensions(b, points, faces):
    prim = base_primitive(b, points, faces)
    prim["extensions"] = {"EXT_ffdtool_test_primitive": {"level": 3}}
    prim["extras"] = {"note": "kept"}
    prim["material"] = 0
    one_mesh(b, prim, [{"mesh": 0, "name": "bunny", "extras": {}, "extensions": {"EXT_ffdtool_test_node": {}}}])
    b.doc["extensionsUsed"] = ["EXT_ffdtool_test_primitive", "EXT_ffdtool_test_node"]
    b.doc["materials"] = [{}]
    b.doc["asset"]["copyright"] = "ffdtool test corpus"
    b.doc["asset"]["extras"] = {"empty": {}, "list": [], "null": None}
    b.doc["scenes"][0]["name"] = "only"
    b.doc["extras"] = {"unicode": "lapin \u00e9\u2603", "big": 12345678901234}


def sparse_morph(b, points, faces):
    prim = base_primitive(b, points, faces)
    pos = b.doc["accessors"][prim["attributes"]["POSITION"]]
    # POSITION as a sparse accessor over zeros: every vertex is substituted.
    del pos["bufferView"]
    idx = np.arange(len(points), dtype=np.uint32)
    pos["sparse"] = {"count": len(points),
                     "indices": {"bufferView": b.view(idx.tobytes()), "componentType": UINT},
                     "values": {"bufferView": b.view(points.tobytes())}}
    offsets = np.zeros_like(points)
    offsets[:, 1] = 0.5
    prim["targets"] = [{"POSITION": b.accessor(offsets, "VEC3", FLOAT, ARRAY_BUFFER, bounds=True)}]
    one_mesh(b, prim)
    b.doc["meshes"][0]["weights"] = [0.5]


def instances(b, points, faces):
    one_mesh(b, base_primitive(b, points, faces),
             [{"children": [1, 2]}, {"mesh": 0, "translation": [-8, 0, 0]}, {"mesh": 0, "translation": [8, 0, 0]}])


CASES = [skin_empty_joint, camera_without_zfar, animation_pointer, named_sampler, wrong_bounds,
         unknown_extensions, sparse_morph, instances]


def write_corpus(folder, bunny_obj):
    """Writes every case as NAME.gltf (with NAME.bin) and NAME.glb; returns the paths."""
    points, faces = bunny(bunny_obj)
    paths = []
    for case in CASES:
        b = Builder()
        case(b, points, faces)
        name = case.__name__
        text, data = b.gltf(name + ".bin")
        with open(os.path.join(folder, name + ".gltf"), "wb") as f:
            f.write(text)
        with open(os.path.join(folder, name + ".bin"), "wb") as f:
            f.write(data)
        with open(os.path.join(folder, name + ".glb"), "wb") as f:
            f.write(b.glb())
        paths += [os.path.join(folder, name + ".gltf"), os.path.join(folder, name + ".glb")]
    return paths


if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    write_corpus(sys.argv[1], os.path.join(here, "..", "..", "test_data", "bunny.obj"))
