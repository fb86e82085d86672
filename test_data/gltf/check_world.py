#!/usr/bin/env python3
"""Compare world-space vertex positions of a GLB with a world-space OBJ.

    python3 test_data/gltf/check_world.py test_data/gltf/scene.glb test_data/gltf/scene_world.obj

Standard library only.  Reads the GLB's JSON and BIN chunks with struct,
composes node transforms down the hierarchy from the scene roots (``matrix``
or ``translation`` * ``rotation`` (quaternion x, y, z, w) * ``scale``), and
transforms every POSITION of every primitive of every mesh node into world
space.  The OBJ's vertices are grouped by their ``o NAME`` lines; a node
named NAME is compared against the OBJ object of the same name.

Vertex order differs between the two files (the glTF exporter splits
vertices at UV seams and sharp normals and reorders them; Blender's OBJ
exporter writes each object's mesh vertices once, in Blender's order), so
each GLB vertex is matched to its nearest OBJ vertex of the same object, and
each OBJ vertex to its nearest GLB vertex (so both directions are covered).

Also checked, as secondary information: NORMAL (world normal = normalized
inverse-transpose(world 3x3) * n) against the OBJ normals used with the
matched OBJ vertex by its faces, and TEXCOORD_0 (u, 1 - v) against the
OBJ texture coordinates used with that vertex.

Prints one line per node, then ``max position difference: X`` (the larger of
the two directions over all nodes).  Exit status 1 if that exceeds the
tolerance (default 1e-5, or a third argument).
"""

import json
import math
import struct
import sys

COMPONENT = {5120: ("b", 1), 5121: ("B", 1), 5122: ("h", 2), 5123: ("H", 2),
             5125: ("I", 4), 5126: ("f", 4)}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


def read_glb(path):
    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2:
        raise SystemExit("%s: not a glTF 2.0 binary" % path)
    off, doc, binchunk = 12, None, b""
    while off < length:
        clen, ctype = struct.unpack_from("<I4s", data, off)
        chunk = data[off + 8:off + 8 + clen]
        if ctype == b"JSON":
            doc = json.loads(chunk.decode("utf-8"))
        elif ctype == b"BIN\x00":
            binchunk = chunk
        off += 8 + clen
    return doc, binchunk


def read_accessor(doc, binchunk, index):
    acc = doc["accessors"][index]
    fmt, size = COMPONENT[acc["componentType"]]
    n = NCOMP[acc["type"]]
    bv = doc["bufferViews"][acc["bufferView"]]
    if bv.get("buffer", 0) != 0 or "uri" in doc["buffers"][bv.get("buffer", 0)]:
        raise SystemExit("only the GLB's own BIN buffer is supported")
    base = bv.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = bv.get("byteStride", 0) or size * n
    out = []
    for i in range(acc["count"]):
        out.append(struct.unpack_from("<%d%s" % (n, fmt), binchunk, base + i * stride))
    return out


def mat_mul(a, b):  # 4x4 row-major lists of lists
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def local_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    tx, ty, tz = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    sx, sy, sz = node.get("scale", [1, 1, 1])
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    s = (sx, sy, sz)
    t = (tx, ty, tz)
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + [[0, 0, 0, 1]]


def world_matrices(doc):
    out = {}
    scene = doc["scenes"][doc.get("scene", 0)]
    stack = [(n, [[1 if i == j else 0 for j in range(4)] for i in range(4)]) for n in scene["nodes"]]
    while stack:
        idx, parent = stack.pop()
        world = mat_mul(parent, local_matrix(doc["nodes"][idx]))
        out[idx] = world
        for c in doc["nodes"][idx].get("children", []):
            stack.append((c, world))
    return out


def xform_point(m, p):
    return tuple(m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3))


def normal_matrix(m):
    a = [row[:3] for row in m[:3]]
    det = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
           - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
           + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
    # inverse-transpose = cofactor matrix / det
    cof = [[(a[(i + 1) % 3][(j + 1) % 3] * a[(i + 2) % 3][(j + 2) % 3]
             - a[(i + 1) % 3][(j + 2) % 3] * a[(i + 2) % 3][(j + 1) % 3]) / det
            for j in range(3)] for i in range(3)]
    return cof


