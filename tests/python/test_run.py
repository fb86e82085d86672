"""ffdtool.run: the CLI's results bit for bit, for every op kind, at any thread count."""
import filecmp
import json
import os
import warnings

import numpy as np
import pytest

import ffdtool

# A cube cage around the bunny (x -5..5, y 0..10, z -4..4 and some), outward quads.
CAGE_OFF = """OFF
8 6 0
-7 -2 -6
 7 -2 -6
 7 12 -6
-7 12 -6
-7 -2 6
 7 -2 6
 7 12 6
-7 12 6
4 0 3 2 1
4 4 5 6 7
4 0 1 5 4
4 2 3 7 6
4 1 2 6 5
4 3 0 4 7
"""

CENTRES = [[-3, 2, 0], [3, 2, 0], [0, 8, 0], [0, 4, 3], [0, 4, -3], [0, 11, 0]]


def steps(*s):
    return {"version": 1, "steps": list(s)}


def inline_scripts():
    """The ops the repository's own scripts (test_data) do not cover."""
    move_centre = {"op": "move", "lattice": "D", "points": [{"index": 2, "by": [0.4, 0.7, -0.2]}]}
    return {
        "rbf": steps({"op": "rbf", "name": "D", "kernel": "thin_plate_spline", "radius": 4, "points": CENTRES},
                     move_centre),
        "idw": steps({"op": "idw", "name": "D", "power": 3, "points": CENTRES}, move_centre),
        "cage": steps({"op": "cage", "name": "D", "cage": "cage.off"},
                      {"op": "move", "lattice": "D", "points": [{"index": 6, "by": [1, 1.5, 0.5]}]}),
        "subdivide": steps({"op": "lattice", "name": "L", "basis": "octree", "levels": 2},
                           {"op": "subdivide", "lattice": "L", "level": 1, "cells": {"near": [0, 8, 0]}},
                           {"op": "move", "lattice": "L", "level": 3, "select": {"near": [0, 9, 0]},
                            "transform": {"translate": [0.3, 0.5, 0]}}),
        "transform_bernstein": steps(
            {"op": "lattice", "name": "B", "basis": "bernstein", "cells": [3, 3, 3]},
            {"op": "move", "lattice": "B", "points": [{"index": [1, 2, 1], "by": [0.5, 0.3, 0.1]}]}),
    }


FILE_SCRIPTS = ["demo.json", "bcm_bunny.json", "fig7_bunny.json", "seam/bunny_octree.json",
                "seam/bunny_bspline.json", "seam/bunny_bernstein.json"]


def script_cases(data, folder):
    (folder / "cage.off").write_text(CAGE_OFF)
    cases = {os.path.splitext(os.path.basename(f))[0]: json.load(open(os.path.join(data, f))) for f in FILE_SCRIPTS}
    cases.update(inline_scripts())
    return cases


def cli_run(run_cli, mesh, script, folder, name, threads):
    path = folder / (name + ".json")
    path.write_text(json.dumps(script))
    out = folder / "cli" / (name + ".obj")
    out.parent.mkdir(exist_ok=True)
    r = run_cli("run", mesh, path, "-o", out, "--stats", folder / (name + ".stats.json"),
                "--quiet", "--threads", threads)
    assert r.returncode == 0, r.stderr
    return out


