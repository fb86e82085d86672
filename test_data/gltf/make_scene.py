"""Build the ffdtool glTF test scene in Blender and export it.

Made with Blender 3.4.1 (Debian package, /usr/bin/blender, bundled glTF add-on
"Khronos glTF Blender I/O" 3.4.50).  Regenerate every file in this folder, from
the repository root, with

    blender -b --factory-startup --python-exit-code 1 \
        --python test_data/gltf/make_scene.py

(an output folder other than this script's folder can be given after "--":
``... --python test_data/gltf/make_scene.py -- /tmp/out``).

The scene, built from scratch after deleting the factory-startup objects:

  Root   Empty; location (0.5, -1.0, 0.25), Euler XYZ (0.3, 0.5, 0.2),
         scale (1.5, 1.0, 0.75)
    Body   UV sphere (24 segments, 12 rings, radius 1), smooth shaded, UV map
           "UVMap", material "BodyMat" whose Base Color is an image texture
           of the packed 8x8 checker PNG "checker" (made here, not read from
           disk); location (1.0, 0.5, -0.25), Euler (0.4, -0.2, 0.7)
      Nose   cube (size 0.4), material "NoseMat" (plain colour), custom
             property ffd_tag = "nose" (exported as node extras);
             location (0, -1.1, 0.1), Euler (0.1, 0.2, 0.3),
             scale (1.0, 0.6, 1.4)
    Body2  linked duplicate of Body: the same mesh datablock "BodyMesh"
           (so the glTF has one mesh used by two nodes);
           location (-1.5, 0.3, 0.4), Euler (-0.5, 0.1, 1.2), scale 0.8

Parents are set without a parent-inverse matrix, so each object's local
transform is exactly the location/rotation/scale given above.

Outputs:
  scene.glb             glTF binary, extras on, +Y up, texture embedded
  scene_separate.gltf   same scene as GLTF_SEPARATE, with
  scene_separate.bin    ... its buffer and
  checker.png           ... its texture image
  scene_world.obj       world-space OBJ (Blender 3.4's C++ exporter), same
                        axes as the glTF (forward -Z, up +Y), normals, UVs,
                        triangulated, no .mtl

Nothing random is involved: all geometry comes from primitive operators with
fixed parameters and the texture from a fixed formula.  One thing is not
repeatable by itself in Blender 3.4: the order of the UV sphere's faces
(see canonical_mesh), so both meshes are rebuilt in a canonical order and
re-running gives byte-identical files.

Needs numpy for Blender's Python (the glTF add-on imports it): on Debian,
apt-get install python3-numpy.  The add-on logs an ERROR that the Draco
library is missing; that is harmless (Draco compression is off here).
"""

import os
import random
import sys

import bpy

random.seed(0)  # nothing below uses randomness; fixed anyway

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
OUT = os.path.abspath(argv[0]) if argv else os.path.dirname(os.path.abspath(__file__))
os.makedirs(OUT, exist_ok=True)

# --- empty the factory-startup scene (Cube, Light, Camera) and its data ---
for ob in list(bpy.data.objects):
    bpy.data.objects.remove(ob, do_unlink=True)
for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras,
             bpy.data.lights, bpy.data.images, bpy.data.textures):
    for block in list(coll):
        coll.remove(block)

scene = bpy.context.scene
scene.frame_set(1)
collection = scene.collection


def canonical_mesh(ob, name):
    """Replace ob's mesh by a copy with a canonical element order.

    Blender 3.4's primitive_uv_sphere_add welds its spun rings through a
    pointer-keyed hash, so the order of the faces it makes (and so the order
    of the exporters' vertices, the vertex-normal sums and the OBJ normal
    list) changes from run to run.  Here each face's corner list is rotated
    to start at its smallest vertex index (winding kept, UVs rotated with it)
    and the faces are sorted by their sorted vertex indices, then the mesh is
    rebuilt with from_pydata; vertex order is kept (it is already stable).
    """
    old = ob.data
    verts = [tuple(v.co) for v in old.vertices]
    uvdata = old.uv_layers[0].data
    faces = []
    for poly in old.polygons:
        vs = list(poly.vertices)
        uvs = [tuple(uvdata[li].uv) for li in poly.loop_indices]
        k = vs.index(min(vs))
        faces.append((vs[k:] + vs[:k], uvs[k:] + uvs[:k]))
    faces.sort(key=lambda f: sorted(f[0]))
    new = bpy.data.meshes.new(name + "_tmp")
    new.from_pydata(verts, [], [f[0] for f in faces])
    layer = new.uv_layers.new(name="UVMap")
    i = 0
    for _, uvs in faces:
        for uv in uvs:
            layer.data[i].uv = uv
            i += 1
    new.validate()
    new.update()
    ob.data = new
    bpy.data.meshes.remove(old)
    new.name = name
    return new


def make_active(ob):
    bpy.ops.object.select_all(action='DESELECT')
    ob.select_set(True)
    bpy.context.view_layer.objects.active = ob


# --- Root: an empty with a non-trivial transform ---
root = bpy.data.objects.new("Root", None)
root.empty_display_type = 'PLAIN_AXES'
collection.objects.link(root)
root.location = (0.5, -1.0, 0.25)
root.rotation_mode = 'XYZ'
root.rotation_euler = (0.3, 0.5, 0.2)
root.scale = (1.5, 1.0, 0.75)

