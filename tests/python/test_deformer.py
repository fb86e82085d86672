"""Deformer objects: identity at rest, PyGeM's Bernstein formula, Jacobians and
sensitivities against finite differences, weights that reproduce the map, views of the
control points, no copies, threads, and the GIL released while they work."""
import math
import threading
import time
import tracemalloc

import numpy as np
import pytest

import ffdtool

BOX = {"min": [-1.0, -0.5, 0.0], "max": [2.0, 1.5, 1.0]}
CENTRES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1], [0.5, 0.5, 0.5]], dtype=float)


def random_points(n, seed=1):
    rng = np.random.default_rng(seed)
    lo, hi = np.array(BOX["min"]), np.array(BOX["max"])
    return lo + rng.random((n, 3)) * (hi - lo)


def cube_cage(path):
    path.write_text("OFF\n8 6 0\n-2 -2 -2\n3 -2 -2\n3 3 -2\n-2 3 -2\n-2 -2 3\n3 -2 3\n3 3 3\n-2 3 3\n"
                    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 3 0 4 7\n")
    return path


def a_movable_point(d):
    """The index scripts give one of d's movable points, from the middle of the list."""
    movable = np.flatnonzero(d.movable())
    id = int(movable[len(movable) // 2])
    index = d.indices()[id]
    return index.tolist() if index.ndim else int(index)


def point_id(d, index):
    if isinstance(index, int):
        return index
    return int(np.flatnonzero((d.indices() == index).all(axis=1))[0])


@pytest.fixture
def kinds(tmp_path, bunny):
    """One deformer of each kind, and a movable point of each (its index as scripts give it)."""
    mesh = ffdtool.read(bunny)
    made = {
        "bspline": ffdtool.BSplineLattice(None, cells=[4, 4, 4], box=BOX),
        "bernstein": ffdtool.BernsteinLattice(None, cells=[3, 2, 2], box=BOX),
        "octree": ffdtool.OctreeLattice(mesh, levels=2),
        "rbf": ffdtool.RBF(CENTRES, kernel="thin_plate_spline", radius=1.0),
        "idw": ffdtool.IDW(CENTRES, power=3),
        "cage": ffdtool.Cage(cube_cage(tmp_path / "cage.off")),
    }
    return {name: (d, a_movable_point(d)) for name, d in made.items()}


def points_for(d, bunny):
    if d.kind == "octree":
        return ffdtool.read(bunny).vertices[::7].copy()
    return random_points(500)


def test_an_unmoved_deformer_is_the_identity(kinds, bunny):
    for name, (d, _) in kinds.items():
        x = points_for(d, bunny)
        tol = 1e-12 * d.scale if name in ("bernstein", "rbf", "cage", "octree") else 0.0
        assert np.max(np.abs(d(x) - x)) <= tol, name


def pygem_bernstein(points, lattice, box_min, box_max):
    """PyGeM's FFD formula (pygem/ffd.py): box coordinates, then sum_ijk B_i B_j B_k P_ijk
    over the lattice as given by its (l+1) x (m+1) x (n+1) points."""
    degrees = np.array(lattice.shape[:3]) - 1
    u = (points - box_min) / (box_max - box_min)
    basis = []
    for a in range(3):
        n = degrees[a]
        i = np.arange(n + 1)
        binom = np.array([math.comb(n, k) for k in i], dtype=float)
        basis.append(binom * u[:, a, None] ** i * (1 - u[:, a, None]) ** (n - i))
    return np.einsum("pi,pj,pk,ijkc->pc", basis[0], basis[1], basis[2], lattice)


def test_bernstein_lattice_matches_pygems_formula():
    d = ffdtool.BernsteinLattice(None, cells=[3, 2, 4], box=BOX)
    rng = np.random.default_rng(7)
    index = d.indices()
    movable = np.flatnonzero(d.movable())
    for id in movable[:10]:
        d.move(index[id].tolist(), by=rng.normal(scale=0.2, size=3))
    lattice = np.zeros((4, 3, 5, 3))
    lattice[index[:, 0], index[:, 1], index[:, 2]] = d.points()
    x = random_points(2000, seed=3)
    expected = pygem_bernstein(x, lattice, np.array(BOX["min"]), np.array(BOX["max"]))
    assert np.max(np.abs(d(x) - expected)) <= 1e-12


def moved(kinds, rng):
    for name, (d, index) in kinds.items():
        d.move(index, by=rng.normal(scale=0.1, size=3) * d.scale)
    return kinds


def test_jacobians_match_central_differences(kinds, bunny):
    moved(kinds, np.random.default_rng(2))
    h = 1e-6
    for name, (d, _) in kinds.items():
        x = points_for(d, bunny)[:60]
        y, J = d(x, jacobians=True)
        assert J.shape == (len(x), 3, 3)
        assert np.array_equal(y, d(x))
        for c in range(3):
            e = np.zeros(3)
            e[c] = h * d.scale
            fd = (d(x + e) - d(x - e)) / (2 * e[c])
            assert np.max(np.abs(J[:, :, c] - fd)) <= 1e-5 * max(1.0, np.abs(J).max()), (name, c)


def test_weights_reproduce_the_map(kinds, bunny):
    rest = {name: d.points().copy() for name, (d, _) in kinds.items()}
    moved(kinds, np.random.default_rng(4))
    for name, (d, _) in kinds.items():
        x = points_for(d, bunny)
        W = d.weights(x)
        assert W.shape == (len(x), d.num_points())
        predicted = x + W @ (d.points() - rest[name])
        assert np.max(np.abs(d(x) - predicted)) <= 1e-10 * d.scale, name


def test_sensitivities_match_finite_differences_of_moves(kinds, bunny):
    for name, (d, index) in kinds.items():
        x = points_for(d, bunny)[:200]
        S = d.sensitivity(x)
        movable = np.flatnonzero(d.movable())
        assert S.shape == (3 * len(x), 3 * len(movable))
        column = int(np.flatnonzero(movable == point_id(d, index))[0])
        h = 1e-4 * d.scale
        for axis in range(3):
            step = np.zeros(3)
            step[axis] = h
            before = d(x)
            d.move(index, by=step)
            fd = (d(x) - before).reshape(-1) / h
            d.move(index, by=-step)
            assert np.max(np.abs(S[:, 3 * column + axis].toarray().ravel() - fd)) <= 1e-6, (name, axis)


def test_a_mesh_sensitivity_is_its_vertices_sensitivity(bunny):
    mesh = ffdtool.read(bunny)
    d = ffdtool.BSplineLattice(mesh, cells=[5, 5, 5])
    a, b = d.sensitivity(mesh), d.sensitivity(mesh.vertices)
    assert (a != b).nnz == 0 and a.nnz > 0


def test_points_is_a_view_that_moves_what_is_written(bunny):
    a = ffdtool.BSplineLattice(None, cells=[6, 6, 6], box=BOX)
    b = ffdtool.BSplineLattice(None, cells=[6, 6, 6], box=BOX)
    p = a.points()
    assert p.base is a and p.shape == (a.num_points(), 3)
    id = int(np.flatnonzero(a.movable())[5])
    index = a.indices()[id].tolist()
    p[id] += [0.1, -0.2, 0.3]
    b.move(index, by=[0.1, -0.2, 0.3])
    x = random_points(300)
    assert np.array_equal(a(x), b(x))
    assert np.array_equal(a.points(), b.points())
    fixed = int(np.flatnonzero(~a.movable())[0])
    before = p[fixed].copy()
    p[fixed] += 1.0
    with pytest.raises(ffdtool.InputError) as e:
        a(x)
    assert e.value.place == f"BSplineLattice.points(0)[{fixed}]" and "not movable" in e.value.message
    assert np.array_equal(p[fixed], before)


def test_writing_an_octree_level_moves_it_as_move_does(bunny):
    mesh = ffdtool.read(bunny)
    a, b = ffdtool.OctreeLattice(mesh, levels=2), ffdtool.OctreeLattice(mesh, levels=2)
    movable = np.flatnonzero(a.movable(level=1))
    id = int(movable[len(movable) // 2])
    level2 = a.points(level=2).copy()
    a.points(level=1)[id] += [0.2, 0.1, 0.0]
    b.move(a.indices(level=1)[id], by=[0.2, 0.1, 0.0], level=1)  # a numpy index
    x = mesh.vertices[::5]
    assert np.array_equal(a(x), b(x))
    assert np.array_equal(a.points(level=2), b.points(level=2))
    assert not np.array_equal(a.points(level=2), level2)  # the finer level follows the coarser one


def test_numpy_integers_name_points_as_python_ones_do():
    r = ffdtool.IDW(CENTRES)
    r.move(np.int64(2), to=[0.1, 0.2, 0.3])
    assert np.array_equal(r.points()[2], [0.1, 0.2, 0.3])
    r.move(np.array([0, 1]), by=[[0, 0, 0.1], [0, 0, 0.2]])
    assert np.array_equal(r.points()[:2, 2], CENTRES[:2, 2] + [0.1, 0.2])
    lattice = ffdtool.BSplineLattice(None, cells=[6, 6, 6], box=BOX)
    with pytest.raises(ffdtool.InputError) as e:
        lattice.move([[3, 3, 3], [3, 3]], by=[0, 0, 1])
    assert e.value.place == "BSplineLattice.move: index[1]"
    with pytest.raises(ffdtool.InputError) as e:
        r.move([1.5], by=[0, 0, 1])
    assert e.value.place == "IDW.move: index[0]"


def test_no_copy_of_c_contiguous_float64_points():
    d = ffdtool.BSplineLattice(None, cells=[6, 6, 6], box=BOX)
    d.move([3, 3, 3], by=[0.1, 0.1, 0.1])
    x = random_points(200_000)
    out_bytes = x.nbytes

    def peak_of(points):
        tracemalloc.start()
        d(points)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        return peak

    assert peak_of(x) < 1.2 * out_bytes  # only the result is allocated
    assert peak_of(np.asfortranarray(x)) > 1.8 * out_bytes  # a converted input shows as a copy


def test_out_takes_the_result_in_place():
    d = ffdtool.BSplineLattice(None, cells=[6, 6, 6], box=BOX)
    d.move([3, 3, 3], by=[0.1, 0.1, 0.1])
    x = random_points(1000)
    out = np.empty_like(x)
    result = d(x, out=out)
    assert result is out or np.shares_memory(result, out)
    assert np.array_equal(out, d(x))
    with pytest.raises(ffdtool.InputError, match="overlaps"):
        d(x, out=x)
    with pytest.raises(ffdtool.InputError, match="out must be"):
        d(x, out=np.empty((1000, 3), dtype=np.float32))


def test_one_and_two_threads_give_the_same_bytes(kinds, bunny):
    moved(kinds, np.random.default_rng(5))
    for name, (d, _) in kinds.items():
        x = points_for(d, bunny)
        one, j1 = d(x, jacobians=True, threads=1)
        two, j2 = d(x, jacobians=True, threads=2)
        assert one.tobytes() == two.tobytes() and j1.tobytes() == j2.tobytes(), name
        assert (d.weights(x, threads=1) != d.weights(x, threads=2)).nnz == 0


def test_deformer_errors_name_the_keyword():
    sphere = {"sphere": {"center": [0, 0, 0], "radius": 1}}
    with pytest.raises(ffdtool.InputError, match="not bcm") as e:
        ffdtool.Deformer("bcm", None, "Deformer", support=sphere, handles=[{"name": "h", "select": sphere}])
    tb = e.value.__traceback__
    while tb.tb_next:
        tb = tb.tb_next
    unmade = tb.tb_frame.f_locals["self"]  # what a traceback still reaches
    with pytest.raises(ffdtool.InputError, match="never made"):
        unmade.points()
    with pytest.raises(ffdtool.InputError, match="never made"):
        unmade(np.zeros((1, 3)))
    assert "never made" in repr(unmade)
    with pytest.raises(ffdtool.InputError) as e:
        ffdtool.BSplineLattice(None, cells=[2, 4, 4], box=BOX)
    assert e.value.place == "BSplineLattice: /cells/0"
    d = ffdtool.BSplineLattice(None, cells=[6, 6, 6], box=BOX)
    with pytest.raises(ffdtool.InputError) as e:
        d.move([[3, 3, 3], [0, 0, 0]], by=[0, 0, 1])
    assert e.value.place == "BSplineLattice.move: index[1]"
    with pytest.raises(ffdtool.InputError, match="level 3 does not exist"):
        d.points(level=3)
    with pytest.raises(ffdtool.InputError, match="expected an \\(n, 3\\) array"):
        d(np.zeros((5, 2)))


def test_drag_takes_object_points_to_their_targets():
    d = ffdtool.BSplineLattice(None, cells=[5, 5, 5], box=BOX)
    at = np.array([[0.5, 0.5, 0.5], [1.0, 0.2, 0.4]])
    to = at + [[0.05, 0.0, 0.02], [-0.03, 0.04, 0.0]]
    result = d.drag(at, to)
    assert result["max_residual"] < 1e-12 and result["points_changed"] > 0
    assert np.max(np.abs(d(at) - to)) < 1e-12


def counting_during(call):
    """How far a second Python thread counts while `call` runs, against while sleeping as long."""
    count, done = [0], [False]

    def counter():
        while not done[0]:
            count[0] += 1

    worker = threading.Thread(target=counter)
    worker.start()
    time.sleep(0.05)
    start, t0 = count[0], time.perf_counter()
    call()
    during, seconds = count[0] - start, time.perf_counter() - t0
    start = count[0]
    time.sleep(seconds)
    idle = count[0] - start
    done[0] = True
    worker.join()
    return during, idle, seconds


def test_the_gil_is_released_while_a_kernel_runs():
    d = ffdtool.IDW(random_points(200, seed=9), power=2)
    d.move(3, by=[0.1, 0, 0])
    x = random_points(400_000)
    during, idle, seconds = counting_during(lambda: d(x, jacobians=True, threads=1))
    assert seconds > 0.1, "the kernel is too short to tell"
    assert during > 0.25 * idle, (during, idle)
