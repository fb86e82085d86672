"""Volume meshes through the CLI, held against meshio (Debian's python3-meshio) as an
independent reader, on real meshes made at test time (volume_corpus.py): TetGen's
tetrahedra of CGAL's elephant, Gmsh's hexahedra and prism/tet boundary layer, an OpenFOAM
polyMesh (test_data/volume), and a designed case for the inverted-cell guard.
"""
import json
import os
import shutil
import struct

import meshio
import numpy as np
import pytest

import volume_corpus as corpus

IDENTITY = {"version": 1, "steps": [{"op": "lattice", "name": "L", "basis": "bspline", "degree": 3,
                                     "box": {"fit": "aabb", "padding": 0.05}, "cells": [5, 5, 5]}]}


def moved(by, index=(2, 2, 2), basis="bspline", cells=(5, 5, 5)):
    return {"version": 1, "steps": [
        {"op": "lattice", "name": "L", "basis": basis, "degree": 3 if basis == "bspline" else 1,
         "box": {"fit": "aabb", "padding": 0.05}, "cells": list(cells)},
        {"op": "move", "lattice": "L", "points": [{"index": list(index), "by": list(by)}]}]}


def write_json(path, value):
    with open(path, "w") as f:
        json.dump(value, f)
    return str(path)


@pytest.fixture(scope="module")
def meshes(tmp_path_factory, cgal_mesh):
    """The real meshes: name -> a meshio.Mesh read from the file Gmsh or TetGen wrote."""
    folder = tmp_path_factory.mktemp("volume")
    tets = meshio.read(corpus.elephant_tets(cgal_mesh("elephant.off"), str(folder)))
    return {
        "elephant": tets,
        "hex": meshio.read(corpus.gmsh_mesh(corpus.HEX_GEO, str(folder), "hex")),
        "mixed": meshio.read(corpus.gmsh_mesh(corpus.MIXED_GEO, str(folder), "mixed")),
        "folder": folder,
    }


def same_cells(a, b):
    """The same cells, kind by kind in order (meshio splits them into blocks)."""
    def by_kind(m):
        out = {}
        for block in m.cells:
            out.setdefault(block.type, []).append(block.data)
        return {k: np.concatenate(v) for k, v in out.items()}
    ka, kb = by_kind(a), by_kind(b)
    assert ka.keys() == kb.keys()
    for kind in ka:
        np.testing.assert_array_equal(ka[kind], kb[kind], err_msg=kind)


@pytest.mark.parametrize("variant", sorted(corpus.MESHIO_VARIANTS))
def test_an_unmoved_lattice_writes_every_format_back_byte_for_byte(variant, meshes, run_cli, tmp_path):
    source = corpus.write_variant(meshes["elephant"], str(tmp_path), "elephant", variant)
    out = str(tmp_path / ("out" + os.path.splitext(source)[1]))
    r = run_cli("run", source, write_json(tmp_path / "s.json", IDENTITY), "-o", out, "--quiet")
    assert r.returncode == 0, r.stderr
    with open(source, "rb") as a, open(out, "rb") as b:
        assert a.read() == b.read()


@pytest.mark.parametrize("variant", sorted(corpus.MESHIO_VARIANTS))
def test_a_lattice_moves_the_nodes_as_it_moves_the_same_points_as_a_cloud(variant, meshes, run_cli, tmp_path):
    """The volume run's nodes (read back by meshio) are the point-cloud run's points (a
    binary PLY of meshio's nodes), bit for bit in the file's precision; cells unchanged."""
    mesh = meshes["elephant"]
    source = corpus.write_variant(mesh, str(tmp_path), "elephant", variant)
    original = meshio.read(source)
    script = write_json(tmp_path / "s.json", moved([0.05, -0.03, 0.02]))
    out = str(tmp_path / ("out" + os.path.splitext(source)[1]))
    r = run_cli("run", source, script, "-o", out, "--quiet", "--stats", tmp_path / "stats.json")
    assert r.returncode == 0, r.stderr
    cloud = tmp_path / "nodes.ply"
    write_ply(cloud, original.points.astype(np.float64))
    r = run_cli("run", cloud, script, "-o", tmp_path / "cloud_out.ply", "--quiet")
    assert r.returncode == 0, r.stderr
    expected = read_ply(tmp_path / "cloud_out.ply")
    result = meshio.read(out)
    assert result.points.dtype == original.points.dtype
    np.testing.assert_array_equal(result.points, expected.astype(original.points.dtype))
    assert not np.array_equal(result.points, original.points)
    same_cells(result, original)
    with open(tmp_path / "stats.json") as f:
        stats = json.load(f)
    assert stats["input"]["volume"]["nodes"] == len(original.points)
    assert stats["input"]["guard"]["inverted_cells"] == 0
    assert stats["steps"][1]["guard"]["inverted_cells"] == 0


