"""Blender side of bench/peers/run.sh (Blender 3.4, Cycles on the CPU).

  blender -b --factory-startup -P blender_bake.py -- MODE IO MESH.ply TEXTURE X,Y,Z OUT [SIZE]

MODE vertex: the Earth map projected from a sphere centred at X,Y,Z (pole +z,
u = 0 towards +x: SPEC section 2) baked with Cycles EMIT, 1 sample, into a
colour attribute, written as a binary PLY. MODE atlas: Smart UV Project
(Blender's defaults: 66 degree angle limit, no island margin), then the same
material baked into a SIZE x SIZE image (margin 8 texels, texbake's default
padding at 2048) saved as PNG.

IO addon: the mesh is read and written by Blender 3.4's own PLY add-on
(import_mesh.ply / export_mesh.ply), what a Blender user runs; it is pure
Python (about 10 s to read the 832k-triangle mesh, 5 s to write it) and
writes only a per-corner byte colour layer, so the vertex bake goes to one
(BYTE_COLOR, CORNER) and the export splits vertices whose corners differ.
IO numpy: the mesh is read and written with numpy through foreach_set /
foreach_get and the vertex bake goes to a per-vertex float attribute
(FLOAT_COLOR, POINT; written as sRGB bytes): Blender's baking without its
slow add-on, the fastest Blender can do this job.

The material: Texture Coordinate (Object) -> Mapping (point: rotate -90
degrees about z, move the sphere centre to (0.5, 0.5, 0.5)) -> Image Texture
(Sphere projection, linear interpolation, repeat) -> Emission -> Output.
Cycles' sphere projection takes the vector in the unit cube centred at 0.5
(texco_remap_square) and gives u = (1 - atan2(x, y) / pi) / 2, v = 1 -
acos(z / |p|) / pi: the same v as texbake's sphere, and u 0.25 ahead, which
the -90 degree turn takes back.
"""
import math
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peers_util  # noqa: E402 (beside this script)


def log(msg, t0=[time.time()]):
    print(f"blender_bake: {time.time() - t0[0]:7.2f} s {msg}", flush=True)


def linear_to_srgb(c):
    c = np.clip(c, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def make_object(v, t):
    mesh = bpy.data.meshes.new("mesh")
    mesh.vertices.add(len(v))
    mesh.vertices.foreach_set("co", v.ravel())
    mesh.loops.add(3 * len(t))
    mesh.loops.foreach_set("vertex_index", t.ravel())
    mesh.polygons.add(len(t))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * len(t), 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(t), 3, dtype=np.int32))
    mesh.update()
    obj = bpy.data.objects.new("mesh", mesh)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    return obj


def make_material(obj, texture, center):
    mat = bpy.data.materials.new("projection")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    coord = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    mapping.vector_type = "POINT"
    # out = R (p) + L with R = -90 degrees about z ((x, y) -> (y, -x)) and
    # L = (0.5, 0.5, 0.5) - R c.
    cx, cy, cz = center
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, -math.pi / 2)
    mapping.inputs["Location"].default_value = (0.5 - cy, 0.5 + cx, 0.5 - cz)
    image = nodes.new("ShaderNodeTexImage")
    image.image = bpy.data.images.load(texture)
    image.projection = "SPHERE"
    image.interpolation = "Linear"
    image.extension = "REPEAT"
    emit = nodes.new("ShaderNodeEmission")
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(coord.outputs["Object"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], image.inputs["Vector"])
    links.new(image.outputs["Color"], emit.inputs["Color"])
    links.new(emit.outputs["Emission"], out.inputs["Surface"])
    obj.data.materials.append(mat)
    return mat


def setup_cycles():
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    return scene


def main(argv):
    mode, io, mesh_path, texture, center, out = argv[:6]
    center = [float(x) for x in center.split(",")]
    if io not in ("addon", "numpy"):
        sys.exit(f"blender_bake.py: IO is addon or numpy, not {io}")
    for o in list(bpy.data.objects):  # the factory scene's cube, camera, light
        bpy.data.objects.remove(o)
    if io == "addon":
        bpy.ops.import_mesh.ply(filepath=mesh_path)
        obj = bpy.context.selected_objects[0]
        bpy.context.view_layer.objects.active = obj
    else:
        vert, t = peers_util.read_ply(mesh_path)
        if t is None:
            sys.exit(f"{mesh_path}: not all faces are uchar-int triangles")
        v = np.stack([vert["x"], vert["y"], vert["z"]], 1)
        obj = make_object(v, t)
    mat = make_material(obj, texture, center)
    scene = setup_cycles()
    log(f"scene of {len(obj.data.vertices)} vertices, {len(obj.data.polygons)} triangles")
    if mode == "vertex":
        if io == "addon":
            attr = obj.data.color_attributes.new("baked", "BYTE_COLOR", "CORNER")
        else:
            attr = obj.data.color_attributes.new("baked", "FLOAT_COLOR", "POINT")
        obj.data.color_attributes.active_color = attr
        bpy.ops.object.bake(type="EMIT", target="VERTEX_COLORS")
        log("baked")
        if io == "addon":
            bpy.ops.export_mesh.ply(filepath=out, use_selection=True, use_normals=False,
                                    use_uv_coords=False, use_colors=True)
        else:
            rgba = np.empty(4 * len(v), dtype=np.float32)
            attr.data.foreach_get("color", rgba)
            rgb = np.rint(linear_to_srgb(rgba.reshape(-1, 4)[:, :3]) * 255).astype(np.uint8)
            peers_util.write_ply(out, v, t, rgb)
    elif mode == "atlas":
        size = int(argv[6]) if len(argv) > 6 else 2048
        # The square bake target is the active image node before the UV
        # projection: Smart UV Project corrects the charts for the aspect of
        # the active image (the 2:1 Earth map would squeeze them in u).
        img = bpy.data.images.new("atlas", size, size)
        target = mat.node_tree.nodes.new("ShaderNodeTexImage")
        target.image = img
        mat.node_tree.nodes.active = target
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")
        bpy.ops.uv.smart_project()
        bpy.ops.object.mode_set(mode="OBJECT")
        log("smart UV project")
        scene.render.bake.margin = 8
        bpy.ops.object.bake(type="EMIT", target="IMAGE_TEXTURES")
        log("baked")
        img.filepath_raw = out
        img.file_format = "PNG"
        img.save()
    else:
        sys.exit(f"blender_bake.py: unknown mode {mode}")
    log(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:])
