#!/usr/bin/env python3
"""Generates the reference-suite scenes in scenes/suite/ (deterministic: rerunning rewrites the
same bytes).

Every scene uses explicit geometry only (TOML `polygon` objects, TOML `mesh` objects naming an
OBJ file, bare OBJ scenes and a glTF scene), so that `benches/suite/reference.py` reads exactly
the same faces as our loader without any of our code. Lengths in metres, except
`cornell-faces` (millimetres, as the Cornell data). Fronts follow the right-hand rule
(counter-clockwise seen from the front).

Usage: python3 benches/suite/make_scenes.py [OUT_DIR]   (default: scenes/suite)
"""

import json
import math
import pathlib
import random
import struct
import sys
import tomllib

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
OUT = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "scenes" / "suite"


# ---------------------------------------------------------------------------------------------
# Geometry helpers


def fmt(x):
    """A short exact-enough decimal for a coordinate (rounded to 0.1 µm in scene units)."""
    x = round(float(x), 7)
    if x == 0:
        x = 0.0
    s = repr(x)
    return s


def rect(k, c, lo, hi, sign):
    """Axis-aligned rectangle in the plane coordinate[k] = c, spanning lo..hi on the two other
    axes (components of the 3-vectors lo, hi), front towards sign * axis k."""
    i, j = (k + 1) % 3, (k + 2) % 3

    def p(a, b):
        v = [0.0, 0.0, 0.0]
        v[k], v[i], v[j] = c, a, b
        return v

    q = [p(lo[i], lo[j]), p(hi[i], lo[j]), p(hi[i], hi[j]), p(lo[i], hi[j])]
    return q if sign > 0 else q[::-1]


def box_faces(lo, hi, skip=()):
    """The six outward quads of an axis-aligned box; `skip` names faces to leave out
    ('-x', '+x', '-y', '+y', '-z', '+z')."""
    faces = []
    for k, axis in enumerate("xyz"):
        if f"-{axis}" not in skip:
            faces.append(rect(k, lo[k], lo, hi, -1))
        if f"+{axis}" not in skip:
            faces.append(rect(k, hi[k], lo, hi, +1))
    return faces


def room_faces(lo, hi):
    """{name: quad} of the inward-facing walls of an axis-aligned room."""
    return {
        "floor": rect(1, lo[1], lo, hi, +1),
        "ceiling": rect(1, hi[1], lo, hi, -1),
        "x0": rect(0, lo[0], lo, hi, +1),
        "x1": rect(0, hi[0], lo, hi, -1),
        "z0": rect(2, lo[2], lo, hi, +1),
        "z1": rect(2, hi[2], lo, hi, -1),
    }


def holed_rect(k, c, lo, hi, hole_lo, hole_hi, sign):
    """A rectangle with a rectangular hole as four quads (two full-width strips, two side
    pieces), same conventions as `rect`."""
    i, j = (k + 1) % 3, (k + 2) % 3

    def v(a, b):
        w = [0.0, 0.0, 0.0]
        w[i], w[j] = a, b
        return w

    parts = [
        (v(lo[i], lo[j]), v(hi[i], hole_lo[j])),
        (v(lo[i], hole_hi[j]), v(hi[i], hi[j])),
        (v(lo[i], hole_lo[j]), v(hole_lo[i], hole_hi[j])),
        (v(hole_hi[i], hole_lo[j]), v(hi[i], hole_hi[j])),
    ]
    return [rect(k, c, a, b, sign) for a, b in parts]


def newell(poly):
    n = [0.0, 0.0, 0.0]
    for a, b in zip(poly, poly[1:] + poly[:1]):
        n[0] += (a[1] - b[1]) * (a[2] + b[2])
        n[1] += (a[2] - b[2]) * (a[0] + b[0])
        n[2] += (a[0] - b[0]) * (a[1] + b[1])
    return n


