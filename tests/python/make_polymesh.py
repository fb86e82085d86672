"""An OpenFOAM polyMesh of a hex grid in a box, written with numpy alone as blockMesh would
write the `cavity` tutorial's mesh: points in blockMesh's order (x fastest), internal
faces first in upper-triangular order (each cell's faces to higher-numbered neighbours,
by neighbour), each face wound so its right-hand normal points from owner to neighbour,
then the patches movingWall (y = max), fixedWalls (x = min, x = max, y = min) and
frontAndBack (z = min, z = max), their faces wound outward.

Besides the five files it writes a `cellZones` file and a `sets/lidCells` cellSet (the
companions a reader must list and leave alone).

    python3 make_polymesh.py FOLDER [--cells 4 3 2] [--box 0.1 0.1 0.01]
        [--format ascii|binary] [--label 32|64] [--scalar 32|64] [--faces list|compact]
        [--bundle FILE]

--faces: `list` is a faceList (what OpenFOAM writes in ASCII), `compact` a
faceCompactList (what it writes in binary, the default there). --bundle writes the five
files into FILE as ffd's fuzz seed form (each file preceded by its size, 8 bytes
little-endian) instead of into FOLDER (pass `-` as FOLDER).

test_data/volume/cavity_ascii and cavity_binary are `FOLDER` and `FOLDER --format binary`;
the seeds in tests/fuzz/corpus/foam are, in that folder:
    make_polymesh.py - --cells 2 2 1 --bundle ascii_list_2x2x1
    make_polymesh.py - --cells 2 1 1 --faces compact --bundle ascii_compact_2x1x1
    make_polymesh.py - --cells 2 2 2 --format binary --label 64 --scalar 32 --bundle binary_label64_float_2x2x2
    make_polymesh.py - --cells 1 2 1 --format binary --faces list --bundle binary_facelist_1x2x1
"""
import argparse
import os
import struct

import numpy as np

BANNER = r"""/*--------------------------------*- C++ -*----------------------------------*\
  =========                 |
  \\      /  F ield         | OpenFOAM: The Open Source CFD Toolbox
   \\    /   O peration     | Version:  v2306
    \\  /    A nd           | Website:  www.openfoam.com
     \\/     M anipulation  |
\*---------------------------------------------------------------------------*/
"""
DIVIDER = "// * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * //\n"
FOOTER = "\n\n// ************************************************************************* //\n"


def grid(nx, ny, nz, box):
    """Points (blockMesh order), faces, owner, neighbour and the patches (name, type,
    face count) of an nx x ny x nz hex grid over [0, box]."""
    xs, ys, zs = (np.linspace(0.0, box[d], n + 1) for d, n in enumerate((nx, ny, nz)))
    z, y, x = np.meshgrid(zs, ys, xs, indexing="ij")
    points = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)

    def p(i, j, k):
        return i + (nx + 1) * (j + (ny + 1) * k)

    # The quad of the grid plane normal to axis d through corner (i, j, k), wound so
    # its normal is +d.
    def quad(d, i, j, k):
        if d == 0:
            return [p(i, j, k), p(i, j + 1, k), p(i, j + 1, k + 1), p(i, j, k + 1)]
        if d == 1:
            return [p(i, j, k), p(i, j, k + 1), p(i + 1, j, k + 1), p(i + 1, j, k)]
        return [p(i, j, k), p(i + 1, j, k), p(i + 1, j + 1, k), p(i, j + 1, k)]

    def cell(i, j, k):
        return i + nx * (j + ny * k)

    def outward(face, positive):  # OpenFOAM's reversal keeps the first point
        return face if positive else [face[0]] + face[:0:-1]

    faces, owner, neighbour = [], [], []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                for d, (di, dj, dk), more in ((0, (1, 0, 0), i + 1 < nx), (1, (0, 1, 0), j + 1 < ny),
                                              (2, (0, 0, 1), k + 1 < nz)):
                    if more:
                        faces.append(quad(d, i + di, j + dj, k + dk))
                        owner.append(cell(i, j, k))
                        neighbour.append(cell(i + di, j + dj, k + dk))
    patches = []

    def side(d, at_max):
        """The boundary faces on the side normal to axis d (min or max), cell order."""
        count = 0
        n = (nx, ny, nz)
        for k in range(nz):
            for j in range(ny):
                for i in range(nx):
                    c = (i, j, k)
                    if c[d] != (n[d] - 1 if at_max else 0):
                        continue
                    corner = list(c)
                    corner[d] += 1 if at_max else 0
                    faces.append(outward(quad(d, *corner), at_max))
                    owner.append(cell(i, j, k))
                    count += 1
        return count

    patches.append(("movingWall", "wall", side(1, True)))
    patches.append(("fixedWalls", "wall", side(0, False) + side(0, True) + side(1, False)))
    patches.append(("frontAndBack", "empty", side(2, False) + side(2, True)))
    return points, faces, np.array(owner), np.array(neighbour), patches


def header(fmt, cls, obj, label, scalar, note=None):
    lines = [BANNER, "FoamFile\n{\n", "    version     2.0;\n", "    format      %s;\n" % fmt,
             '    arch        "LSB;label=%d;scalar=%d";\n' % (label, scalar), "    class       %s;\n" % cls]
    if note:
        lines.append('    note        "%s";\n' % note)
    lines += ['    location    "constant/polyMesh";\n', "    object      %s;\n" % obj, "}\n", DIVIDER, "\n"]
    return "".join(lines).encode()


