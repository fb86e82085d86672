"""Volume meshes for the volume tests, made at test time from Debian's tools:

- a tetrahedral mesh of CGAL's elephant (libcgal-demo's data) made by TetGen
  (`tetgen -pq1.5 -k`, a legacy VTK file);
- a hexahedral block and a mixed boundary-layer mesh (a layer of prisms under tetrahedra)
  made by Gmsh from the .geo texts below, with named physical groups;
- a hex block and tet block side by side, written by meshio from numpy (the guard's
  designed case);
- each written again by meshio in every encoding it has (VTU ASCII/base64/zlib, legacy
  VTK ASCII/binary, MSH 2.2 and 4.1 ASCII/binary, SU2), and by Gmsh in its own.
"""
import os
import subprocess

import meshio
import numpy as np

HEX_GEO = """Point(1) = {0, 0, 0, 1};
l[] = Extrude {1, 0, 0} { Point{1}; Layers{4}; };
s[] = Extrude {0, 1, 0} { Line{l[1]}; Layers{4}; Recombine; };
v[] = Extrude {0, 0, 1} { Surface{s[1]}; Layers{4}; Recombine; };
Physical Surface("bottom") = {s[1]};
Physical Surface("top") = {v[0]};
Physical Volume("block") = {v[1]};
"""

# A boundary layer: the bottom square's triangles extruded into three layers of prisms,
# then tetrahedra above, conforming to the layer's top triangles.
MIXED_GEO = """Point(1) = {0, 0, 0, 0.25}; Point(2) = {1, 0, 0, 0.25};
Point(3) = {1, 1, 0, 0.25}; Point(4) = {0, 1, 0, 0.25};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
a[] = Extrude {0, 0, 0.2} { Surface{1}; Layers{3}; Recombine; };
b[] = Extrude {0, 0, 0.8} { Surface{a[0]}; };
Physical Surface("wall") = {1};
Physical Volume("layer") = {a[1]};
Physical Volume("core") = {b[1]};
"""

# meshio's writers: variant name -> (extension, keyword arguments of meshio.write).
MESHIO_VARIANTS = {
    "vtu_ascii": (".vtu", {"file_format": "vtu", "binary": False}),
    "vtu_base64": (".vtu", {"file_format": "vtu", "binary": True, "compression": None}),
    "vtu_zlib": (".vtu", {"file_format": "vtu", "binary": True, "compression": "zlib"}),
    "vtk42_ascii": (".vtk", {"file_format": "vtk", "binary": False, "fmt_version": "4.2"}),
    "vtk42_binary": (".vtk", {"file_format": "vtk", "binary": True, "fmt_version": "4.2"}),
    "vtk51_ascii": (".vtk", {"file_format": "vtk", "binary": False, "fmt_version": "5.1"}),
    "vtk51_binary": (".vtk", {"file_format": "vtk", "binary": True, "fmt_version": "5.1"}),
    "msh22_ascii": (".msh", {"file_format": "gmsh22", "binary": False}),
    "msh22_binary": (".msh", {"file_format": "gmsh22", "binary": True}),
    "msh41_ascii": (".msh", {"file_format": "gmsh", "binary": False}),
    "msh41_binary": (".msh", {"file_format": "gmsh", "binary": True}),
    "su2": (".su2", {"file_format": "su2"}),
}

# Gmsh's own writers: variant name -> (extension, command-line format options).
GMSH_VARIANTS = {
    "msh41_ascii": (".msh", ["-format", "msh41"]),
    "msh41_binary": (".msh", ["-format", "msh41", "-bin"]),
    "msh22_ascii": (".msh", ["-format", "msh22"]),
    "msh22_binary": (".msh", ["-format", "msh22", "-bin"]),
    "su2": (".su2", ["-format", "su2"]),
    "vtk": (".vtk", ["-format", "vtk"]),
}


def elephant_tets(off_path, folder):
    """TetGen's quality tetrahedral mesh of a closed OFF surface, as a legacy VTK file."""
    os.makedirs(folder, exist_ok=True)
    local = os.path.join(folder, "elephant.off")
    with open(off_path, "rb") as src, open(local, "wb") as dst:
        dst.write(src.read())
    subprocess.run(["tetgen", "-pq1.5Q", "-k", local], check=True, capture_output=True)
    return os.path.join(folder, "elephant.1.vtk")