def icosphere(freq):
    """Geodesic sphere of radius 1: every icosahedron face split into freq^2 triangles,
    projected on the sphere. (vertices, faces), faces counter-clockwise seen from outside."""
    t = (1 + 5**0.5) / 2
    base = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
            (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
            (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
            (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts, index, faces = [], {}, []

    def vid(p):
        n = math.sqrt(sum(c * c for c in p))
        p = tuple(c / n for c in p)
        key = tuple(round(c, 9) for c in p)
        if key not in index:
            index[key] = len(verts)
            verts.append(list(p))
        return index[key]

    for a, b, c in tris:
        A, B, C = base[a], base[b], base[c]

        def pt(i, j):  # i steps along AB, j along AC
            return tuple(A[k] + (B[k] - A[k]) * i / freq + (C[k] - A[k]) * j / freq for k in range(3))

        for i in range(freq):
            for j in range(freq - i):
                faces.append((vid(pt(i, j)), vid(pt(i + 1, j)), vid(pt(i, j + 1))))
                if i + j < freq - 1:
                    faces.append((vid(pt(i + 1, j)), vid(pt(i + 1, j + 1)), vid(pt(i, j + 1))))
    # orient outwards
    out = []
    for f in faces:
        a, b, c = (verts[i] for i in f)
        n = [(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
             (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
             (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])]
        out.append(f if sum(n[k] * (a[k] + b[k] + c[k]) for k in range(3)) > 0 else f[::-1])
    return verts, out


def placed_sphere(freq, radius, cx, cz, floor_y, wobble, seed):
    """An icosphere radially perturbed by `wobble` (relative, deterministic smooth + random),
    moved so that its lowest vertex lies exactly on y = floor_y."""
    verts, faces = icosphere(freq)
    rng = random.Random(seed)
    out = []
    for x, y, z in verts:
        smooth = math.sin(3 * x + 0.5) * math.sin(4 * y + 1.0) * math.cos(5 * z)
        r = radius * (1 + wobble * (0.6 * smooth + 0.4 * (2 * rng.random() - 1)))
        out.append([r * x, r * y, r * z])
    ymin = min(v[1] for v in out)
    out = [[v[0] + cx, v[1] - ymin + floor_y, v[2] + cz] for v in out]
    for v in out:
        if abs(v[1] - floor_y) < 1e-12:
            v[1] = floor_y
    return out, faces


def mesh_of_boxes(boxes):
    """(vertices, quads) of closed boxes given as (lo, hi), each with 8 shared corners."""
    verts, faces = [], []
    for lo, hi in boxes:
        index = {}
        for q in box_faces(lo, hi):
            f = []
            for v in q:
                key = tuple(v)
                if key not in index:
                    index[key] = len(verts)
                    verts.append(list(v))
                f.append(index[key])
            faces.append(f)
    return verts, faces


# ---------------------------------------------------------------------------------------------
# Writers


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return fmt(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise TypeError(v)


def write_toml(path, header, camera, materials, objects):
    """objects: list of dicts (name, material, shape, vertices | path)."""
    lines = [f"# {line}" if line else "#" for line in header.splitlines()]
    lines += ["", "[camera]"]
    lines += [f"{k} = {toml_value(v)}" for k, v in camera.items()]
    lines += ["", "[render]", "width = 512", "height = 512"]
    for name, m in materials.items():
        lines += ["", f"[materials.{name}]"]
        lines += [f"{k} = {toml_value(v)}" for k, v in m.items()]
    for o in objects:
        lines += ["", "[[objects]]"]
        lines += [f"{k} = {toml_value(v)}" for k, v in o.items()]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")
    tomllib.loads(path.read_text())  # sanity


def polys(name, material, quads):
    return [{"name": name, "material": material, "shape": "polygon", "vertices": q} for q in quads]


def write_obj(path, groups, mtllib=None, header="", normals=None):
    """groups: list of (object name, material or None, vertices, faces (0-based lists)).
    Vertices are written per group (indices continue across groups, 1-based)."""
    lines = [f"# {line}" for line in header.splitlines()]
    if mtllib:
        lines.append(f"mtllib {mtllib}")
    base = 1
    for name, material, verts, faces in groups:
        lines.append(f"o {name}")
        lines += [f"v {fmt(x)} {fmt(y)} {fmt(z)}" for x, y, z in verts]
        if material:
            lines.append(f"usemtl {material}")
        lines += ["f " + " ".join(str(base + i) for i in f) for f in faces]
        base += len(verts)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")


def write_mtl(path, materials):
    lines = []
    for name, m in materials.items():
        lines += [f"newmtl {name}", "Kd " + " ".join(fmt(c) for c in m["Kd"])]
        if "Ke" in m:
            lines.append("Ke " + " ".join(fmt(c) for c in m["Ke"]))
        lines += ["Ns 0", "illum 1", ""]
    path.write_text("\n".join(lines))


# ---------------------------------------------------------------------------------------------
# Scenes

WHITE = [0.73, 0.71, 0.68]
RED = [0.63, 0.065, 0.05]
GREEN = [0.14, 0.45, 0.091]


def cornell_faces():
    src = tomllib.loads((ROOT / "scenes" / "cornell" / "scene.toml").read_text())
    objects, counts = [], {}
    for o in src["objects"]:
        if o["name"] in ("short_block", "tall_block"):
            i = counts.get(o["name"], 0)
            counts[o["name"]] = i + 1
            n = newell(o["vertices"])
            k = max(range(3), key=lambda a: abs(n[a]))
            # As the Cornell walls: x = 556 is the left (red) wall seen from the camera at -z.
            side = {(1, True): "top", (2, False): "front", (2, True): "back",
                    (0, True): "left", (0, False): "right"}[(k, n[k] > 0)]
            objects.append(dict(o, name=f"{o['name']}_{side}"))
        else:
            objects.append(dict(o))
    names = [o["name"] for o in objects]
    assert len(set(n for n in names if "block" in n)) == 10
    write_toml(
        OUT / "cornell-faces" / "scene.toml",
        "The Cornell box of scenes/cornell/scene.toml (MILLIMETRES, same walls, light and\n"
        "materials), with every face of each block its own object: short_block_top,\n"
        "short_block_front (-z, facing the camera), _back (+z), _left (+x, the red side),\n"
        "_right (-x). Generated by benches/suite/make_scenes.py.",
        src["camera"], src["materials"], objects)


def obj_box():
    """Bare OBJ Cornell-style box, 2 m, open at z = 0; walls are 3 x 3 grids of quads on a
    shared lattice whose vertices are pushed 1-2 % of the wall size out of their planes."""
    size, n = 2.0, 3
    rng = random.Random(7)
    lattice = {}

    def vert(i, j, k):
        key = (i, j, k)
        if key not in lattice:
            p = [size * i / n, size * j / n, size * k / n]
            for a, c in enumerate(key):
                if c in (0, n):
                    p[a] += rng.choice((-1, 1)) * size * rng.uniform(0.01, 0.02)
            lattice[key] = p
        return key

    walls = {}

    def grid(name, k, c, sign):
        i, j = (k + 1) % 3, (k + 2) % 3
        quads = []
        for a in range(n):
            for b in range(n):
                q = []
                for da, db in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    key = [0, 0, 0]
                    key[k], key[i], key[j] = c, a + da, b + db
                    q.append(vert(*key))
                quads.append(q if sign > 0 else q[::-1])
        walls[name] = quads

    grid("floor", 1, 0, +1)
    grid("ceiling", 1, n, -1)
    grid("back_wall", 2, n, -1)
    grid("right_wall", 0, 0, +1)   # x = 0: green
    grid("left_wall", 0, n, -1)    # x = size: red
    s = size / 555.0
    short = [[290, 114], [240, 272], [82, 225], [130, 65]]  # Cornell footprints (mm)
    tall = [[423, 247], [472, 406], [314, 456], [265, 296]]

    def block(foot, h):
        foot = [[x * s, z * s] for x, z in foot]
        # make the footprint clockwise in (x, z) so that the top (+y) is counter-clockwise from above
        area = sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(foot, foot[1:] + foot[:1]))
        if area < 0:
            foot = foot[::-1]
        verts = [[x, 0.0, z] for x, z in foot] + [[x, h, z] for x, z in foot]
        faces = [[7, 6, 5, 4]]
        for a in range(4):
            b = (a + 1) % 4
            faces.append([a, b, 4 + b, 4 + a])
        # orient every face outwards (by the centroid)
        cx = sum(v[0] for v in verts) / 8
        cy = h / 2
        cz = sum(v[2] for v in verts) / 8
        out = []
        for f in faces:
            q = [verts[i] for i in f]
            nn = newell(q)
            m = [sum(v[c] for v in q) / 4 for c in range(3)]
            d = nn[0] * (m[0] - cx) + nn[1] * (m[1] - cy) + nn[2] * (m[2] - cz)
            out.append(f if d > 0 else f[::-1])
        out.append(list(out[2]))  # the defect: a side face repeated as the "bottom"
        return verts, out

    sb, tb = block(short, 165 * s), block(tall, 330 * s)
    keys = sorted(lattice)
    kid = {k: i for i, k in enumerate(keys)}
    lines = ["# Cornell-style box as a modelling tool exports it (benches/suite/make_scenes.py):",
             "# shared lattice vertices pushed 1-2 % of the wall size out of plane, non-planar",
             "# quads, each block with a side face repeated as a coincident 'bottom' face.",
             "mtllib scene.mtl"]
    lines += [f"v {fmt(x)} {fmt(y)} {fmt(z)}" for x, y, z in (lattice[k] for k in keys)]
    mats = {"floor": "white", "ceiling": "white", "back_wall": "white",
            "right_wall": "green", "left_wall": "red"}
    for name, quads in walls.items():
        lines += [f"o {name}", f"usemtl {mats[name]}"]
        lines += ["f " + " ".join(str(kid[v] + 1) for v in q) for q in quads]
    base = len(keys) + 1
    nbase = 1
    for name, (verts, faces) in (("short_block", sb), ("tall_block", tb)):
        lines += [f"o {name}"]
        lines += [f"v {fmt(x)} {fmt(y)} {fmt(z)}" for x, y, z in verts]
        normals = []
        for f in faces:
            nn = newell([verts[i] for i in f])
            ln = math.sqrt(sum(c * c for c in nn))
            normals.append([c / ln for c in nn])
        lines += [f"vn {fmt(a)} {fmt(b)} {fmt(c)}" for a, b, c in normals]
        lines += ["usemtl white", "s off"]
        for fi, f in enumerate(faces):
            if fi == len(faces) - 1:
                lines.append("# bottom")
            lines.append("f " + " ".join(f"{base + i}//{nbase + fi}" for i in f))
        base += len(verts)
        nbase += len(faces)
    c = size / 2
    h = size - 0.06
    lamp = [[c - 0.25, h, c - 0.25], [c + 0.25, h, c - 0.25], [c + 0.25, h, c + 0.25], [c - 0.25, h, c + 0.25]]
    assert newell(lamp)[1] < 0
    lines += ["o light"] + [f"v {fmt(x)} {fmt(y)} {fmt(z)}" for x, y, z in lamp]
    lines += ["usemtl light", f"f {base} {base + 1} {base + 2} {base + 3}"]
    d = OUT / "obj-box"
    d.mkdir(parents=True, exist_ok=True)
    (d / "scene.obj").write_text("\n".join(lines) + "\n")
    write_mtl(d / "scene.mtl", {
        "white": {"Kd": WHITE}, "red": {"Kd": RED}, "green": {"Kd": GREEN},
        "light": {"Kd": [0.78, 0.78, 0.78], "Ke": [15.0, 12.0, 7.0]},
    })


def cornell_room(size, lamp_half, lamp_emission, extra_objects, materials_extra, header, path,
                 camera=None):
    """TOML Cornell-style box of side `size` (metres, open at z = 0), one-sided inward walls,
    light in the ceiling plane with the ceiling as four quads around it."""
    lo, hi = [0.0, 0.0, 0.0], [size, size, size]
    w = room_faces(lo, hi)
    c = size / 2
    hole_lo, hole_hi = [c - lamp_half, 0, c - lamp_half], [c + lamp_half, 0, c + lamp_half]
    ceiling = holed_rect(1, size, lo, hi, hole_lo, hole_hi, -1)
    lamp = rect(1, size, hole_lo, hole_hi, -1)
    objects = (polys("floor", "white", [w["floor"]]) + polys("light", "light", [lamp])
               + polys("ceiling", "white", ceiling) + polys("back_wall", "white", [w["z1"]])
               + polys("right_wall", "green", [w["x0"]]) + polys("left_wall", "red", [w["x1"]])
               + extra_objects)
    materials = {"white": {"reflectance": WHITE}, "red": {"reflectance": RED},
                 "green": {"reflectance": GREEN},
                 "light": {"reflectance": [0.78, 0.78, 0.78], "emission": lamp_emission}}
    materials.update(materials_extra)
    camera = camera or {"eye": [c, c, -1.6 * size], "target": [c, c, 0.0], "up": [0, 1, 0],
                        "fov_y": 39.3}
    write_toml(path, header, camera, materials, objects)


def closed_mesh():
    verts, faces = placed_sphere(12, 0.55, 1.05, 1.1, 0.0, 0.04, seed=3)
    d = OUT / "closed-mesh"
    write_obj(d / "blob.obj", [("blob", None, verts, faces)],
              header="Geodesic icosphere (frequency 12, 2880 triangles), radii perturbed by up to 4 %,\n"
                     "lowest vertex on y = 0. benches/suite/make_scenes.py")
    cornell_room(
        2.0, 0.25, [18.0, 15.0, 10.0],
        [{"name": "blob", "material": "blue_two_sided", "shape": "mesh", "path": "blob.obj"}],
        {"blue_two_sided": {"reflectance": [0.3, 0.45, 0.7], "two_sided": True}},
        "Cornell-style 2 m box (metres, open at z = 0) with a closed two-sided mesh standing on\n"
        "the floor: a perturbed geodesic sphere (blob.obj). benches/suite/make_scenes.py",
        d / "scene.toml")
    return len(faces)


def partitions():
    """10 x 3 x 6 m room (x, y, z); a 2 cm thick partition at x = 4 with a door, a zero-thickness
    two-sided panel at x = 7 leaving a 1 m gap at z = 5..6; the light is over the middle part."""
    X, Y, Z = 10.0, 3.0, 6.0
    ax0, ax1 = 3.99, 4.01  # thick partition
    bx = 7.0  # thin panel
    dz0, dz1, dh = 2.5, 3.5, 2.1  # door
    gap = 5.0  # panel spans z 0..5
    objs = []

    def span(name, mat, x0, x1):
        lo, hi = [x0, 0.0, 0.0], [x1, Y, Z]
        objs.extend(polys(f"{name}_floor", "floor", [rect(1, 0.0, lo, hi, +1)]))
        return lo, hi

    # floors
    span("left", "floor", 0.0, ax0)
    span("mid", "floor", ax1, bx)
    objs.extend(polys("mid_floor", "floor", [rect(1, 0.0, [ax0, 0, dz0], [ax1, 0, dz1], +1)]))
    span("right", "floor", bx, X)
    # ceilings (light in the middle one, 1.2 x 1.2 m)
    lc = [(ax1 + bx) / 2, 0, Z / 2]
    l_lo, l_hi = [lc[0] - 0.6, 0, lc[2] - 0.6], [lc[0] + 0.6, 0, lc[2] + 0.6]
    objs.extend(polys("left_ceiling", "ceiling", [rect(1, Y, [0, 0, 0], [ax0, 0, Z], -1)]))
    objs.extend(polys("mid_ceiling", "ceiling", holed_rect(1, Y, [ax1, 0, 0], [bx, 0, Z], l_lo, l_hi, -1)))
    objs.extend(polys("light", "light", [rect(1, Y, l_lo, l_hi, -1)]))
    objs.extend(polys("right_ceiling", "ceiling", [rect(1, Y, [bx, 0, 0], [X, 0, Z], -1)]))
    # outer walls per part
    objs.extend(polys("left_walls", "red_wall", [
        rect(0, 0.0, [0, 0, 0], [0, Y, Z], +1),
        rect(2, 0.0, [0, 0, 0], [ax0, Y, 0], +1),
        rect(2, Z, [0, 0, 0], [ax0, Y, 0], -1)]))
    objs.extend(polys("mid_walls", "white", [
        rect(2, 0.0, [ax1, 0, 0], [bx, Y, 0], +1),
        rect(2, Z, [ax1, 0, 0], [bx, Y, 0], -1)]))
    objs.extend(polys("right_walls", "blue_wall", [
        rect(0, X, [0, 0, 0], [0, Y, Z], -1),
        rect(2, 0.0, [bx, 0, 0], [X, Y, 0], +1),
        rect(2, Z, [bx, 0, 0], [X, Y, 0], -1)]))
    # thick partition: both sides as three quads around the door, jambs and head
    pa = []
    for x, sign in ((ax0, -1), (ax1, +1)):
        pa += [rect(0, x, [0, 0, 0], [0, Y, dz0], sign),
               rect(0, x, [0, 0, dz1], [0, Y, Z], sign),
               rect(0, x, [0, dh, dz0], [0, Y, dz1], sign)]
    pa += [rect(2, dz0, [ax0, 0, 0], [ax1, dh, 0], +1),
           rect(2, dz1, [ax0, 0, 0], [ax1, dh, 0], -1),
           rect(1, dh, [ax0, 0, dz0], [ax1, 0, dz1], -1)]
    objs.extend(polys("partition_thick", "white", pa))
    # thin two-sided panel, front towards the lit middle part (-x)
    objs.extend(polys("partition_panel", "panel", [rect(0, bx, [0, 0, 0], [0, Y, gap], -1)]))
    materials = {
        "white": {"reflectance": [0.72, 0.72, 0.7]},
        "ceiling": {"reflectance": [0.8, 0.8, 0.8]},
        "floor": {"reflectance": [0.5, 0.42, 0.33]},
        "red_wall": {"reflectance": [0.7, 0.4, 0.35]},
        "blue_wall": {"reflectance": [0.35, 0.45, 0.7]},
        "panel": {"reflectance": [0.6, 0.6, 0.5], "two_sided": True},
        "light": {"reflectance": [0.5, 0.5, 0.5], "emission": [20.0, 19.0, 17.0]},
    }
    write_toml(OUT / "partitions" / "scene.toml",
               "10 x 6 x 3 m room (x 0..10, y 0..3 up, z 0..6) in three parts: a 2 cm thick\n"
               "partition (explicit one-sided faces) at x = 4 with a 1 x 2.1 m door, a two-sided\n"
               "zero-thickness panel at x = 7 leaving a 1 m gap at z = 5..6. Ceiling light over the\n"
               "middle part; the left and right parts are lit only through the door and the gap.\n"
               "benches/suite/make_scenes.py",
               {"eye": [5.0, 2.6, -1.0], "target": [5.0, 1.0, 4.0], "up": [0, 1, 0], "fov_y": 70.0},
               materials, objs)


def emitter_near_wall(facing):
    X, Y, Z = 4.0, 2.5, 3.0
    lo, hi = [0.0, 0.0, 0.0], [X, Y, Z]
    w = room_faces(lo, hi)
    l_lo, l_hi = [1.8, 0, 1.3], [2.2, 0, 1.7]
    wz = Z - 0.001
    win = rect(2, wz, [1.4, 0.8, 0], [2.6, 1.8, 0], +1 if facing else -1)
    objs = (polys("floor", "floor", [w["floor"]])
            + polys("ceiling", "white", holed_rect(1, Y, lo, hi, l_lo, l_hi, -1))
            + polys("lamp", "lamp", [rect(1, Y, l_lo, l_hi, -1)])
            + polys("back_wall", "white", [w["z1"]])
            + polys("front_wall", "white", [w["z0"]])
            + polys("left_wall", "red", [w["x0"]])
            + polys("right_wall", "green", [w["x1"]])
            + polys("window", "window", [win]))
    materials = {
        "white": {"reflectance": [0.75, 0.75, 0.72]},
        "floor": {"reflectance": [0.45, 0.4, 0.35]},
        "red": {"reflectance": [0.7, 0.3, 0.25]},
        "green": {"reflectance": [0.3, 0.6, 0.3]},
        "lamp": {"reflectance": [0.5, 0.5, 0.5], "emission": [10.0, 9.0, 7.0]},
        "window": {"reflectance": [0.5, 0.5, 0.5], "emission": [5.0, 5.5, 6.0]},
    }
    name = "emitter-near-wall-" + ("facing" if facing else "away")
    write_toml(OUT / name / "scene.toml",
               "Closed 4 x 2.5 x 3 m room, one-sided walls facing in, a small ceiling lamp and a\n"
               "1.2 x 1 m window-like emitter 1 mm in front of the back wall (z = 3), its front "
               + ("facing the WALL\n(a vertex-order mistake: its light is trapped in the 1 mm slit)."
                  if facing else "facing into\nthe room.") + " benches/suite/make_scenes.py",
               {"eye": [2.0, 1.3, 0.05], "target": [2.0, 1.2, 3.0], "up": [0, 1, 0], "fov_y": 60.0},
               materials, objs)


def blender_gltf():
    """A Blender-style export: Y-up, every material doubleSided, flat-shaded triangle meshes
    with split per-face vertices, NORMAL and TEXCOORD_0, node TRS, a mesh shared by two nodes."""
    buf = bytearray()
    views, accessors, meshes = [], [], []

    def add_view(data, target):
        while len(buf) % 4:
            buf.append(0)
        views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(data), "target": target})
        buf.extend(data)
        return len(views) - 1

    def add_mesh(name, quads, material):
        pos, nor, uv, idx = [], [], [], []
        for q in quads:
            nn = newell(q)
            ln = math.sqrt(sum(c * c for c in nn))
            nn = [c / ln for c in nn]
            b = len(pos)
            for v, t in zip(q, ((0, 0), (1, 0), (1, 1), (0, 1))):
                pos.append(v)
                nor.append(nn)
                uv.append(t)
            idx += [b, b + 1, b + 2, b, b + 2, b + 3]
        acc = {}
        for key, data, typ in (("POSITION", pos, "VEC3"), ("NORMAL", nor, "VEC3"), ("TEXCOORD_0", uv, "VEC2")):
            flat = [c for v in data for c in v]
            view = add_view(struct.pack(f"<{len(flat)}f", *flat), 34962)
            a = {"bufferView": view, "componentType": 5126, "count": len(data), "type": typ}
            if key == "POSITION":
                f32 = [struct.unpack("<3f", struct.pack("<3f", *v)) for v in data]
                a["min"] = [min(v[k] for v in f32) for k in range(3)]
                a["max"] = [max(v[k] for v in f32) for k in range(3)]
            accessors.append(a)
            acc[key] = len(accessors) - 1
        view = add_view(struct.pack(f"<{len(idx)}H", *idx), 34963)
        accessors.append({"bufferView": view, "componentType": 5123, "count": len(idx), "type": "SCALAR"})
        meshes.append({"name": name, "primitives": [{"attributes": acc, "indices": len(accessors) - 1,
                                                     "material": material}]})
        return len(meshes) - 1

    W, H, D = 3.0, 2.5, 3.0  # room x -1.5..1.5, y 0..2.5, z -1.5..1.5, open at +z
    lo, hi = [-W / 2, 0, -D / 2], [W / 2, H, D / 2]
    mats = [("White", [0.73, 0.71, 0.68]), ("Red", [0.63, 0.065, 0.05]),
            ("Green", [0.14, 0.45, 0.091]), ("Light", [0.8, 0.8, 0.8]), ("Block", [0.6, 0.6, 0.6])]
    materials = []
    for name, col in mats:
        m = {"name": name, "doubleSided": True,
             "pbrMetallicRoughness": {"baseColorFactor": col + [1.0], "metallicFactor": 0.0,
                                      "roughnessFactor": 0.5}}
        if name == "Light":
            m["emissiveFactor"] = [1.0, 0.85, 0.6]
            m["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": 14.0}}
        materials.append(m)
    # walls: meshes in local frames centred on the node, as Blender keeps object origins
    nodes = []

    def node(name, mesh, t=None, r=None, s=None):
        n = {"name": name, "mesh": mesh}
        if r:
            n["rotation"] = r
        if s:
            n["scale"] = s
        if t:
            n["translation"] = t
        nodes.append(n)

    node("Floor", add_mesh("Plane", [rect(1, 0.0, [-1.5, 0, -1.5], [1.5, 0, 1.5], +1)], 0))
    node("Ceiling", add_mesh("Plane.001", [rect(1, 0.0, [-1.5, 0, -1.5], [1.5, 0, 1.5], -1)], 0), t=[0, H, 0])
    node("BackWall", add_mesh("Plane.002", [rect(2, 0.0, [-1.5, -1.25, 0], [1.5, 1.25, 0], +1)], 0),
         t=[0, H / 2, -D / 2])
    node("LeftWall", add_mesh("Plane.003", [rect(0, 0.0, [0, -1.25, -1.5], [0, 1.25, 1.5], +1)], 1),
         t=[-W / 2, H / 2, 0])
    node("RightWall", add_mesh("Plane.004", [rect(0, 0.0, [0, -1.25, -1.5], [0, 1.25, 1.5], -1)], 2),
         t=[W / 2, H / 2, 0])
    node("Light", add_mesh("Plane.005", [rect(1, 0.0, [-0.3, 0, -0.3], [0.3, 0, 0.3], -1)], 3),
         t=[0, H - 0.01, 0])
    cube = add_mesh("Cube", box_faces([-1, -1, -1], [1, 1, 1]), 4)

    def qy(deg):
        a = math.radians(deg) / 2
        return [0.0, math.sin(a), 0.0, math.cos(a)]

    node("ShortBlock", cube, t=[0.6, 0.4, 0.45], r=qy(-18), s=[0.4, 0.4, 0.4])
    node("TallBlock", cube, t=[-0.6, 0.8, -0.5], r=qy(20), s=[0.4, 0.8, 0.4])
    nodes.append({"name": "Camera", "camera": 0, "translation": [0, 1.25, 5.6]})
    while len(buf) % 4:
        buf.append(0)
    gltf = {
        "asset": {"generator": "Khronos glTF Blender I/O v4.1.63", "version": "2.0"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"name": "Scene", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "cameras": [{"name": "Camera", "type": "perspective",
                     "perspective": {"aspectRatio": 1.0, "yfov": 0.6911112070083618,
                                     "zfar": 100.0, "znear": 0.1}}],
        "materials": materials,
        "meshes": meshes,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(buf), "uri": "scene.bin"}],
    }
    d = OUT / "blender-gltf"
    d.mkdir(parents=True, exist_ok=True)
    (d / "scene.gltf").write_text(json.dumps(gltf, indent=2) + "\n")
    (d / "scene.bin").write_bytes(bytes(buf))


