"""Blender side-by-side peer for `ffdbench --suite io`.

Run as:

    blender -b --factory-startup -noaudio -t 1 --python-exit-code 2 \
        -P apps/ffdbench/blender_peer.py -- MODE ARGS...

Modes:

    job IN OUT CELLS_X CELLS_Y CELLS_Z I J K DX DY DZ
        Import IN, fit a B-spline lattice to the mesh, move one lattice point,
        evaluate the Lattice modifier and export OUT -- what a Blender user would
        do to reproduce `ffdtool run`. Each phase is timed.

    kernel IN REPEATS CELLS I J K DX DY DZ
        The Lattice modifier alone: median over REPEATS of a baseline evaluation
        (modifier disabled) and of an evaluation with the modifier enabled, each
        followed by a bulk read of the evaluated positions and vertex normals.

Prints exactly one line `FFDBENCH_JSON {...}` on stdout (Blender prints its own
noise there too; the caller greps for the prefix). On any error prints one line
to stderr and exits with code 2.
"""

import array
import json
import os
import statistics
import sys
import time

import bpy
from mathutils import Vector

JSON_PREFIX = "FFDBENCH_JSON "
ERROR_EXIT = 2
PADDING = 0.05  # box padding on each side, as a fraction of the axis' extent


class PeerError(Exception):
    """An error to report on one stderr line (bad arguments, unsupported format...)."""


# ----------------------------------------------------------------------------
# Scene and file I/O
# ----------------------------------------------------------------------------

def clear_scene():
    """Remove every object (the factory cube, camera and light) and orphan data."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.cameras, bpy.data.lights, bpy.data.materials):
        for block in list(coll):
            coll.remove(block)


def file_ext(path):
    """Lower-case extension of `path` without the dot."""
    return os.path.splitext(path)[1].lower().lstrip(".")


def import_mesh(path):
    """Import `path` by extension and return the single mesh object it created.

    OBJ uses forward=Y, up=Z (no axis conversion) so Blender world space equals the
    file's coordinates, as in ffdtool; the PLY and STL importers already default to
    that. Several imported objects are joined into one.
    """
    if not os.path.isfile(path):
        raise PeerError(f"input file not found: {path}")
    ext = file_ext(path)
    if ext == "obj":
        bpy.ops.wm.obj_import(filepath=path, forward_axis="Y", up_axis="Z")
    elif ext == "ply":
        bpy.ops.import_mesh.ply(filepath=path)
    elif ext == "stl":
        bpy.ops.import_mesh.stl(filepath=path)
    elif ext == "off":
        raise PeerError(f"Blender cannot import OFF files: {path}")
    else:
        raise PeerError(f"unsupported input format '.{ext}': {path}")
    meshes = [ob for ob in bpy.context.scene.objects if ob.type == "MESH"]
    if not meshes:
        raise PeerError(f"no mesh was imported from {path}")
    if len(meshes) > 1:
        join_objects(meshes)
    return meshes[0]


def join_objects(objects):
    """Join `objects` into objects[0] (OBJ files with several `o` groups)."""
    with bpy.context.temp_override(active_object=objects[0], selected_objects=objects,
                                   selected_editable_objects=objects):
        bpy.ops.object.join()


def select_only(ob):
    """Make `ob` the only selected object and the active one."""
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
    ob.select_set(True)
    bpy.context.view_layer.objects.active = ob


def export_mesh(ob, path):
    """Export only `ob` to `path` by extension, modifiers applied, no normals/UVs/materials."""
    select_only(ob)
    ext = file_ext(path)
    if ext == "obj":
        bpy.ops.wm.obj_export(filepath=path, forward_axis="Y", up_axis="Z",
                              apply_modifiers=True, export_selected_objects=True,
                              export_normals=False, export_uv=False,
                              export_materials=False, export_colors=False)
    elif ext == "ply":
        bpy.ops.export_mesh.ply(filepath=path, use_selection=True, use_mesh_modifiers=True,
                                use_normals=False, use_uv_coords=False, use_colors=False)
    elif ext == "stl":
        bpy.ops.export_mesh.stl(filepath=path, use_selection=True, use_mesh_modifiers=True,
                                ascii=False)
    elif ext == "off":
        raise PeerError(f"Blender cannot export OFF files: {path}")
    else:
        raise PeerError(f"unsupported output format '.{ext}': {path}")


# ----------------------------------------------------------------------------
# Lattice
# ----------------------------------------------------------------------------

def world_bbox(ob):
    """Axis-aligned world bounding box (lo, hi) of mesh object `ob`'s vertices."""
    n = len(ob.data.vertices)
    if n == 0:
        raise PeerError("the imported mesh has no vertices")
    co = array.array("f", bytes(4 * 3 * n))
    ob.data.vertices.foreach_get("co", co)
    m = ob.matrix_world
    if m != m.Identity(4):
        # Importers normally leave the object at identity; transform otherwise (slow path).
        pts = [m @ Vector(co[3 * i:3 * i + 3]) for i in range(n)]
        co = [x for p in pts for x in p]
    lo = [min(co[a::3]) for a in range(3)]
    hi = [max(co[a::3]) for a in range(3)]
    return lo, hi