def test_every_op_kind_gives_the_cli_vertices_bit_for_bit(bunny, data, tmp_path, run_cli, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the cage file is relative to the script (here: the current folder)
    for name, script in script_cases(data, tmp_path).items():
        cli_out = cli_run(run_cli, bunny, script, tmp_path, name, 2)
        py_folder = tmp_path / "py" / name
        py_folder.mkdir(parents=True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ffdtool.FfdWarning)
            mesh, stats = ffdtool.run(ffdtool.read(bunny), script, threads=2, save_folder=py_folder)
        assert np.array_equal(mesh.vertices, ffdtool.read(cli_out).vertices), name
        mesh.write(py_folder / "out.obj")
        assert filecmp.cmp(py_folder / "out.obj", cli_out, shallow=False), name
        for step in script["steps"]:  # what save steps wrote, the same bytes
            if step["op"] == "save":
                assert filecmp.cmp(py_folder / step["path"], cli_out.parent / step["path"], shallow=False), name
        cli_stats = json.load(open(tmp_path / (name + ".stats.json")))
        assert list(stats) == list(cli_stats), name
        assert [s["op"] for s in stats["steps"]] == [s["op"] for s in cli_stats["steps"]]
        assert [sorted(s) for s in stats["steps"]] == [sorted(s) for s in cli_stats["steps"]]
        assert stats["output"]["mesh"] is None and stats["warnings"] == cli_stats["warnings"]


def test_one_and_two_threads_give_the_same_bytes(bunny, data, tmp_path):
    script = json.load(open(os.path.join(data, "seam", "bunny_octree.json")))
    outputs = []
    for threads in (1, 2):
        folder = tmp_path / str(threads)
        folder.mkdir()
        mesh, stats = ffdtool.run(bunny, script, threads=threads, save_folder=folder)
        assert stats["threads"] == threads
        mesh.write(folder / "out.ply")
        outputs.append((folder / "out.ply").read_bytes())
    assert outputs[0] == outputs[1]


def test_the_input_mesh_is_left_as_it_was(bunny, data, tmp_path):
    mesh = ffdtool.read(bunny)
    before = mesh.vertices.copy()
    out, _ = ffdtool.run(mesh, os.path.join(data, "demo.json"), save_folder=tmp_path)
    assert (tmp_path / "bunny_stretched.obj").exists()
    assert np.array_equal(mesh.vertices, before)
    assert not np.array_equal(out.vertices, before)


def test_a_run_of_edited_vertices_starts_from_them(bunny):
    mesh = ffdtool.read(bunny)
    mesh.vertices[:] *= 2.0
    identity = steps({"op": "lattice", "name": "L", "cells": [4, 4, 4]})
    out, _ = ffdtool.run(mesh, identity)
    assert np.array_equal(out.vertices, mesh.vertices)
    again, _ = ffdtool.run(out, identity)  # a run's result fed to another run
    assert np.array_equal(again.vertices, mesh.vertices)


def test_errors_carry_the_cli_line_and_its_json_place(bunny, tmp_path):
    bad = steps({"op": "lattice", "name": "L", "cells": [4, 4, 4]},
                {"op": "move", "lattice": "L", "points": [{"index": [9, 0, 0], "by": [0, 0, 1]}]})
    with pytest.raises(ffdtool.InputError) as e:
        ffdtool.run(bunny, bad)
    assert e.value.place == "script: /steps/1/points/0/index"
    assert str(e.value) == e.value.place + ": " + e.value.message
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(bad))
    with pytest.raises(ffdtool.InputError) as e:
        ffdtool.run(bunny, path)
    assert e.value.place == str(path) + ": /steps/1/points/0/index"
    with pytest.raises(ffdtool.InputError, match="/steps/0/cells"):
        ffdtool.run(bunny, '{"version": 1, "steps": [{"op": "lattice", "name": "L", "cells": [4, 4]}]}')
    with pytest.raises(TypeError):
        ffdtool.run(bunny, 42)


def test_warnings_of_a_run_are_python_warnings(bunny):
    script = steps({"op": "lattice", "name": "B", "basis": "bernstein", "cells": [2, 2, 2],
                    "box": {"min": [-2, 2, -2], "max": [2, 6, 2]}},
                   {"op": "move", "lattice": "B", "points": [{"index": [0, 1, 1], "by": [0.5, 0, 0]}]})
    with pytest.warns(ffdtool.FfdWarning):
        _, stats = ffdtool.run(bunny, script)
    assert stats["warnings"]


@pytest.mark.parametrize("source,output", [("gltf/scene.glb", "out.glb"), ("gltf/scene_separate.gltf", "out.gltf"),
                                           ("gltf/scene_world.obj", "out.obj")])
def test_a_scene_with_normals_and_uvs_is_written_as_the_cli_writes_it(data, tmp_path, run_cli, source, output):
    """glTF nodes, materials and buffers, OBJ vn and vt: what the file carries, carried as
    the CLI carries it (normals through the warps' cofactors)."""
    script = steps({"op": "lattice", "name": "L", "cells": [4, 4, 4]},
                   {"op": "move", "lattice": "L", "points": [{"index": [2, 2, 2], "by": [0.2, 0.4, -0.1]}]},
                   {"op": "lattice", "name": "B", "basis": "bernstein", "cells": [2, 2, 2]},
                   {"op": "move", "lattice": "B", "points": [{"index": [1, 1, 1], "by": [0.1, 0, 0.1]}]})
    mesh = os.path.join(data, source)
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    path = tmp_path / "s.json"
    path.write_text(json.dumps(script))
    assert run_cli("run", mesh, path, "-o", tmp_path / "cli" / output, "--quiet").returncode == 0
    out, _ = ffdtool.run(ffdtool.read(mesh), script)
    out.write(tmp_path / "py" / output)
    cli_files = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert cli_files == sorted(p.name for p in (tmp_path / "py").iterdir())
    for name in cli_files:
        assert filecmp.cmp(tmp_path / "cli" / name, tmp_path / "py" / name, shallow=False), name
    if source.endswith(".obj"):
        read = ffdtool.read(mesh)
        assert read.uvs is not None and read.corner_uvs is not None and len(read.corner_uvs) == read.faces.size


@pytest.mark.parametrize("kind", ["bspline", "bernstein", "octree"])
def test_cgals_elephant_gives_the_cli_bytes(data, cgal_mesh, tmp_path, run_cli, kind):
    """The seam's elephant scripts (move, drag, control nets) on CGAL's elephant.off."""
    mesh = cgal_mesh("elephant.off")
    script_path = os.path.join(data, "seam", f"elephant_{kind}.json")
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    assert run_cli("run", mesh, script_path, "-o", tmp_path / "cli" / "out.off", "--quiet").returncode == 0
    out, _ = ffdtool.run(mesh, script_path, save_folder=tmp_path / "py")
    out.write(tmp_path / "py" / "out.off")
    names = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert names == sorted(p.name for p in (tmp_path / "py").iterdir()) and len(names) > 1
    for name in names:
        assert filecmp.cmp(tmp_path / "cli" / name, tmp_path / "py" / name, shallow=False), name
