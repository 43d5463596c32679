"""Builds a motion-blurred scene from nothing and renders it with Cycles on CPU.

    blender -b --factory-startup --python-exit-code 1 --python scene.py -- \\
        OUT.png [--seed N] [--samples N] [--size WxH] [--threads N] [--no-motion-blur]

Everything Cycles hands to Embree for triangle scenes is in it:
- a static ground and back wall (plain triangle meshes, transform applied);
- a cube moving sideways and a sphere spinning (object motion blur: Cycles
  makes each an Embree instance with one quaternion decomposition per time
  step; the sphere uses 5 steps, the cube 3); the sphere has subsurface
  scattering, whose local rays Cycles traces directly in the instanced scene;
- a torus whose shape key is animated across the shutter (deformation blur:
  a triangle geometry with 3 vertex time steps);
- a collection with a mesh shown four times through collection instances,
  one of them moving, and with a partly transparent material (transparent
  shadows: Cycles records every shadow hit in an occlusion filter);
- a sun and an area light, a grey world. No hair, no point clouds.

Writes OUT.png (8-bit, to look at), OUT.exr's pixels as OUT.npy (float32
linear RGBA, top row first) for comparing, and prints the libembree3 file
this Blender process mapped and the render time.
"""

import argparse
import math
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from mapped_library import mapped_embree  # noqa: E402


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="scene.py", description="Cycles motion-blur scene")
    parser.add_argument("out", help="output .png (OUT.npy is written beside it)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--samples", type=int, default=32)
    parser.add_argument("--size", default="200x150")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--no-motion-blur", action="store_true")
    return parser.parse_args(argv)


def material(name, color, transparent=0.0, subsurface=0.0, metallic=0.0, roughness=0.5,
             checker=False):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    if checker:  # makes the rotation visible
        tex = nodes.new("ShaderNodeTexChecker")
        tex.inputs["Scale"].default_value = 6.0
        tex.inputs["Color1"].default_value = (*color, 1.0)
        tex.inputs["Color2"].default_value = (0.1, 0.1, 0.4, 1.0)
        links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    if subsurface > 0.0:
        bsdf.inputs["Subsurface"].default_value = subsurface
        bsdf.inputs["Subsurface Radius"].default_value = (0.3, 0.15, 0.1)
        bsdf.inputs["Subsurface Color"].default_value = (*color, 1.0)
    if transparent > 0.0:
        mix = nodes.new("ShaderNodeMixShader")
        clear = nodes.new("ShaderNodeBsdfTransparent")
        mix.inputs["Fac"].default_value = transparent
        links.new(bsdf.outputs["BSDF"], mix.inputs[1])
        links.new(clear.outputs["BSDF"], mix.inputs[2])
        links.new(mix.outputs["Shader"], nodes["Material Output"].inputs["Surface"])
    return mat


def add(op, name, mat, collection=None, **kwargs):
    """Adds a mesh primitive with bpy.ops.mesh.<op> and names it."""
    getattr(bpy.ops.mesh, op)(**kwargs)
    obj = bpy.context.active_object
    obj.name = name
    obj.data.materials.append(mat)
    if collection is not None:
        for c in obj.users_collection:
            c.objects.unlink(obj)
        collection.objects.link(obj)
    return obj


def keyframes(obj, path, values_by_frame):
    for frame, value in values_by_frame.items():
        setattr(obj, path, value)
        obj.keyframe_insert(data_path=path, frame=frame)
    for fcurve in obj.animation_data.action.fcurves:
        for point in fcurve.keyframe_points:
            point.interpolation = "LINEAR"


