# Makes test_data/volume/mixed_* (VTU and legacy VTK) with meshio 7.0, and the appended
# VTU variants (which meshio does not write) by hand in VTK's layout.
import base64, sys, zlib
import numpy as np
import meshio

out = sys.argv[1]
# A unit hex, a wedge on top of it, a pyramid beside it, two tets beside that.
pts = np.array([
    [0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1],
    [0.5, 0.1, 1.7], [0.5, 0.9, 1.7], [2.25, 0.5, 0.5], [1 / 3, -1.1, 0.2], [0.7, -0.9, 1e-7],
], dtype=np.float64)
cells = [("hexahedron", np.array([[0, 1, 2, 3, 4, 5, 6, 7]])),
         ("wedge", np.array([[4, 5, 8, 7, 6, 9]])),
         ("pyramid", np.array([[1, 2, 6, 5, 10]])),
         ("tetra", np.array([[0, 1, 4, 11], [1, 5, 4, 12]]))]
point_data = {"temperature": np.arange(13, dtype=np.float64) * 0.5}
cell_data = {"zone": [np.array([1], dtype=np.int32), np.array([2], dtype=np.int32), np.array([3], dtype=np.int32),
                      np.array([4, 5], dtype=np.int32)]}
m64 = meshio.Mesh(pts, cells, point_data=point_data, cell_data=cell_data)
m32 = meshio.Mesh(pts.astype(np.float32), cells, point_data=point_data, cell_data=cell_data)
meshio.write(f"{out}/mixed_ascii.vtu", m64, file_format="vtu", binary=False)
meshio.write(f"{out}/mixed_binary.vtu", m64, file_format="vtu", binary=True, compression=None)
meshio.write(f"{out}/mixed_zlib32.vtu", m32, file_format="vtu", binary=True, compression="zlib")
meshio.vtk.write(f"{out}/mixed_ascii42.vtk", m64, binary=False, fmt_version="4.2")
meshio.vtk.write(f"{out}/mixed_binary42.vtk", m32, binary=True, fmt_version="4.2")
meshio.vtk.write(f"{out}/mixed_ascii51.vtk", m32, binary=False, fmt_version="5.1")
meshio.vtk.write(f"{out}/mixed_binary51.vtk", m64, binary=True, fmt_version="5.1")


def appended(path, points, encoding, zlib_blocks, header, block=64):
    """VTK's appended layout: PointData, Points, then the Cells arrays and CellData."""
    h = {"UInt32": np.uint32, "UInt64": np.uint64}[header]
    # VTK's wedge corner order is meshio's [0, 2, 1, 3, 5, 4] (what meshio.write does).
    conn = np.concatenate([(c[:, [0, 2, 1, 3, 5, 4]] if t == "wedge" else c).ravel() for t, c in cells]).astype(np.int64)
    offs = np.cumsum([c.shape[1] for _, c in cells for _ in c]).astype(np.int64)
    types = np.array([{"hexahedron": 12, "wedge": 13, "pyramid": 14, "tetra": 10}[t] for t, c in cells for _ in c], np.uint8)
    arrays = [("PointData", "temperature", "Float64", 1, point_data["temperature"]),
              ("Points", None, "Float32" if points.dtype == np.float32 else "Float64", 3, points),
              ("Cells", "connectivity", "Int64", 1, conn), ("Cells", "offsets", "Int64", 1, offs),
              ("Cells", "types", "UInt8", 1, types),
              ("CellData", "zone", "Int32", 1, np.concatenate(cell_data["zone"]))]
    data, offsets = b"", []
    for _, _, _, _, a in arrays:
        raw = a.tobytes()
        if zlib_blocks:
            chunks = [raw[i:i + block] for i in range(0, len(raw), block)] or [b""]
            packed = [zlib.compress(c) for c in chunks]
            last = len(raw) - (len(chunks) - 1) * block
            head = np.array([len(chunks), block, last] + [len(p) for p in packed], h).tobytes()
            body = b"".join(packed)
        else:
            head, body = np.array([len(raw)], h).tobytes(), raw
        enc = base64.b64encode(head) + base64.b64encode(body) if encoding == "base64" else head + body
        offsets.append(len(data))
        data += enc
    comp = ' compressor="vtkZLibDataCompressor"' if zlib_blocks else ""
    x = [f'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="{header}"{comp}>\n',
         f'  <UnstructuredGrid>\n    <Piece NumberOfPoints="{len(points)}" NumberOfCells="{len(types)}">\n']
    for section in ["PointData", "CellData", "Points", "Cells"]:
        x.append(f"      <{section}>\n")
        for (s, name, t, n, _), o in zip(arrays, offsets):
            if s == section:
                nm = f' Name="{name}"' if name else ""
                nc = f' NumberOfComponents="{n}"' if n > 1 else ""
                x.append(f'        <DataArray type="{t}"{nm}{nc} format="appended" offset="{o}"/>\n')
        x.append(f"      </{section}>\n")
    x.append(f'    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding="{encoding}">\n   _')
    with open(path, "wb") as f:
        f.write("".join(x).encode() + data + b"\n  </AppendedData>\n</VTKFile>\n")


appended(f"{out}/mixed_appended_raw.vtu", pts, "raw", False, "UInt64")
appended(f"{out}/mixed_appended_zlib32.vtu", pts.astype(np.float32), "raw", True, "UInt32")
appended(f"{out}/mixed_appended_base64.vtu", pts, "base64", False, "UInt32")
appended(f"{out}/mixed_appended_base64_zlib.vtu", pts, "base64", True, "UInt64")

# A polyhedron: a square pyramid given by its five faces, outward.
poly = meshio.Mesh(np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.75]]),
                   [("polyhedron5", [[[0, 3, 2, 1], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]])])
meshio.write(f"{out}/poly_ascii.vtu", poly, binary=False)
meshio.write(f"{out}/poly_zlib.vtu", poly, binary=True, compression="zlib")