def bare_obj_many():
    """Bare OBJ room 4 x 3 x 4 m open at z = 0: tiled floor (50 x 40 quads), walls 12 x 9
    quads, ceiling around a light, a torus of 72 x 36 quads lying on the floor, a block."""
    X, Y, Z = 4.0, 3.0, 4.0
    groups = []

    def tiled(k, c, lo, hi, sign, ni, nj):
        i, j = (k + 1) % 3, (k + 2) % 3
        quads = []
        for a in range(ni):
            for b in range(nj):
                l, h = [0.0] * 3, [0.0] * 3
                l[i], h[i] = lo[i] + (hi[i] - lo[i]) * a / ni, lo[i] + (hi[i] - lo[i]) * (a + 1) / ni
                l[j], h[j] = lo[j] + (hi[j] - lo[j]) * b / nj, lo[j] + (hi[j] - lo[j]) * (b + 1) / nj
                quads.append(rect(k, c, l, h, sign))
        return quads

    def add(name, mat, quads):
        verts, faces, index = [], [], {}
        for q in quads:
            f = []
            for v in q:
                key = tuple(round(c, 9) for c in v)
                if key not in index:
                    index[key] = len(verts)
                    verts.append(list(v))
                f.append(index[key])
            faces.append(f)
        groups.append((name, mat, verts, faces))

    add("floor", "tiles", tiled(1, 0.0, [0, 0, 0], [X, 0, Z], +1, 40, 50))
    l_lo, l_hi = [1.6, 0, 1.6], [2.4, 0, 2.4]
    add("ceiling", "white", holed_rect(1, Y, [0, 0, 0], [X, 0, Z], l_lo, l_hi, -1))
    add("light", "light", [rect(1, Y, l_lo, l_hi, -1)])
    add("back_wall", "white", tiled(2, Z, [0, 0, 0], [X, Y, 0], -1, 12, 9))
    add("right_wall", "green", tiled(0, 0.0, [0, 0, 0], [0, Y, Z], +1, 9, 12))
    add("left_wall", "red", tiled(0, X, [0, 0, 0], [0, Y, Z], -1, 9, 12))
    # torus lying on the floor
    R, r, cx, cz, nu, nv = 0.8, 0.25, 1.7, 2.3, 72, 36
    verts, faces = [], []
    for a in range(nu):
        u = 2 * math.pi * a / nu
        for b in range(nv):
            v = 2 * math.pi * b / nv
            verts.append([cx + (R + r * math.cos(v)) * math.cos(u), r + r * math.sin(v),
                          cz + (R + r * math.cos(v)) * math.sin(u)])
    for a in range(nu):
        for b in range(nv):
            i00, i10 = a * nv + b, ((a + 1) % nu) * nv + b
            i01, i11 = a * nv + (b + 1) % nv, ((a + 1) % nu) * nv + (b + 1) % nv
            f = [i00, i01, i11, i10]
            q = [verts[i] for i in f]
            nn = newell(q)
            m = [sum(p[k] for p in q) / 4 for k in range(3)]
            ang = math.atan2(m[2] - cz, m[0] - cx)
            ring = [cx + R * math.cos(ang), r, cz + R * math.sin(ang)]
            if sum(nn[k] * (m[k] - ring[k]) for k in range(3)) < 0:
                f = f[::-1]
            faces.append(f)
    groups.append(("torus", "orange", verts, faces))
    add("block", "white", box_faces([2.9, 0.0, 0.6], [3.5, 0.9, 1.2], skip=("-y",)))
    d = OUT / "bare-obj-many"
    write_obj(d / "scene.obj", groups, mtllib="scene.mtl",
              header="Bare OBJ room with > 4096 faces (benches/suite/make_scenes.py): tiled floor,\n"
                     "tiled walls, a 72 x 36 torus, a block; every face two-sided as a bare OBJ.")
    write_mtl(d / "scene.mtl", {
        "tiles": {"Kd": [0.55, 0.5, 0.45]}, "white": {"Kd": [0.75, 0.75, 0.75]},
        "green": {"Kd": [0.2, 0.55, 0.25]}, "red": {"Kd": [0.7, 0.2, 0.15]},
        "orange": {"Kd": [0.8, 0.5, 0.2]},
        "light": {"Kd": [0.7, 0.7, 0.7], "Ke": [12.0, 12.0, 11.0]},
    })
    return sum(len(g[3]) for g in groups)