def build_scene():
    scene = bpy.context.scene
    ground = add("primitive_plane_add", "ground", material("ground", (0.6, 0.6, 0.55)), size=12)
    wall = add("primitive_plane_add", "wall", material("wall", (0.5, 0.55, 0.65)), size=12,
               location=(0, 4, 3), rotation=(math.radians(90), 0, 0))
    del ground, wall

    # Object motion: translation (3 steps) and rotation (5 steps).
    cube = add("primitive_cube_add", "moving_cube", material("red", (0.8, 0.1, 0.08)),
               size=1.0, location=(-2.2, 0.5, 0.5))
    keyframes(cube, "location", {1: (-3.0, 0.5, 0.5), 3: (-1.4, 0.5, 0.5)})
    sphere = add("primitive_uv_sphere_add", "spinning_sphere",
                 material("skin", (0.9, 0.6, 0.45), subsurface=0.4, checker=True), radius=0.8,
                 segments=12, ring_count=8, location=(0.0, 1.0, 0.8))
    sphere.cycles.motion_steps = 2
    keyframes(sphere, "rotation_euler", {1: (0.0, 0.0, 0.0), 3: (0.0, math.radians(40), math.radians(80))})

    # Deformation motion: a shape key animated across the shutter.
    torus = add("primitive_torus_add", "deforming_torus", material("gold", (0.9, 0.7, 0.2),
                metallic=0.8, roughness=0.3), major_radius=0.6, minor_radius=0.2,
                location=(2.2, 0.3, 0.35), major_segments=32, minor_segments=12)
    torus.shape_key_add(name="Basis")
    stretched = torus.shape_key_add(name="stretched")
    for point in stretched.data:
        x, y, z = point.co
        point.co = (x * 1.6, y * 0.7, z + 0.5 * x)
    stretched.value = 0.0
    stretched.keyframe_insert("value", frame=1)
    stretched.value = 1.0
    stretched.keyframe_insert("value", frame=3)

    # Instancing: one collection shown four times; one instance moves.
    proto = bpy.data.collections.new("prototype")
    scene.collection.children.link(proto)
    add("primitive_monkey_add", "monkey", material("glass_green", (0.2, 0.8, 0.3), transparent=0.5),
        collection=proto, size=0.6)
    bpy.context.view_layer.layer_collection.children["prototype"].exclude = True
    for i, (x, y) in enumerate([(-1.5, -1.0), (-0.5, -1.3), (0.5, -1.3), (1.5, -1.0)]):
        inst = bpy.data.objects.new(f"monkey_instance_{i}", None)
        inst.instance_type = "COLLECTION"
        inst.instance_collection = proto
        inst.location = (x, y, 0.35)
        inst.rotation_euler = (0.0, 0.0, math.radians(180 + 20 * (i - 1.5)))
        scene.collection.objects.link(inst)
        if i == 2:
            keyframes(inst, "location", {1: (x, y, 0.05), 3: (x, y, 0.75)})

    sun = bpy.data.lights.new("sun", "SUN")
    sun.energy = 3.0
    sun.angle = math.radians(5)
    sun_obj = bpy.data.objects.new("sun", sun)
    sun_obj.rotation_euler = (math.radians(40), math.radians(-20), math.radians(30))
    scene.collection.objects.link(sun_obj)
    area = bpy.data.lights.new("area", "AREA")
    area.energy = 300.0
    area.size = 2.0
    area_obj = bpy.data.objects.new("area", area)
    area_obj.location = (2.5, -3.0, 4.0)
    area_obj.rotation_euler = (math.radians(40), 0.0, math.radians(40))
    scene.collection.objects.link(area_obj)

    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.25, 0.27, 0.3, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.5
    scene.world = world

    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.location = (0.0, -6.5, 2.4)
    cam.rotation_euler = (math.radians(76), 0.0, 0.0)
    cam.data.lens = 42
    scene.collection.objects.link(cam)
    scene.camera = cam


def configure(scene, args):
    width, height = (int(v) for v in args.size.split("x"))
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.seed = args.seed
    scene.cycles.use_animated_seed = False
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 4
    scene.cycles.transparent_max_bounces = 8
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads
    scene.render.use_motion_blur = not args.no_motion_blur
    scene.render.motion_blur_shutter = 1.0
    scene.cycles.motion_blur_position = "CENTER"
    scene.render.use_persistent_data = False
    scene.frame_start = scene.frame_end = 2
    scene.frame_set(2)


def save_pixels(scene, png_path):
    """Writes the render as PNG, and its float pixels (from an EXR) as .npy."""
    result = bpy.data.images["Render Result"]
    settings = scene.render.image_settings
    settings.file_format = "PNG"
    settings.color_mode = "RGB"
    result.save_render(png_path, scene=scene)
    exr_path = os.path.splitext(png_path)[0] + ".exr"
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGBA"
    settings.color_depth = "32"
    result.save_render(exr_path, scene=scene)
    image = bpy.data.images.load(exr_path)
    width, height = image.size
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    # Blender stores the bottom row first.
    np.save(os.path.splitext(png_path)[0] + ".npy", pixels.reshape(height, width, 4)[::-1])
    os.remove(exr_path)


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build_scene()
    scene = bpy.context.scene
    configure(scene, args)
    start = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    seconds = time.perf_counter() - start
    save_pixels(scene, os.path.abspath(args.out))
    print(f"scene.py: libembree3 mapped: {mapped_embree()}")
    print(f"scene.py: render_seconds {seconds:.3f} (seed {args.seed}, {args.samples} samples, "
          f"{args.size}, motion blur {'off' if args.no_motion_blur else 'on'}, {args.threads} threads)")


if __name__ == "__main__":
    main()