def number(x):
    """A coordinate as OpenFOAM writes it at writePrecision 6."""
    return "%.6g" % x


def ascii_labels(values):
    values = [int(v) for v in values]
    if len(values) <= 10:  # OpenFOAM writes short label lists on one line
        return ("%d(%s)\n" % (len(values), " ".join(map(str, values)))).encode()
    return ("%d\n(\n%s\n)\n" % (len(values), "\n".join(map(str, values)))).encode()


def binary_list(array, dtype):
    data = np.ascontiguousarray(array, dtype=dtype)
    if data.size == 0:
        return b"\n0\n"
    return ("\n%d\n(" % len(data)).encode() + data.tobytes() + b")\n"


def write_files(points, faces, owner, neighbour, patches, args):
    """The five files' bytes, by name."""
    fmt, label, scalar = args.format, args.label, args.scalar
    ldt, sdt = ("<i4" if label == 32 else "<i8"), ("<f8" if scalar == 64 else "<f4")
    note = "nPoints:%d nCells:%d nFaces:%d nInternalFaces:%d" % (
        len(points), owner.max() + 1, len(faces), len(neighbour))
    out = {}
    h = lambda cls, obj, n=None: header(fmt, cls, obj, label, scalar, n)  # noqa: E731
    if fmt == "ascii":
        body = "%d\n(\n%s\n)\n" % (len(points), "\n".join("(%s)" % " ".join(map(number, q)) for q in points))
        out["points"] = h("vectorField", "points") + body.encode()
    else:
        out["points"] = h("vectorField", "points") + binary_list(points, sdt)
    offsets = np.cumsum([0] + [len(f) for f in faces])
    flat = [v for f in faces for v in f]
    if args.faces == "compact" and fmt == "binary":
        out["faces"] = h("faceCompactList", "faces") + binary_list(offsets, ldt) + binary_list(flat, ldt)
    elif args.faces == "compact":
        out["faces"] = h("faceCompactList", "faces") + ascii_labels(offsets) + b"\n\n" + ascii_labels(flat)
    elif fmt == "binary":  # a List<face>: text around each face's raw labels
        body = b"".join(binary_list(f, ldt) for f in faces)
        out["faces"] = h("faceList", "faces") + ("\n%d\n(" % len(faces)).encode() + body + b")\n"
    else:
        body = "%d\n(\n%s\n)\n" % (len(faces), "\n".join("%d(%s)" % (len(f), " ".join(map(str, f))) for f in faces))
        out["faces"] = h("faceList", "faces") + body.encode()
    for name, values in (("owner", owner), ("neighbour", neighbour)):
        out[name] = h("labelList", name, note) + (ascii_labels(values) if fmt == "ascii" else binary_list(values, ldt))
    start = len(neighbour)
    body = "%d\n(\n" % len(patches)
    for name, kind, count in patches:
        body += ("    %s\n    {\n        type            %s;\n        inGroups        1(%s);\n"
                 "        nFaces          %d;\n        startFace       %d;\n    }\n") % (name, kind, kind, count, start)
        start += count
    out["boundary"] = header(fmt, "polyBoundaryMesh", "boundary", label, scalar) + (body + ")\n").encode()
    return {name: data + FOOTER.encode() for name, data in out.items()}


def companions(ncells, nx, ny, nz, args):
    """cellZones (the top layer of cells as zone `lid`) and sets/lidCells, by path."""
    lid = [c for c in range(ncells) if (c // nx) % ny == ny - 1]
    cells = " ".join(map(str, lid))
    zones = header("ascii", "regIOobject", "cellZones", args.label, args.scalar)
    zones += ("1\n(\nlid\n{\n    type cellZone;\ncellLabels      List<label> %d(%s);\n}\n)\n" % (len(lid), cells)).encode()
    cell_set = header("ascii", "cellSet", "lidCells", args.label, args.scalar)
    cell_set += ascii_labels(lid)
    return {"cellZones": zones + FOOTER.encode(), os.path.join("sets", "lidCells"): cell_set + FOOTER.encode()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder")
    parser.add_argument("--cells", type=int, nargs=3, default=[4, 3, 2])
    parser.add_argument("--box", type=float, nargs=3, default=[0.1, 0.1, 0.01])
    parser.add_argument("--format", choices=["ascii", "binary"], default="ascii")
    parser.add_argument("--label", type=int, choices=[32, 64], default=32)
    parser.add_argument("--scalar", type=int, choices=[32, 64], default=64)
    parser.add_argument("--faces", choices=["list", "compact"], default=None)
    parser.add_argument("--bundle")
    args = parser.parse_args()
    if args.faces is None:
        args.faces = "list" if args.format == "ascii" else "compact"
    nx, ny, nz = args.cells
    points, faces, owner, neighbour, patches = grid(nx, ny, nz, args.box)
    files = write_files(points, faces, owner, neighbour, patches, args)
    if args.bundle:
        with open(args.bundle, "wb") as f:
            for name in ("points", "faces", "owner", "neighbour", "boundary"):
                f.write(struct.pack("<Q", len(files[name])) + files[name])
        return
    files.update(companions(nx * ny * nz, nx, ny, nz, args))
    for name, data in files.items():
        path = os.path.join(args.folder, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