def furnished_room():
    X, Y, Z = 5.0, 2.7, 4.0
    d = OUT / "furnished-room"
    lo, hi = [0.0, 0.0, 0.0], [X, Y, Z]
    w = room_faces(lo, hi)
    win_lo, win_hi = [0, 0.9, 1.2], [0, 2.1, 2.8]
    l_lo, l_hi = [2.35, 0, 1.85], [2.65, 0, 2.15]
    objs = (polys("floor", "wood", [w["floor"]])
            + polys("ceiling", "ceiling", holed_rect(1, Y, lo, hi, l_lo, l_hi, -1))
            + polys("lamp", "lamp", [rect(1, Y, l_lo, l_hi, -1)])
            + polys("window_wall", "wall", holed_rect(0, 0.0, [0, 0, 0], [0, Y, Z], win_lo, win_hi, +1))
            + polys("window", "window", [rect(0, 0.0, win_lo, win_hi, +1)])
            + polys("wall_x5", "wall", [w["x1"]])
            + polys("wall_z0", "wall", [w["z0"]])
            + polys("wall_z4", "accent", [w["z1"]]))

    def furniture(name, material, boxes):
        verts, faces = mesh_of_boxes(boxes)
        write_obj(d / f"{name}.obj", [(name, None, verts, faces)],
                  header=f"{name}: closed boxes, outward quads (benches/suite/make_scenes.py)")
        objs.append({"name": name, "material": material, "shape": "mesh", "path": f"{name}.obj"})
        return len(faces)

    # table 1.4 x 0.8, top 0.72..0.77, centred at (2.7, 1.7)
    tx, tz = 2.7, 1.7
    table = [([tx - 0.7, 0.72, tz - 0.4], [tx + 0.7, 0.77, tz + 0.4])]
    for sx in (-1, 1):
        for sz in (-1, 1):
            x, z = tx + sx * 0.62, tz + sz * 0.32
            table.append(([x - 0.025, 0.0, z - 0.025], [x + 0.025, 0.72, z + 0.025]))
    furniture("table", "table", table)

    def chair(cx, cz, back_side):
        b = [([cx - 0.225, 0.43, cz - 0.225], [cx + 0.225, 0.47, cz + 0.225])]
        for sx in (-1, 1):
            for sz in (-1, 1):
                x, z = cx + sx * 0.2, cz + sz * 0.2
                b.append(([x - 0.015, 0.0, z - 0.015], [x + 0.015, 0.43, z + 0.015]))
        zb = cz + back_side * 0.21
        b.append(([cx - 0.225, 0.47, zb - 0.015], [cx + 0.225, 0.92, zb + 0.015]))
        return b

    furniture("chair_1", "chair", chair(2.5, 1.05, -1))
    furniture("chair_2", "chair", chair(2.9, 2.35, +1))
    furniture("sofa", "sofa", [
        ([1.4, 0.0, 3.1], [3.6, 0.42, 3.95]),
        ([1.4, 0.42, 3.75], [3.6, 0.88, 3.95]),
        ([1.4, 0.42, 3.1], [1.55, 0.62, 3.75]),
        ([3.45, 0.42, 3.1], [3.6, 0.62, 3.75]),
    ])
    shelf = [([4.6, 0.0, 0.3], [4.95, 1.8, 0.32]), ([4.6, 0.0, 1.28], [4.95, 1.8, 1.3]),
             ([4.93, 0.0, 0.32], [4.95, 1.8, 1.28])]
    for k in range(5):
        y = 0.05 + k * 0.43
        shelf.append(([4.6, y, 0.32], [4.93, y + 0.02, 1.28]))
    furniture("shelf", "shelf", shelf)
    verts, faces = placed_sphere(4, 0.12, 2.55, 1.65, 0.77, 0.0, seed=1)
    write_obj(d / "ball.obj", [("ball", None, verts, faces)],
              header="ball: icosphere (frequency 4, 320 triangles) on the table top")
    objs.append({"name": "ball", "material": "ball", "shape": "mesh", "path": "ball.obj"})
    materials = {
        "wall": {"reflectance": [0.72, 0.7, 0.65]},
        "accent": {"reflectance": [0.35, 0.5, 0.6]},
        "ceiling": {"reflectance": [0.8, 0.8, 0.8]},
        "wood": {"reflectance": [0.45, 0.32, 0.22]},
        "table": {"reflectance": [0.55, 0.4, 0.25]},
        "chair": {"reflectance": [0.3, 0.3, 0.35]},
        "sofa": {"reflectance": [0.6, 0.25, 0.2]},
        "shelf": {"reflectance": [0.7, 0.6, 0.45]},
        "ball": {"reflectance": [0.2, 0.5, 0.7]},
        "lamp": {"reflectance": [0.5, 0.5, 0.5], "emission": [25.0, 22.0, 18.0]},
        "window": {"reflectance": [0.3, 0.3, 0.3], "emission": [6.0, 6.5, 7.0]},
    }
    write_toml(d / "scene.toml",
               "Furnished 5 x 4 x 2.7 m room (x 0..5, y up, z 0..4): a window-like emitter in the\n"
               "wall x = 0, a ceiling lamp, a table with an icosphere on it, two chairs with thin\n"
               "legs, a sofa and a shelf (closed boxes as OBJ meshes, one-sided materials).\n"
               "benches/suite/make_scenes.py",
               {"eye": [4.8, 1.6, 0.2], "target": [1.5, 0.8, 2.6], "up": [0, 1, 0], "fov_y": 65.0},
               materials, objs)


def main():
    cornell_faces()
    obj_box()
    closed_mesh()
    partitions()
    emitter_near_wall(True)
    emitter_near_wall(False)
    blender_gltf()
    bare_obj_many()
    furnished_room()
    for p in sorted(OUT.rglob("*")):
        if p.is_file():
            assert p.stat().st_size < 1 << 20, p
            print(f"{p.stat().st_size:9d}  {p.relative_to(OUT)}")


if __name__ == "__main__":
    main()
