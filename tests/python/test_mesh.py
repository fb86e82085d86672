"""ffdtool.Mesh and ffdtool.read: views without copies, arrays in and out, errors by name."""
import filecmp

import numpy as np
import pytest

import ffdtool


def test_vertices_view_the_mesh_and_writes_go_through(bunny, tmp_path, run_cli):
    mesh = ffdtool.read(bunny)
    v = mesh.vertices
    assert v.shape == (mesh.num_vertices, 3) and v.dtype == np.float64 and v.flags.c_contiguous
    assert v.base is mesh
    assert np.shares_memory(v, mesh.vertices)  # two views of one memory, no copy
    v[0] = [100.0, 200.0, 300.0]
    mesh.write(tmp_path / "edited.obj")
    back = ffdtool.read(tmp_path / "edited.obj")
    assert np.array_equal(back.vertices[0], [100.0, 200.0, 300.0])
    assert np.array_equal(back.vertices[1:], v[1:])


def test_an_unedited_mesh_is_written_as_the_cli_writes_it(bunny, tmp_path, run_cli):
    ffdtool.read(bunny).write(tmp_path / "py.ply")
    script = tmp_path / "empty.json"
    script.write_text('{"version": 1, "steps": []}')
    assert run_cli("run", bunny, script, "-o", tmp_path / "cli.ply", "--quiet").returncode == 0
    assert filecmp.cmp(tmp_path / "py.ply", tmp_path / "cli.ply", shallow=False)


def test_faces_of_a_triangle_mesh_are_an_m_by_3_array(bunny):
    mesh = ffdtool.read(bunny)
    faces = mesh.faces
    assert faces.shape == (mesh.num_faces, 3) and faces.dtype == np.int64
    assert faces.min() >= 0 and faces.max() < mesh.num_vertices
    normals = mesh.normals
    assert not normals.flags.writeable
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)


def test_a_mesh_from_arrays_round_trips_through_a_file(tmp_path):
    vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 1]], dtype=float)
    mixed = [[0, 1, 2, 3], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    mesh = ffdtool.Mesh(vertices, mixed)
    offsets, indices = mesh.faces
    assert list(offsets) == [0, 4, 7, 10, 13, 16]
    assert list(indices[:4]) == [0, 1, 2, 3]
    mesh.write(tmp_path / "pyramid.off")
    back = ffdtool.read(tmp_path / "pyramid.off")
    assert np.array_equal(back.vertices, vertices)
    assert np.array_equal(back.faces[0], offsets) and np.array_equal(back.faces[1], indices)
    tris = ffdtool.Mesh(vertices, np.array([[0, 1, 4], [1, 2, 4]], dtype=np.int32))
    assert tris.faces.shape == (2, 3)
    cloud = ffdtool.Mesh(vertices)
    assert cloud.num_faces == 0 and cloud.num_vertices == 5


def test_bad_arrays_and_files_raise_input_error_with_the_place(tmp_path):
    with pytest.raises(ffdtool.InputError) as e:
        ffdtool.Mesh(np.zeros((3, 3)), [[0, 1, 2], [0, 1, 7]])
    assert e.value.place == "Mesh(): faces[1]" and "vertex 7" in e.value.message
    assert str(e.value).startswith("Mesh(): faces[1]: ")
    with pytest.raises(ffdtool.InputError, match="expected an \\(n, 3\\) array"):
        ffdtool.Mesh(np.zeros((4, 2)))
    with pytest.raises(ffdtool.InputError, match="integers") as e:
        ffdtool.Mesh(np.zeros((3, 3)), np.array([[0.0, 1.0, 2.0]]))
    assert e.value.place == "Mesh(): faces[0]"
    with pytest.raises(ffdtool.InputError, match="sequence of vertex indices"):
        ffdtool.Mesh(np.zeros((3, 3)), [[0, 1, 2], 7])
    with pytest.raises(ffdtool.InputError, match="not a finite number") as e:
        ffdtool.Mesh(np.array([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]]), [[0, 1, 2]])
    assert e.value.place == "Mesh(): vertices[1]"
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 9\n")
    with pytest.raises(ffdtool.InputError) as e:
        ffdtool.read(bad)
    assert str(bad) in e.value.place and ":3" in e.value.place
    with pytest.raises(ffdtool.InputError, match="missing.obj"):
        ffdtool.read(tmp_path / "missing.obj")
    assert issubclass(ffdtool.InputError, ValueError) and issubclass(ffdtool.IoError, OSError)
    assert issubclass(ffdtool.TopologyError, ffdtool.InputError)


def test_a_cgal_mesh_round_trips_exactly(cgal_mesh, tmp_path):
    path = cgal_mesh("elephant.off")
    mesh = ffdtool.read(path)
    assert mesh.num_vertices > 1000 and repr(mesh).startswith("<ffdtool.Mesh")
    mesh.write(tmp_path / "elephant.obj")
    assert np.array_equal(ffdtool.read(tmp_path / "elephant.obj").vertices, mesh.vertices)


def test_colours_and_uvs_are_the_files(tmp_path, data):
    coff = tmp_path / "c.off"
    coff.write_text("COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n")
    colors = ffdtool.read(coff).colors
    assert colors.dtype == np.float32 and np.array_equal(colors, np.eye(3, dtype=np.float32))
    assert ffdtool.read(coff).uvs is None
    obj = tmp_path / "t.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nvt 1 0\nf 1/1 2/2 3/1\n")
    mesh = ffdtool.read(obj)
    assert np.array_equal(mesh.uvs, [[0.25, 0.5], [1, 0]]) and list(mesh.corner_uvs) == [0, 1, 0]
    assert mesh.colors is None