def xform_normal(nm, n):
    v = [nm[i][0] * n[0] + nm[i][1] * n[1] + nm[i][2] * n[2] for i in range(3)]
    length = math.sqrt(sum(c * c for c in v)) or 1.0
    return tuple(c / length for c in v)


def read_obj(path):
    """Objects by name: positions (global list indices), and for each global
    vertex index the sets of normal and texcoord indices its corners use."""
    v, vt, vn = [], [], []
    objects = {}
    cur = None
    corner_n, corner_t = {}, {}
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        key = parts[0]
        if key == "o":
            cur = objects.setdefault(" ".join(parts[1:]), [])
        elif key == "v":
            if cur is None:
                cur = objects.setdefault("", [])
            cur.append(len(v))
            v.append(tuple(float(c) for c in parts[1:4]))
        elif key == "vt":
            vt.append(tuple(float(c) for c in parts[1:3]))
        elif key == "vn":
            vn.append(tuple(float(c) for c in parts[1:4]))
        elif key == "f":
            for corner in parts[1:]:
                f = corner.split("/")
                vi = int(f[0])
                vi = vi - 1 if vi > 0 else len(v) + vi
                if len(f) > 1 and f[1]:
                    ti = int(f[1])
                    corner_t.setdefault(vi, set()).add(ti - 1 if ti > 0 else len(vt) + ti)
                if len(f) > 2 and f[2]:
                    ni = int(f[2])
                    corner_n.setdefault(vi, set()).add(ni - 1 if ni > 0 else len(vn) + ni)
    return v, vt, vn, objects, corner_n, corner_t


def dist(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))


def nearest(p, candidates, points):
    best, best_i = float("inf"), -1
    for i in candidates:
        q = points[i]
        d = (p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 + (p[2] - q[2]) ** 2
        if d < best:
            best, best_i = d, i
    return best_i, math.sqrt(best)


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    tol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-5
    doc, binchunk = read_glb(sys.argv[1])
    ov, ovt, ovn, objects, corner_n, corner_t = read_obj(sys.argv[2])
    worlds = world_matrices(doc)
    overall = 0.0
    for idx in sorted(worlds):
        node = doc["nodes"][idx]
        if "mesh" not in node:
            continue
        name = node.get("name", "")
        if name not in objects:
            raise SystemExit("node %d %r has no OBJ object of that name" % (idx, name))
        obj_idx = objects[name]
        m = worlds[idx]
        nm = normal_matrix(m)
        pts, nrm, uvs = [], [], []
        for prim in doc["meshes"][node["mesh"]]["primitives"]:
            a = prim["attributes"]
            pts += [xform_point(m, p) for p in read_accessor(doc, binchunk, a["POSITION"])]
            if "NORMAL" in a:
                nrm += [xform_normal(nm, n) for n in read_accessor(doc, binchunk, a["NORMAL"])]
            if "TEXCOORD_0" in a:
                uvs += [(u, 1.0 - w) for u, w in read_accessor(doc, binchunk, a["TEXCOORD_0"])]
        fwd = bwd = 0.0
        nerr = uverr = 0.0
        for k, p in enumerate(pts):
            j, d = nearest(p, obj_idx, ov)
            fwd = max(fwd, d)
            if nrm and j in corner_n:
                nerr = max(nerr, min(dist(nrm[k], ovn[ni]) for ni in corner_n[j]))
            if uvs and j in corner_t:
                uverr = max(uverr, min(dist(uvs[k], ovt[ti]) for ti in corner_t[j]))
        for j in obj_idx:
            _, d = nearest(ov[j], range(len(pts)), pts)
            bwd = max(bwd, d)
        print("node %d %-6s mesh %d: %d GLB vertices, %d OBJ vertices; "
              "position GLB->OBJ %.3g, OBJ->GLB %.3g; normal %.3g; uv %.3g"
              % (idx, name, node["mesh"], len(pts), len(obj_idx), fwd, bwd, nerr, uverr))
        overall = max(overall, fwd, bwd)
    print("max position difference: %.3g" % overall)
    return 0 if overall <= tol else 1


if __name__ == "__main__":
    sys.exit(main())
