#!/usr/bin/env python3
"""Opens a `.glb` export in Blender (bpy from PyPI) as a user would, and renders it.

Prints what Blender read — mesh objects, cameras (position, view direction, vertical field of
view), the scene's bounds in metres and the material's shader nodes — and renders the file's
own camera with Cycles, nothing changed, to OUT.png: the light must show with no node work.

Setup: python3.11 -m venv V && V/bin/pip install bpy==5.0.1
Usage: V/bin/python benches/blender_import.py lit.glb out.png [--size 256] [--samples 16]
"""

import argparse
import math
import sys

import bpy
import mathutils


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("glb")
    p.add_argument("out")
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--samples", type=int, default=16)
    args = p.parse_args(argv)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=args.glb)
    scene = bpy.context.scene
    meshes = [o for o in scene.objects if o.type == "MESH"]
    cameras = [o for o in scene.objects if o.type == "CAMERA"]
    print(f"mesh objects: {len(meshes)}")
    lo = mathutils.Vector((math.inf,) * 3)
    hi = -lo
    for o in meshes:
        for corner in o.bound_box:
            w = o.matrix_world @ mathutils.Vector(corner)
            lo = mathutils.Vector(map(min, lo, w))
            hi = mathutils.Vector(map(max, hi, w))
    print(f"bounds (m, Blender's z-up axes): {tuple(round(x, 4) for x in lo)} .. "
          f"{tuple(round(x, 4) for x in hi)}")
    for c in cameras:
        view = c.matrix_world.to_3x3() @ mathutils.Vector((0, 0, -1))
        print(f"camera {c.name}: at {tuple(round(x, 4) for x in c.matrix_world.translation)}, "
              f"looking {tuple(round(x, 3) for x in view)}, "
              f"vertical fov {math.degrees(c.data.angle_y):.3f} deg")
    if meshes and meshes[0].active_material:
        nodes = meshes[0].active_material.node_tree.nodes
        print(f"material nodes: {sorted(n.bl_idname for n in nodes)}")
    if not cameras:
        sys.exit("no camera in the file")
    scene.camera = cameras[0]
    scene.render.engine = "CYCLES"
    scene.cycles.samples = args.samples
    scene.cycles.device = "CPU"
    scene.render.resolution_x = args.size
    scene.render.resolution_y = args.size
    scene.view_settings.view_transform = "Standard"
    scene.render.filepath = args.out
    bpy.ops.render.render(write_still=True)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
