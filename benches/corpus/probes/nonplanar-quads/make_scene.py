#!/usr/bin/env python3
"""Writes this probe: the Cornell box whose block sides are slightly non-planar quads.

The geometry, materials and light are scenes/cornell/scene.toml's, in metres. Each block side is
a quad with one top corner moved along the face's normal by LIFT times the face's diagonal; the
faces start at alternating corners, so the fan diagonal (first corner to third, the two
triangles Mitsuba 3 and our reader cut) runs both ways. LIFT 0 gives the planar twin.

Usage: python3 make_scene.py [--lift 0.005] [--out .]
"""

import argparse
import math
import pathlib

MM = 1e-3


def mm(*v):
    return [c * MM for c in v]


WHITE = [
    [mm(552.8, 0, 0), mm(0, 0, 0), mm(0, 0, 559.2), mm(549.6, 0, 559.2)],
    [mm(556, 548.8, 0), mm(556, 548.8, 227), mm(0, 548.8, 227), mm(0, 548.8, 0)],
    [mm(556, 548.8, 332), mm(556, 548.8, 559.2), mm(0, 548.8, 559.2), mm(0, 548.8, 332)],
    [mm(556, 548.8, 227), mm(556, 548.8, 332), mm(343, 548.8, 332), mm(343, 548.8, 227)],
    [mm(213, 548.8, 227), mm(213, 548.8, 332), mm(0, 548.8, 332), mm(0, 548.8, 227)],
    [mm(549.6, 0, 559.2), mm(0, 0, 559.2), mm(0, 548.8, 559.2), mm(556, 548.8, 559.2)],
]
GREEN = [[mm(0, 0, 559.2), mm(0, 0, 0), mm(0, 548.8, 0), mm(0, 548.8, 559.2)]]
RED = [[mm(552.8, 0, 0), mm(549.6, 0, 559.2), mm(556, 548.8, 559.2), mm(556, 548.8, 0)]]
LIGHT = [[mm(343, 548.8, 227), mm(343, 548.8, 332), mm(213, 548.8, 332), mm(213, 548.8, 227)]]
TOPS = [
    [mm(130, 165, 65), mm(82, 165, 225), mm(240, 165, 272), mm(290, 165, 114)],
    [mm(423, 330, 247), mm(265, 330, 296), mm(314, 330, 456), mm(472, 330, 406)],
]
# Sides as (bottom, top, top, bottom), counter-clockwise seen from outside.
SHORT = [
    [mm(290, 0, 114), mm(290, 165, 114), mm(240, 165, 272), mm(240, 0, 272)],
    [mm(130, 0, 65), mm(130, 165, 65), mm(290, 165, 114), mm(290, 0, 114)],
    [mm(82, 0, 225), mm(82, 165, 225), mm(130, 165, 65), mm(130, 0, 65)],
    [mm(240, 0, 272), mm(240, 165, 272), mm(82, 165, 225), mm(82, 0, 225)],
]
TALL = [
    [mm(423, 0, 247), mm(423, 330, 247), mm(472, 330, 406), mm(472, 0, 406)],
    [mm(472, 0, 406), mm(472, 330, 406), mm(314, 330, 456), mm(314, 0, 456)],
    [mm(314, 0, 456), mm(314, 330, 456), mm(265, 330, 296), mm(265, 0, 296)],
    [mm(265, 0, 296), mm(265, 330, 296), mm(423, 330, 247), mm(423, 0, 247)],
]

HEADER = """# The Cornell box's two blocks (scenes/cornell/scene.toml, in metres). The tops are planar;
# each side is a quad with one top corner moved along the face's normal by {lift:g} of the face's
# diagonal, as a modelling tool leaves a quad. The faces start at alternating corners, so the
# fan diagonal (first corner to third, the triangles Mitsuba and we cut) runs both ways.
# Written by make_scene.py --lift {lift:g}.
"""

XML = """<scene version="3.0.0">
  <!-- The Cornell box (scenes/cornell/scene.toml in metres, its camera, materials and light)
       with slightly non-planar block sides (blocks.obj). Face normals: each triangle flat,
       as our reader keeps it. Written by make_scene.py. -->
  <integrator type="path"/>
  <sensor type="perspective">
    <float name="fov" value="39.3077"/>
    <transform name="to_world"><lookat origin="0.278, 0.273, -0.8" target="0.278, 0.273, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="256"/><integer name="height" value="256"/></film>
  </sensor>
  <bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.725, 0.71, 0.68"/></bsdf>
  <bsdf type="diffuse" id="red"><rgb name="reflectance" value="0.63, 0.065, 0.05"/></bsdf>
  <bsdf type="diffuse" id="green"><rgb name="reflectance" value="0.14, 0.45, 0.091"/></bsdf>
  <bsdf type="diffuse" id="light"><rgb name="reflectance" value="0.78, 0.78, 0.78"/></bsdf>
{shapes}</scene>
"""


def moved(quad, k, lift):
    """Side `k` with corner 1 or 2 (alternately) moved along its normal by `lift` of its
    diagonal, starting at corner 0 or 1 (alternately every second face)."""
    u = [quad[1][i] - quad[0][i] for i in range(3)]
    v = [quad[3][i] - quad[0][i] for i in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    length = math.sqrt(sum(c * c for c in n))
    offset = lift * math.dist(quad[0], quad[2])
    q = [list(c) for c in quad]
    corner = 1 if k % 2 == 0 else 2
    q[corner] = [q[corner][i] + offset * n[i] / length for i in range(3)]
    start = (k // 2) % 2
    return q[start:] + q[:start]


def obj(polygons, header=""):
    lines, base = [], 1
    for p in polygons:
        lines += ["v %.7g %.7g %.7g" % tuple(c) for c in p]
        lines.append("f " + " ".join(str(base + i) for i in range(len(p))))
        base += len(p)
    return header + "\n".join(lines) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--lift", type=float, default=0.005, help="corner offset / face diagonal")
    p.add_argument("--out", default=str(pathlib.Path(__file__).resolve().parent))
    args = p.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    sides = [moved(q, k, args.lift) for k, q in enumerate(SHORT)]
    sides += [moved(q, k + 1, args.lift) for k, q in enumerate(TALL)]
    files = {
        "white.obj": obj(WHITE),
        "red.obj": obj(RED),
        "green.obj": obj(GREEN),
        "light.obj": obj(LIGHT),
        "blocks.obj": obj(TOPS + sides, HEADER.format(lift=args.lift)),
    }
    for name, text in files.items():
        (out / name).write_text(text)
    shape = ('  <shape type="obj"><string name="filename" value="{}"/>'
             '<boolean name="face_normals" value="true"/><ref id="{}"/>{}</shape>\n')
    emitter = '<emitter type="area"><rgb name="radiance" value="17, 12, 4"/></emitter>'
    shapes = "".join(shape.format(f, m, e) for f, m, e in [
        ("white.obj", "white", ""), ("red.obj", "red", ""), ("green.obj", "green", ""),
        ("blocks.obj", "white", ""), ("light.obj", "light", emitter)])
    (out / "scene.xml").write_text(XML.format(shapes=shapes))


if __name__ == "__main__":
    main()