# --- the checker texture: 8x8 RGBA, 2x2-pixel cells, packed as PNG ---
img = bpy.data.images.new("checker", width=8, height=8, alpha=False)
pixels = []
for y in range(8):
    for x in range(8):
        if ((x // 2) + (y // 2)) % 2 == 0:
            pixels += [0.9, 0.2, 0.1, 1.0]
        else:
            pixels += [0.1, 0.3, 0.9, 1.0]
img.pixels[:] = pixels
img.file_format = 'PNG'
img.pack()  # generated image -> packed PNG, so it travels inside the .blend/GLB

# --- BodyMat: Principled BSDF with the checker on Base Color ---
body_mat = bpy.data.materials.new("BodyMat")
body_mat.use_nodes = True
nt = body_mat.node_tree
bsdf = nt.nodes["Principled BSDF"]
bsdf.inputs["Roughness"].default_value = 0.6
bsdf.inputs["Metallic"].default_value = 0.0
tex = nt.nodes.new("ShaderNodeTexImage")
tex.image = img
tex.interpolation = 'Closest'
tex.location = (-300, 300)
uvnode = nt.nodes.new("ShaderNodeUVMap")
uvnode.uv_map = "UVMap"
uvnode.location = (-500, 300)
nt.links.new(uvnode.outputs["UV"], tex.inputs["Vector"])
nt.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])

# --- NoseMat: plain colour ---
nose_mat = bpy.data.materials.new("NoseMat")
nose_mat.use_nodes = True
nbsdf = nose_mat.node_tree.nodes["Principled BSDF"]
nbsdf.inputs["Base Color"].default_value = (0.8, 0.6, 0.1, 1.0)
nbsdf.inputs["Roughness"].default_value = 0.4
nbsdf.inputs["Metallic"].default_value = 0.2
nose_mat.diffuse_color = (0.8, 0.6, 0.1, 1.0)

# --- Body: UV sphere, smooth shaded ---
bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=1.0,
                                     calc_uvs=True, location=(0, 0, 0))
body = bpy.context.active_object
body.name = "Body"
canonical_mesh(body, "BodyMesh")
bpy.ops.object.shade_smooth()
body.data.materials.append(body_mat)
body.parent = root
body.matrix_parent_inverse.identity()
body.location = (1.0, 0.5, -0.25)
body.rotation_mode = 'XYZ'
body.rotation_euler = (0.4, -0.2, 0.7)
body.scale = (1.0, 1.0, 1.0)

# --- Nose: cube, child of Body ---
bpy.ops.mesh.primitive_cube_add(size=0.4, calc_uvs=True, location=(0, 0, 0))
nose = bpy.context.active_object
nose.name = "Nose"
canonical_mesh(nose, "NoseMesh")
nose.data.materials.append(nose_mat)
nose.parent = body
nose.matrix_parent_inverse.identity()
nose.location = (0.0, -1.1, 0.1)
nose.rotation_mode = 'XYZ'
nose.rotation_euler = (0.1, 0.2, 0.3)
nose.scale = (1.0, 0.6, 1.4)
nose["ffd_tag"] = "nose"

# --- Body2: linked duplicate (same mesh datablock) under Root ---
body2 = bpy.data.objects.new("Body2", body.data)
collection.objects.link(body2)
body2.parent = root
body2.matrix_parent_inverse.identity()
body2.location = (-1.5, 0.3, 0.4)
body2.rotation_mode = 'XYZ'
body2.rotation_euler = (-0.5, 0.1, 1.2)
body2.scale = (0.8, 0.8, 0.8)
assert body2.data is body.data

bpy.context.view_layer.update()
make_active(root)

nverts = sum(len(o.data.vertices) for o in (body, nose, body2))
print("ffd make_scene: Blender vertices (Body, Nose, Body2):",
      len(body.data.vertices), len(nose.data.vertices), len(body2.data.vertices),
      "total", nverts)

# --- exports ---
common = dict(
    export_extras=True,
    export_yup=True,
    export_apply=True,
    export_normals=True,
    export_texcoords=True,
    export_tangents=False,
    export_materials='EXPORT',
    export_colors=False,
    export_attributes=False,
    export_cameras=False,
    export_lights=False,
    export_animations=False,
    export_skins=False,
    export_morph=False,
    export_image_format='AUTO',
    export_draco_mesh_compression_enable=False,
    use_selection=False,
    use_visible=False,
    use_renderable=False,
    use_active_collection=False,
    will_save_settings=False,
)
bpy.ops.export_scene.gltf(filepath=os.path.join(OUT, "scene.glb"),
                          export_format='GLB', **common)
bpy.ops.export_scene.gltf(filepath=os.path.join(OUT, "scene_separate.gltf"),
                          export_format='GLTF_SEPARATE', export_texture_dir="",
                          **common)
bpy.ops.wm.obj_export(filepath=os.path.join(OUT, "scene_world.obj"),
                      export_animation=False,
                      forward_axis='NEGATIVE_Z', up_axis='Y',
                      global_scale=1.0,
                      apply_modifiers=True,
                      export_eval_mode='DAG_EVAL_VIEWPORT',
                      export_selected_objects=False,
                      export_uv=True, export_normals=True, export_colors=False,
                      export_materials=False,
                      export_triangulated_mesh=True,
                      export_curves_as_nurbs=False,
                      export_object_groups=False,
                      export_material_groups=False,
                      export_vertex_groups=False,
                      export_smooth_groups=False)
print("ffd make_scene: wrote", sorted(os.listdir(OUT)))