def padded_box(lo, hi):
    """Centre and size of the bbox padded by PADDING x each axis' extent on each side.

    A flat axis (zero extent) is padded by PADDING x the largest extent instead.
    """
    extent = [h - l for l, h in zip(lo, hi)]
    largest = max(extent)
    if largest <= 0:
        raise PeerError("the mesh is a single point; cannot fit a lattice box")
    centre = [0.5 * (l + h) for l, h in zip(lo, hi)]
    size = [e + 2 * PADDING * (e if e > 0 else largest) for e in extent]
    return centre, size


def add_lattice(centre, size, cells):
    """Add a cubic B-spline Lattice object spanning the box (centre, size).

    Blender lattice mapping: a lattice with n points per axis has its points evenly
    spaced over -0.5..0.5 in local space, so the object's location is the box centre
    and its scale the box size. With 'KEY_BSPLINE' Blender evaluates a uniform cubic
    B-spline whose control points sit at those n grid positions, touching 4 points
    per axis (64 per vertex) and repeating the edge points past the ends. We use
    n = CELLS + 3 points, the control-point count of ffdtool's cubic B-spline lattice
    with CELLS cells, so both do the same amount of work per vertex. Blender numbers
    the points from 0 and ffdtool's cubic lattice from -1, so ffdtool's point i is
    Blender's i + 1 (the caller passes Blender's index). The results still differ:
    Blender spreads the points edge to edge, box / (CELLS + 2) apart, where ffdtool's
    nodes are box / CELLS apart with the outer layers outside the box.
    """
    lat = bpy.data.lattices.new("ffd_lattice")
    # The object must exist before the resize: resizing a lattice that no object uses
    # lays its points out on an integer grid (-(n-1)/2 .. (n-1)/2) instead of -0.5..0.5.
    ob = bpy.data.objects.new("ffd_lattice", lat)
    bpy.context.scene.collection.objects.link(ob)
    lat.points_u, lat.points_v, lat.points_w = (c + 3 for c in cells)
    lat.interpolation_type_u = "KEY_BSPLINE"
    lat.interpolation_type_v = "KEY_BSPLINE"
    lat.interpolation_type_w = "KEY_BSPLINE"
    lat.use_outside = False
    first, last = lat.points[0].co, lat.points[-1].co
    if any(abs(a + 0.5) > 1e-6 or abs(b - 0.5) > 1e-6 for a, b in zip(first, last)):
        raise PeerError(f"unexpected lattice point span {tuple(first)} .. {tuple(last)}")
    ob.location = centre
    ob.scale = size
    return ob


def move_lattice_point(lat_ob, ijk, delta):
    """Move lattice point (i, j, k) by the world-space vector `delta` (u index fastest)."""
    lat = lat_ob.data
    pu, pv, pw = lat.points_u, lat.points_v, lat.points_w
    i, j, k = ijk
    if not (0 <= i < pu and 0 <= j < pv and 0 <= k < pw):
        raise PeerError(f"lattice point ({i},{j},{k}) is outside the {pu}x{pv}x{pw} grid")
    point = lat.points[i + j * pu + k * pu * pv]
    scale = lat_ob.scale  # no rotation: world -> local is a per-axis division
    point.co_deform = [c + d / s for c, d, s in zip(point.co, delta, scale)]


def setup_ffd(mesh_ob, cells, ijk, delta):
    """Fit the lattice to `mesh_ob`, move one point and add the Lattice modifier."""
    centre, size = padded_box(*world_bbox(mesh_ob))
    lat_ob = add_lattice(centre, size, cells)
    move_lattice_point(lat_ob, ijk, delta)
    mod = mesh_ob.modifiers.new("ffd", "LATTICE")
    mod.object = lat_ob
    return lat_ob, mod


# ----------------------------------------------------------------------------
# Evaluation
# ----------------------------------------------------------------------------

def evaluate(ob):
    """Evaluate the depsgraph and return `ob`'s evaluated object."""
    bpy.context.view_layer.update()
    dg = bpy.context.evaluated_depsgraph_get()
    return ob.evaluated_get(dg)


def read_geometry(ob_eval, co_buf, nor_buf):
    """Bulk-read evaluated positions and vertex normals (forcing normal computation)."""
    mesh = ob_eval.data
    mesh.vertices.foreach_get("co", co_buf)
    mesh.vertex_normals.foreach_get("vector", nor_buf)


def ms_since(t0):
    """Milliseconds elapsed since perf_counter value `t0`."""
    return (time.perf_counter() - t0) * 1e3


# ----------------------------------------------------------------------------
# Modes
# ----------------------------------------------------------------------------