def write_ply(path, points):
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty double x\n"
              "property double y\nproperty double z\nend_header\n" % len(points))
    with open(path, "wb") as f:
        f.write(header.encode() + np.ascontiguousarray(points, dtype="<f8").tobytes())


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    count = int(header.split("element vertex ")[1].split()[0])
    assert "property double x" in header
    return np.frombuffer(data[end:end + 24 * count], dtype="<f8").reshape(count, 3)


@pytest.mark.parametrize("variant", sorted(corpus.GMSH_VARIANTS))
@pytest.mark.parametrize("name", ["hex", "mixed"])
def test_gmsh_meshes_keep_their_groups_and_read_as_meshio_reads_them(name, variant, meshes, run_cli, tmp_path):
    geo = corpus.HEX_GEO if name == "hex" else corpus.MIXED_GEO
    source = corpus.gmsh_mesh(geo, str(tmp_path), name, variant)
    info = run_cli("info", "--json", source)
    assert info.returncode == 0, info.stderr
    facts = json.loads(info.stdout)
    reference = meshio.read(source)
    np.testing.assert_array_equal(reference.points[:, :3], meshio.read(source).points[:, :3])
    counts = {}
    for block in reference.cells:
        counts[block.type] = counts.get(block.type, 0) + len(block.data)
    ours = {k.replace("hexahedron", "hexahedron"): v for k, v in facts["volume"]["cells_by_type"].items()}
    for kind in ("tetra", "hexahedron", "wedge"):
        assert ours.get(kind, 0) == counts.get(kind, 0), kind
    assert facts["guard"]["inverted_cells"] == 0, "a mesh as Gmsh made it has no inverted cell"
    if variant.startswith("msh"):  # meshio keeps $PhysicalNames in field_data
        assert {m["name"] for m in facts["volume"]["markers"]} == set(reference.field_data)
    out = str(tmp_path / ("out" + os.path.splitext(source)[1]))
    r = run_cli("run", source, write_json(tmp_path / "s.json", moved([0.02, 0.01, -0.02])), "-o", out, "--quiet")
    assert r.returncode == 0, r.stderr
    result = meshio.read(out)
    same_cells(result, reference)
    assert not np.array_equal(result.points, reference.points)


def test_the_elephant_from_tetgen_has_no_inverted_cell_and_a_large_move_inverts_some(meshes, run_cli, tmp_path):
    source = corpus.write_variant(meshes["elephant"], str(tmp_path), "elephant", "vtu_zlib")
    info = json.loads(run_cli("info", "--json", source).stdout)
    assert info["volume"]["cells_by_type"] == {"tetra": len(meshes["elephant"].cells[0].data)}
    assert info["guard"]["inverted_cells"] == 0
    r = run_cli("run", source, write_json(tmp_path / "s.json", moved([0, 0, -3])), "-o",
                tmp_path / "out.vtu", "--quiet")
    assert r.returncode == 2
    assert "inverted cell" in r.stderr and "nothing is written" in r.stderr
    assert not (tmp_path / "out.vtu").exists()


