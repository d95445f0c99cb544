#!/usr/bin/env python3
"""Renders a TOML or OBJ scene with Blender Cycles (bpy from PyPI), for time-to-error comparisons.

The geometry, materials and emitters are read as benches/suite/reference.py reads them (the
scenes of the Mitsuba references), the camera from the TOML file's [camera] table. Every
surface is a Lambertian Diffuse BSDF of the scene's reflectance; emitters add an Emission of
strength 1 and colour L_e (radiance), from their front only (a Backfacing switch), as ours and
Mitsuba's do. Cycles on the CPU with the settings of a fair comparison with a converged
reference: 64 bounces of every kind, no clamping, a box pixel filter one pixel wide, no
adaptive sampling; optionally Intel Open Image Denoise (bundled with Blender). The image is
linear radiance, written as EXR; the render time (bpy.ops.render.render only, scene build
excluded) is printed.

Setup: python3.11 -m venv V && V/bin/pip install bpy==5.0.1 mitsuba==3.9.1
Usage: V/bin/python benches/image/cycles_render.py scenes/cornell/scene.toml --spp 64 [--denoise] -o c.exr
"""

import argparse
import pathlib
import sys
import time
import tomllib

import bpy
import mathutils

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "suite"))

import reference as suite  # noqa: E402


def material(name, rho, emission):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*rho, 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0
    if max(emission) <= 0.0:
        links.new(diffuse.outputs[0], out.inputs["Surface"])
        return m
    emit = nodes.new("ShaderNodeEmission")
    emit.inputs["Color"].default_value = (*emission, 1.0)
    emit.inputs["Strength"].default_value = 1.0
    black = nodes.new("ShaderNodeEmission")
    black.inputs["Strength"].default_value = 0.0
    geometry = nodes.new("ShaderNodeNewGeometry")
    front_only = nodes.new("ShaderNodeMixShader")
    links.new(geometry.outputs["Backfacing"], front_only.inputs[0])
    links.new(emit.outputs[0], front_only.inputs[1])
    links.new(black.outputs[0], front_only.inputs[2])
    both = nodes.new("ShaderNodeAddShader")
    links.new(diffuse.outputs[0], both.inputs[0])
    links.new(front_only.outputs[0], both.inputs[1])
    links.new(both.outputs[0], out.inputs["Surface"])
    return m


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene")
    p.add_argument("--width", type=int, help="default: the scene's [render] width, else 512")
    p.add_argument("--height", type=int, help="default: the scene's [render] height, else 512")
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--denoise", action="store_true")
    p.add_argument("--threads", type=int, default=0, help="0: all cores")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("-o", "--output", required=True)
    args = p.parse_args(argv)
    args.width, args.height = suite.image_size(args.scene, args.width, args.height)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    objects = suite.load(args.scene)
    scale = suite.scene_scale(objects)
    for o in objects:
        for k, (tris, rho, emission, _two_sided) in enumerate(o["groups"]):
            verts = [tuple(v * scale) for t in tris for v in t]
            faces = [(3 * i, 3 * i + 1, 3 * i + 2) for i in range(len(tris))]
            mesh = bpy.data.meshes.new(f"{o['name']}.{k}")
            mesh.from_pydata(verts, [], faces)
            mesh.materials.append(material(f"{o['name']}.{k}", rho, emission))
            scene.collection.objects.link(bpy.data.objects.new(mesh.name, mesh))

    cam = tomllib.loads(pathlib.Path(args.scene).read_text())["camera"]
    eye = mathutils.Vector(cam["eye"]) * scale
    target = mathutils.Vector(cam["target"]) * scale
    up = mathutils.Vector(cam.get("up", [0.0, 1.0, 0.0]))
    forward = (target - eye).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    rotation = mathutils.Matrix((right, true_up, -forward)).transposed().to_4x4()
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.matrix_world = mathutils.Matrix.Translation(eye) @ rotation
    camera.data.sensor_fit = "VERTICAL"
    camera.data.angle_y = float(cam.get("fov_y", 39.3)) * 3.141592653589793 / 180.0
    camera.data.clip_start = 1e-3
    scene.collection.objects.link(camera)
    scene.camera = camera

    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = args.spp
    c.use_adaptive_sampling = False
    c.seed = args.seed
    for bounces in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                    "volume_bounces", "transparent_max_bounces"):
        setattr(c, bounces, 64)
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.use_denoising = args.denoise
    if args.denoise:
        c.denoiser = "OPENIMAGEDENOISE"
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    scene.render.threads_mode = "FIXED" if args.threads else "AUTO"
    if args.threads:
        scene.render.threads = args.threads
    scene.render.resolution_x = args.width
    scene.render.resolution_y = args.height
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = str(pathlib.Path(args.output).resolve())
    t = time.time()
    bpy.ops.render.render(write_still=True)
    seconds = time.time() - t
    print(f"{args.output}: {args.width}x{args.height}, {args.spp} spp"
          f"{', denoised' if args.denoise else ''}, {seconds:.2f} s")


if __name__ == "__main__":
    main()