def run_job(args):
    """Mode `job`: import, lattice modifier, export; returns the JSON dict."""
    if len(args) != 11:
        raise PeerError("usage: job IN OUT CELLS_X CELLS_Y CELLS_Z I J K DX DY DZ")
    src, dst = args[0], args[1]
    cells = parse_ints(args[2:5], minimum=1)
    ijk = parse_ints(args[5:8], minimum=0)
    delta = parse_floats(args[8:11])
    if file_ext(dst) not in ("obj", "ply", "stl"):
        raise PeerError(f"unsupported output format '.{file_ext(dst)}': {dst}")
    clear_scene()

    t_start = time.perf_counter()
    ob = import_mesh(src)
    import_ms = ms_since(t_start)

    t0 = time.perf_counter()
    setup_ffd(ob, cells, ijk, delta)
    setup_ms = ms_since(t0)

    t0 = time.perf_counter()
    ob_eval = evaluate(ob)
    vertices = len(ob_eval.data.vertices)
    faces = len(ob_eval.data.polygons)
    modifier_ms = ms_since(t0)

    t0 = time.perf_counter()
    export_mesh(ob, dst)
    export_ms = ms_since(t0)
    total_ms = ms_since(t_start)

    return {"mode": "job", "blender": bpy.app.version_string, "vertices": vertices,
            "faces": faces, "import_ms": import_ms, "setup_ms": setup_ms,
            "modifier_ms": modifier_ms, "export_ms": export_ms, "total_ms": total_ms}


def timed_eval(ob, mod, enabled, co_buf, nor_buf):
    """Time one forced re-evaluation of `ob` with the modifier on/off, plus the bulk read."""
    mod.show_viewport = enabled
    ob.update_tag()  # geometry must be recomputed, not served from the depsgraph cache
    t0 = time.perf_counter()
    read_geometry(evaluate(ob), co_buf, nor_buf)
    return ms_since(t0)


def run_kernel(args):
    """Mode `kernel`: median baseline vs lattice-modifier evaluation; returns the JSON dict."""
    if len(args) != 9:
        raise PeerError("usage: kernel IN REPEATS CELLS I J K DX DY DZ")
    src = args[0]
    repeats, cells = parse_ints(args[1:3], minimum=1)
    ijk = parse_ints(args[3:6], minimum=0)
    delta = parse_floats(args[6:9])
    clear_scene()
    ob = import_mesh(src)
    _, mod = setup_ffd(ob, (cells,) * 3, ijk, delta)

    n = len(ob.data.vertices)
    co_buf = array.array("f", bytes(4 * 3 * n))
    nor_buf = array.array("f", bytes(4 * 3 * n))
    timed_eval(ob, mod, True, co_buf, nor_buf)  # warm-up: first evaluation builds the depsgraph
    baseline, lattice = [], []
    for _ in range(repeats):  # interleaved so drift affects both alike
        baseline.append(timed_eval(ob, mod, False, co_buf, nor_buf))
        lattice.append(timed_eval(ob, mod, True, co_buf, nor_buf))
    base_ms = statistics.median(baseline)
    lat_ms = statistics.median(lattice)
    return {"mode": "kernel", "blender": bpy.app.version_string, "vertices": n,
            "repeats": repeats, "baseline_ms": base_ms, "lattice_ms": lat_ms,
            "modifier_ms": lat_ms - base_ms}


# ----------------------------------------------------------------------------
# Command line
# ----------------------------------------------------------------------------

def parse_ints(values, minimum):
    """Parse integer arguments, each >= `minimum`."""
    try:
        out = [int(v) for v in values]
    except ValueError as e:
        raise PeerError(f"expected integers, got {' '.join(values)}") from e
    if any(v < minimum for v in out):
        raise PeerError(f"expected integers >= {minimum}, got {' '.join(values)}")
    return out


def parse_floats(values):
    """Parse float arguments."""
    try:
        return [float(v) for v in values]
    except ValueError as e:
        raise PeerError(f"expected numbers, got {' '.join(values)}") from e


def script_args():
    """Arguments after Blender's `--` separator."""
    argv = sys.argv
    return argv[argv.index("--") + 1:] if "--" in argv else []


def main():
    """Dispatch on MODE, print the JSON line, exit 2 on any error."""
    args = script_args()
    modes = {"job": run_job, "kernel": run_kernel}
    try:
        if not args or args[0] not in modes:
            raise PeerError("usage: blender_peer.py -- {job|kernel} ARGS...")
        result = modes[args[0]](args[1:])
    except Exception as e:  # noqa: BLE001 -- any failure must become exit code 2
        msg = str(e).strip().replace("\n", " ") or type(e).__name__
        print(f"blender_peer: error: {msg}", file=sys.stderr, flush=True)
        sys.exit(ERROR_EXIT)
    print(JSON_PREFIX + json.dumps(result), flush=True)


main()