# The guard's designed case: a block of hexahedra beside a block of tetrahedra, and a
# control point pulled through the mesh. Which cells invert is computed here from the
# written nodes with this file's own corner tables (corpus.CORNERS).
def test_the_guard_counts_the_inverted_cells_an_independent_computation_finds(run_cli, tmp_path):
    mesh = corpus.hex_and_tet_blocks()
    source = str(tmp_path / "blocks.vtu")
    meshio.write(source, mesh, binary=False)
    big = moved([0, 0, -12], index=(1, 1, 1), basis="bernstein", cells=(2, 2, 2))
    stats_path = tmp_path / "stats.json"
    refused = run_cli("run", source, write_json(tmp_path / "big.json", big), "-o", tmp_path / "no.vtu", "--quiet")
    assert refused.returncode == 2 and not (tmp_path / "no.vtu").exists()
    r = run_cli("run", source, tmp_path / "big.json", "-o", tmp_path / "out.vtu", "--quiet", "--allow-inverted",
                "--stats", stats_path)
    assert r.returncode == 0, r.stderr
    points = meshio.read(tmp_path / "out.vtu").points
    hexes, tets = mesh.cells[0].data, mesh.cells[1].data
    hex_sj = corpus.corner_determinants(points, hexes, "hexahedron").min(axis=1)
    tet_sj = corpus.corner_determinants(points, tets, "tetra").min(axis=1) * np.sqrt(2)
    scaled = np.concatenate([hex_sj, tet_sj])
    tet_volume = np.einsum("ij,ij->i", points[tets[:, 1]] - points[tets[:, 0]],
                           np.cross(points[tets[:, 2]] - points[tets[:, 0]], points[tets[:, 3]] - points[tets[:, 0]]))
    bad = np.concatenate([hex_sj <= 0, tet_volume <= 0])
    assert bad[:len(hexes)].sum() > 0 and bad[len(hexes):].sum() > 0, "the case inverts cells of both kinds"
    guard = json.load(open(stats_path))["steps"][1]["guard"]
    assert guard["inverted_cells"] == int(bad.sum())
    assert guard["first_inverted_cell"] == int(np.flatnonzero(bad)[0])
    assert guard["min_scaled_jacobian"] == pytest.approx(scaled.min(), abs=1e-12)
    order = np.lexsort((np.arange(len(scaled)), scaled))[:5]
    assert [c["cell"] for c in guard["worst_cells"]] == [int(i) for i in order]
    assert ("%d inverted cell" % bad.sum()) in refused.stderr
    assert ("the first: cell %d in file order" % np.flatnonzero(bad)[0]) in refused.stderr
    assert any("as allowed" in w for w in json.load(open(stats_path))["warnings"])
    small = run_cli("run", source, write_json(tmp_path / "small.json", moved([0, 0, -0.01], index=(1, 1, 1),
                                                                             basis="bernstein", cells=(2, 2, 2))),
                    "-o", tmp_path / "small.vtu", "--quiet", "--stats", tmp_path / "small_stats.json")
    assert small.returncode == 0, small.stderr
    assert json.load(open(tmp_path / "small_stats.json"))["steps"][1]["guard"]["inverted_cells"] == 0


def test_the_script_can_allow_inverted_cells(run_cli, tmp_path):
    source = str(tmp_path / "blocks.vtu")
    meshio.write(source, corpus.hex_and_tet_blocks(), binary=False)
    big = moved([0, 0, -12], index=(1, 1, 1), basis="bernstein", cells=(2, 2, 2))
    big["allow_inverted"] = True
    r = run_cli("run", source, write_json(tmp_path / "s.json", big), "-o", tmp_path / "out.vtu")
    assert r.returncode == 0, r.stderr
    assert "warning" in r.stderr and "inverted cell" in r.stderr


