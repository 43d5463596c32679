"""A tiny Cycles scene with hair, which mbrt's libembree3 does not have.

    blender -b --factory-startup --python-exit-code 1 --debug-cycles --verbose 1 \\
        --python hair.py -- OUT.png

A plane with 200 hair strands (Cycles asks Embree for a curve geometry and
writes the strands through the buffer pointer it gets back, unchecked), a
sphere, a sun; 64x48, 4 samples. run.sh renders it through the shim: Cycles
must log the shim's Embree error for the curve geometry and finish the
render without the hair, not crash. Prints the libembree3 file mapped.
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from mapped_library import mapped_embree  # noqa: E402


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 4
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y = 64, 48
    bpy.ops.mesh.primitive_plane_add(size=2)
    hair = bpy.context.object.modifiers.new("hair", "PARTICLE_SYSTEM").particle_system.settings
    hair.type, hair.count, hair.hair_length = "HAIR", 200, 0.5
    bpy.ops.mesh.primitive_uv_sphere_add(location=(0, 0, 0.6), radius=0.3)
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.location, camera.rotation_euler = (0, -4, 2), (1.1, 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.collection.objects.link(bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN")))
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)
    print(f"hair.py: libembree3 mapped: {mapped_embree()}")
    print(f"hair.py: rendered {out}")


main()
