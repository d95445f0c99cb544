#!/usr/bin/env python3
"""Imports a baked .glb into Blender (bpy from PyPI) with its own glTF importer, as a user
would, and renders the file's first camera with Cycles to a PNG.

Nothing in the imported materials is changed: an unlit (KHR_materials_unlit) material is the
importer's own node setup, which shows the base colour as it is to camera rays. The render
settings are the ones that keep Blender from altering the picture: view transform Standard,
look None, exposure 0, gamma 1, no dithering, no denoising, a 1-pixel box filter (each pixel
the mean over its own area, as `radiosity render` averages its s × s samples), and the
resolution given (the camera's sensor fit from the file's aspect ratio).

Prints one JSON line: the camera, its aspect, the material's node types, the import and render
times.

Usage: V/bin/python benches/bake/blender_render.py baked.glb out.png --width W --height H
       [--samples 16] [--threads 1]
"""

import argparse
import json
import os
import sys
import time

import bpy


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("glb")
    p.add_argument("out")
    p.add_argument("--width", type=int, required=True)
    p.add_argument("--height", type=int, required=True)
    p.add_argument("--samples", type=int, default=16)
    p.add_argument("--threads", type=int, default=1)
    args = p.parse_args(argv)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    start = time.perf_counter()
    bpy.ops.import_scene.gltf(filepath=os.path.abspath(args.glb))
    imported = time.perf_counter() - start
    scene = bpy.context.scene
    cameras = [o for o in scene.objects if o.type == "CAMERA"]
    meshes = [o for o in scene.objects if o.type == "MESH"]
    if not cameras:
        sys.exit("no camera in the file")
    # The importer names the camera object after the glTF node; the first glTF camera is the
    # first one created.
    camera = cameras[0]
    scene.camera = camera

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 1.0
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads
    scene.render.resolution_x = args.width
    scene.render.resolution_y = args.height
    scene.render.resolution_percentage = 100
    scene.render.dither_intensity = 0.0
    scene.render.film_transparent = False
    scene.display_settings.display_device = "sRGB"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.view_settings.use_curve_mapping = False
    scene.sequencer_colorspace_settings.name = "sRGB"
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.color_depth = "8"
    scene.render.filepath = os.path.abspath(args.out)
    if scene.world is not None:
        scene.world.use_nodes = False
        scene.world.color = (0.0, 0.0, 0.0)

    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    rendered = time.perf_counter() - start

    material = meshes[0].active_material if meshes else None
    nodes = sorted(n.bl_idname for n in material.node_tree.nodes) if material else []
    images = {}
    for image in bpy.data.images:
        if image.source == "FILE" or image.packed_file is not None:
            images[image.name] = image.colorspace_settings.name
    interpolation = sorted({n.interpolation for n in material.node_tree.nodes
                            if n.bl_idname == "ShaderNodeTexImage"}) if material else []
    print(json.dumps({
        "blender": bpy.app.version_string,
        "meshes": len(meshes),
        "cameras": [c.name for c in cameras],
        "camera": camera.name,
        "sensor_fit": camera.data.sensor_fit,
        "fov_y_deg": round(camera.data.angle_y * 180 / 3.141592653589793, 4),
        "material_nodes": nodes,
        "texture_interpolation": interpolation,
        "image_colorspaces": images,
        "import_s": round(imported, 3),
        "render_s": round(rendered, 3),
    }))


if __name__ == "__main__":
    main()