# The Python module on a volume mesh: read, moved through the vertices view or a run,
# written back; inverted cells refused as the CLI refuses them, unless allowed.
def test_the_python_module_writes_volume_meshes_and_refuses_inverted_cells(tmp_path):
    import ffdtool
    source = str(tmp_path / "blocks.vtu")
    meshio.write(source, corpus.hex_and_tet_blocks(), binary=True, compression=None)
    mesh = ffdtool.read(source)
    mesh.write(tmp_path / "same.vtu")
    assert open(tmp_path / "same.vtu", "rb").read() == open(source, "rb").read()
    big = moved([0, 0, -12], index=(1, 1, 1), basis="bernstein", cells=(2, 2, 2))
    out, stats = ffdtool.run(mesh, big)
    assert stats["steps"][1]["guard"]["inverted_cells"] > 0
    with pytest.raises(ffdtool.InputError) as refused:
        out.write(tmp_path / "no.vtu")
    assert "inverted cell" in str(refused.value) and "allow_inverted=True" in str(refused.value)
    assert not (tmp_path / "no.vtu").exists()
    with pytest.warns(ffdtool.FfdWarning, match="as allowed"):
        out.write(tmp_path / "yes.vtu", allow_inverted=True)
    assert np.array_equal(meshio.read(tmp_path / "yes.vtu").points, out.vertices)
    # Moved through the view: a node of the first hexahedron pulled through its opposite face.
    hexes = corpus.hex_and_tet_blocks().cells[0].data
    mesh.vertices[hexes[0][6]] = mesh.vertices[hexes[0][0]] - 0.5
    with pytest.raises(ffdtool.InputError, match="the first: cell 0 in file order"):
        mesh.write(tmp_path / "no.vtu")
    assert not (tmp_path / "no.vtu").exists()


@pytest.mark.parametrize("encoding", ["ascii", "binary"])
def test_an_openfoam_case_rewrites_points_and_copies_every_other_file(encoding, data, run_cli, tmp_path):
    case = os.path.join(data, "volume", "cavity_" + encoding)
    source = os.path.join(case, "polyMesh") if os.path.isdir(os.path.join(case, "polyMesh")) else case
    out = tmp_path / "polyMesh"
    r = run_cli("run", source, write_json(tmp_path / "s.json", moved([0.001, 0.002, 0])), "-o", out, "--quiet",
                "--stats", tmp_path / "stats.json")
    assert r.returncode == 0, r.stderr
    names = sorted(os.path.relpath(os.path.join(d, f), source) for d, _, fs in os.walk(source) for f in fs)
    assert sorted(os.path.relpath(os.path.join(d, f), out) for d, _, fs in os.walk(out) for f in fs) == names
    for name in names:
        same = open(os.path.join(source, name), "rb").read() == open(out / name, "rb").read()
        assert same == (name != "points"), name
    stats = json.load(open(tmp_path / "stats.json"))
    assert stats["input"]["guard"]["inverted_cells"] == 0
    assert stats["input"]["volume"]["cells_by_type"]["polyhedron"] > 0
    (tmp_path / "same").mkdir()
    identity = run_cli("run", source, write_json(tmp_path / "i.json", IDENTITY), "-o", tmp_path / "same" / "polyMesh",
                       "--quiet")
    assert identity.returncode == 0, identity.stderr
    assert open(os.path.join(source, "points"), "rb").read() == open(tmp_path / "same" / "polyMesh" / "points", "rb").read()


SU2 = "NDIME= 3\nNELEM= 1\n10 0 1 2 3 0\nNPOIN= 4\n0 0 0 0\n1 0 0 1\n0 1 0 2\n0 0 1 3\nNMARK= 1\n" \
      "MARKER_TAG= wall\nMARKER_ELEMS= 1\n5 0 2 1 0\n"