def gmsh_mesh(geo_text, folder, stem, variant="msh41_ascii"):
    """Gmsh's 3D mesh of `geo_text` in one of GMSH_VARIANTS."""
    os.makedirs(folder, exist_ok=True)
    geo = os.path.join(folder, stem + ".geo")
    with open(geo, "w") as f:
        f.write(geo_text)
    ext, options = GMSH_VARIANTS[variant]
    out = os.path.join(folder, stem + "_" + variant + ext)
    subprocess.run(["gmsh", "-3", geo, *options, "-o", out], check=True, capture_output=True)
    return out


def hex_and_tet_blocks(n=4):
    """Two unit blocks of an n^3 grid side by side: hexahedra for x in [0, 1], and the
    same grid split into six tetrahedra per cube (Kuhn's split, all positive) for x in
    [1, 2]; they share the x = 1 plane's nodes. Cells: the hexahedra, then the tetrahedra."""
    m = n + 1
    idx = lambda i, j, k: i + (2 * n + 1) * (j + m * k)
    grid = np.array([[i / n, j / n, k / n] for k in range(m) for j in range(m) for i in range(2 * n + 1)])
    hexes, tets = [], []
    kuhn = [(0, 1, 3, 7), (0, 1, 7, 5), (0, 4, 5, 7), (0, 2, 6, 7), (0, 3, 2, 7), (0, 6, 4, 7)]
    for k in range(n):
        for j in range(n):
            for i in range(2 * n):
                c = [idx(i + (b & 1), j + ((b >> 1) & 1), k + (b >> 2)) for b in range(8)]
                if i < n:
                    hexes.append([c[0], c[1], c[3], c[2], c[4], c[5], c[7], c[6]])
                else:
                    for t in kuhn:
                        tet = [c[v] for v in t]
                        p = grid[tet]
                        if np.linalg.det(p[1:] - p[0]) < 0:
                            tet[2], tet[3] = tet[3], tet[2]
                        tets.append(tet)
    return meshio.Mesh(grid, [("hexahedron", np.array(hexes)), ("tetra", np.array(tets))])


def write_variant(mesh, folder, stem, variant):
    """`mesh` written by meshio as one of MESHIO_VARIANTS; returns the path."""
    os.makedirs(folder, exist_ok=True)
    ext, options = MESHIO_VARIANTS[variant]
    path = os.path.join(folder, stem + "_" + variant + ext)
    options = dict(options)
    if options.pop("file_format") == "vtk":  # meshio.write does not pass fmt_version on
        meshio.vtk.write(path, mesh, **options)
    else:
        meshio.write(path, mesh, file_format=MESHIO_VARIANTS[variant][1]["file_format"], **options)
    return path


# Corners of each kind in VTK's order: corner, then the three far ends of its edges in the
# reference shape's orientation; written here apart from ffdtool's tables, from VTK's
# parametric coordinates.
CORNERS = {
    "tetra": [(0, 1, 2, 3), (1, 2, 0, 3), (2, 0, 1, 3), (3, 0, 2, 1)],
    "hexahedron": [(0, 1, 3, 4), (1, 2, 0, 5), (2, 3, 1, 6), (3, 0, 2, 7),
                   (4, 7, 5, 0), (5, 4, 6, 1), (6, 5, 7, 2), (7, 6, 4, 3)],
    "wedge": [(0, 2, 1, 3), (1, 0, 2, 4), (2, 1, 0, 5), (3, 4, 5, 0), (4, 5, 3, 1), (5, 3, 4, 2)],
}


def corner_determinants(points, cells, kind):
    """Each cell's corner determinants det[e1 e2 e3] / (|e1| |e2| |e3|), cells × corners."""
    out = []
    for c, a, b, d in CORNERS[kind]:
        e = [points[cells[:, x]] - points[cells[:, c]] for x in (a, b, d)]
        det = np.einsum("ij,ij->i", e[0], np.cross(e[1], e[2]))
        out.append(det / (np.linalg.norm(e[0], axis=1) * np.linalg.norm(e[1], axis=1) * np.linalg.norm(e[2], axis=1)))
    return np.stack(out, axis=1)