def refusal_cases(tmp_path, meshes):
    """name -> (path, words the one error line must hold)."""
    cases = {}
    def put(name, text):
        path = tmp_path / name
        path.write_bytes(text if isinstance(text, bytes) else text.encode())
        return str(path)
    cases["node_out_of_range"] = (put("range.su2", SU2.replace("10 0 1 2 3", "10 0 1 2 7")),
                                  ["range.su2:3:", "node index 7 out of range"])
    cases["unknown_cell_type"] = (put("type.su2", SU2.replace("10 0 1 2 3", "11 0 1 2 3")),
                                  ["type.su2:3:", "element type 11"])
    cases["marker_missing_elements"] = (put("marker.su2", SU2.replace("MARKER_ELEMS= 1", "MARKER_ELEMS= 3")),
                                        ["marker.su2:", "the file ends before every element of the marker is read"])
    binary = corpus.write_variant(meshes["elephant"], str(tmp_path), "cut", "msh41_binary")
    data = open(binary, "rb").read()
    cases["truncated_binary_msh"] = (put("cut.msh", data[:len(data) // 2]), ["cut.msh"])
    vtu = corpus.write_variant(meshes["elephant"], str(tmp_path), "cutvtu", "vtu_base64")
    data = open(vtu, "rb").read()
    cases["truncated_vtu"] = (put("cut.vtu", data[:len(data) // 2]), ["cut.vtu"])
    foam = tmp_path / "nofaces" / "polyMesh"
    shutil.copytree(os.path.join(os.environ["FFD_TEST_DATA"], "volume", "cavity_ascii"), foam.parent, dirs_exist_ok=True)
    if not (foam / "points").exists():
        foam = foam.parent
    os.remove(foam / "faces")
    cases["missing_openfoam_file"] = (str(foam), ["faces"])
    return cases


def test_bad_volume_files_are_refused_with_the_file_and_the_place(meshes, run_cli, tmp_path):
    script = write_json(tmp_path / "s.json", IDENTITY)
    for name, (path, words) in refusal_cases(tmp_path, meshes).items():
        out = tmp_path / ("out_" + name + (os.path.splitext(path)[1] or "")) if os.path.isfile(path) else \
            tmp_path / "polyMesh"
        r = run_cli("run", path, script, "-o", out, "--quiet")
        assert r.returncode == 2, (name, r.stderr)
        lines = [line for line in r.stderr.splitlines() if line.strip()]
        assert len(lines) == 1, (name, r.stderr)
        for word in words:
            assert word in lines[0], (name, lines[0])
        assert not out.exists(), name


@pytest.mark.parametrize("op", [{"op": "remesh"}, {"op": "bcm", "name": "e", "support": {"box": {"min": [0, 0, 0],
                                "max": [1, 1, 1]}}, "handles": [{"name": "h", "select": {"near": [0, 0, 0]}}]}])
def test_surface_ops_refuse_a_volume_mesh(op, run_cli, tmp_path):
    source = tmp_path / "one.su2"
    source.write_text(SU2)
    script = write_json(tmp_path / "s.json", {"version": 1, "steps": [
        {"op": "lattice", "name": "L", "basis": "bernstein", "box": {"fit": "aabb", "padding": 0.1},
         "cells": [1, 1, 1]}, op]})
    r = run_cli("run", source, script, "-o", tmp_path / "out.su2", "--quiet")
    assert r.returncode == 2, r.stderr
    assert "acts on surface meshes" in r.stderr and "volume mesh" in r.stderr
    assert not (tmp_path / "out.su2").exists()


def test_a_volume_mesh_written_as_a_surface_format_warns_that_the_cells_are_dropped(run_cli, tmp_path):
    source = tmp_path / "one.su2"
    source.write_text(SU2)
    r = run_cli("run", source, write_json(tmp_path / "s.json", IDENTITY), "-o", tmp_path / "nodes.ply")
    assert r.returncode == 0, r.stderr
    assert "cells" in r.stderr and "are not written" in r.stderr


def test_a_lattice_box_fits_a_marker(meshes, run_cli, tmp_path):
    """{"marker": NAME} picks the nodes of a physical group's elements: the box fitted to
    the prism layer's floor ("wall", z = 0) is that face's box, padded."""
    source = corpus.gmsh_mesh(corpus.MIXED_GEO, str(tmp_path), "mixed", "msh41_binary")
    script = {"version": 1, "steps": [{"op": "lattice", "name": "L", "basis": "bernstein", "cells": [1, 1, 1],
                                       "box": {"fit": "aabb", "padding": 0, "select": {"marker": "wall"}}}]}
    r = run_cli("run", source, write_json(tmp_path / "s.json", script), "-o", tmp_path / "out.msh", "--quiet",
                "--stats", tmp_path / "stats.json")
    assert r.returncode == 0, r.stderr
    step = json.load(open(tmp_path / "stats.json"))["steps"][0]
    box = step["box"]
    reference = meshio.read(source)
    wall = np.unique(np.concatenate([reference.cells[i].data.ravel()
                                     for i in range(len(reference.cells))
                                     if reference.cells[i].type == "triangle"]))
    lo = reference.points[wall].min(axis=0)
    hi = reference.points[wall].max(axis=0)
    np.testing.assert_allclose(box["origin"][:2], lo[:2], atol=1e-12)  # a flat pick's z gets a sliver
    np.testing.assert_allclose(np.diag(np.array(box["axes"]))[:2], (hi - lo)[:2], atol=1e-12)
    assert abs(box["origin"][2]) < 1e-5
    script["steps"][0]["box"]["select"] = {"marker": "nose"}
    r = run_cli("run", source, write_json(tmp_path / "bad.json", script), "-o", tmp_path / "out2.msh")
    assert r.returncode == 2
    assert "/steps/0/box/select/marker" in r.stderr and "no marker 'nose'" in r.stderr and "wall" in r.stderr


def test_a_marker_cannot_name_lattice_points(run_cli, tmp_path):
    script = moved([0, 0, 0.1])
    script["steps"][1] = {"op": "move", "lattice": "L", "select": {"marker": "wall"},
                          "transform": {"translate": [0, 0, 0.1]}}
    r = run_cli("validate", write_json(tmp_path / "s.json", script))
    assert r.returncode == 2
    assert "/steps/1/select" in r.stderr and "a marker names mesh nodes, not lattice points" in r.stderr


PLANAR_SU2 = ("NDIME= 2\nNELEM= 2\n5 0 1 2 0\n9 1 3 4 2 1\nNPOIN= 5\n0 0 0\n1 0 1\n0 1 2\n2 0 3\n2 1 4\n"
              "NMARK= 1\nMARKER_TAG= wall\nMARKER_ELEMS= 2\n3 0 1\n3 1 3\n")


def test_a_planar_su2_mesh_is_a_surface_written_back_in_two_dimensions(run_cli, tmp_path):
    source = tmp_path / "plane.su2"
    source.write_text(PLANAR_SU2)
    script = {"version": 1, "steps": [
        {"op": "lattice", "name": "L", "basis": "bernstein", "cells": [1, 1, 1], "box": {"min": [-1, -1, -1], "max": [3, 2, 1]}},
        {"op": "move", "lattice": "L", "points": [{"index": [1, 1, 0], "by": [0.5, 0.25, 0]},
                                                  {"index": [1, 1, 1], "by": [0.5, 0.25, 0]}]}]}
    r = run_cli("run", source, write_json(tmp_path / "s.json", script), "-o", tmp_path / "out.su2", "--quiet",
                "--stats", tmp_path / "stats.json")
    assert r.returncode == 0, r.stderr
    stats = json.load(open(tmp_path / "stats.json"))
    assert stats["input"]["faces"] == 2  # the triangle and the quad
    out = (tmp_path / "out.su2").read_text().splitlines()
    nodes = out[out.index("NPOIN= 5") + 1:out.index("NPOIN= 5") + 6]
    assert all(len(line.split()) == 3 for line in nodes), nodes  # x y and the index, as read
    assert nodes[0] != "0 0 0"
    assert out[:out.index("NPOIN= 5") + 1] == PLANAR_SU2.splitlines()[:out.index("NPOIN= 5") + 1]
    r = run_cli("render", tmp_path / "out.su2", "-o", tmp_path / "plane.png", "--size", "64x64")
    assert r.returncode == 0, r.stderr
