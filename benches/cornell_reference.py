#!/usr/bin/env python3
"""Reference radiosities of the built-in Cornell box from an independent path tracer (Mitsuba 3).

For every object of `scenes/cornell/scene.toml` (the file the `cornell` built-in is compiled
from, read here with `tomllib`, so the geometry, reflectances and emission are exactly ours) it
prints the area-weighted mean radiosity

    B = E + rho * H    (W/m^2, per RGB channel)

where E = pi * L_e is the emitted exitance (non-zero on the light only) and H the mean incident
irradiance over the object's front faces. This is the quantity `radiosity solve cornell --stats`
reports in `objects[].radiosity` (leaving power over geometric area; every Cornell material is
one-sided, as ours).

H comes from Mitsuba 3's `irradiancemeter` sensor attached to the object's mesh: it picks a point
uniformly by area over all the object's triangles and a cosine-distributed direction in front of
it, and returns pi * L_in, whose mean is the mean irradiance. L_in is estimated by the `path`
integrator (next-event estimation with multiple importance sampling) with Russian roulette from
depth `--rr-depth` on, which is unbiased, and a hard cap `--max-depth` so high (256) that the
truncated energy (< 0.78^256 of the emitted power) is nil. Each object is rendered `--seeds`
times with independent seeds; the value is the mean and the standard error is the standard
deviation of the per-seed means over sqrt(seeds).

The same setup is checked on a closed form first-hand: the JSON's `self_check` is the mean
irradiance of the CIE 171:2006 TC 5.8 integrating cube (rho = 0.5), exact pi / 27.
Defaults (4 Mi samples x 10 seeds per object) give a standard error of at most 0.2 % (the floor,
lit mostly by directly hitting the small lamp from cosine-sampled rays) in about 15 minutes on
2 cores (`--jobs`, one process per object and seed).

Units: the scene is in millimetres; it is scaled to metres here (radiance and irradiance are
invariant under a uniform scale) so that Mitsuba's fixed ray epsilon is large against the float
spacing of the coordinates. Reflectances are the scene's RGB values and emitted radiance its RGB
L_e, in the `scalar_rgb` variant (three independent channels, no spectral upsampling).
Each polygon is fanned into triangles (all Cornell polygons are convex quads; the left wall is
slightly non-planar, and its two triangles differ from our bilinear quad by < 0.01 % in area).

Usage:
    pip install mitsuba
    python3 benches/cornell_reference.py > crates/cli/data/cornell_reference.json
"""

import argparse
import datetime
import json
import math
import multiprocessing
import os
import pathlib
import sys
import tempfile
import tomllib

import mitsuba as mi
import numpy as np

SCENE = pathlib.Path(__file__).resolve().parent.parent / "scenes" / "cornell" / "scene.toml"
MM_TO_M = 1e-3


def load_scene(path):
    """(materials, objects): objects as {name: (material, [polygon, ...])} in file order."""
    with open(path, "rb") as f:
        data = tomllib.load(f)
    materials = {}
    for name, m in data["materials"].items():
        assert set(m) <= {"reflectance", "emission"}, f"unsupported material keys in {name}"
        materials[name] = (m["reflectance"], m.get("emission", [0.0, 0.0, 0.0]))
    objects = {}
    for o in data["objects"]:
        assert o["shape"] == "polygon", "the Cornell scene is made of polygons"
        material, polygons = objects.setdefault(o["name"], (o["material"], []))
        assert material == o["material"], f"{o['name']}: one material per object"
        polygons.append([[c * MM_TO_M for c in v] for v in o["vertices"]])
    return materials, objects


def write_obj(path, polygons):
    """Writes the polygons, each fanned from its first corner, as an OBJ file."""
    lines, base = [], 1
    for poly in polygons:
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in poly]
        lines += [f"f {base} {base + i} {base + i + 1}" for i in range(1, len(poly) - 1)]
        base += len(poly)
    pathlib.Path(path).write_text("\n".join(lines) + "\n")


def polygon_area(poly):
    """Area of the fan triangulation (what Mitsuba sees)."""
    area = 0.0
    for i in range(1, len(poly) - 1):
        a, b, c = poly[0], poly[i], poly[i + 1]
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        area += 0.5 * math.sqrt(sum(x * x for x in n))
    return area


def cornell_shapes():
    """{object name: (material name, reflectance, emission, polygons)} of our Cornell scene."""
    materials, objects = load_scene(SCENE)
    return {
        name: (material, *materials[material], polygons)
        for name, (material, polygons) in objects.items()
    }


def furnace_shapes(rho):
    """CIE 171:2006 test case 5.8: a closed 1 m cube of uniform reflectance `rho` whose
    ceiling's centre ninth emits radiance 1, faces pointing inwards. Its mean irradiance over
    all surfaces is exactly pi / 9 / (6 (1 - rho)) (every bounce spreads the remaining power
    over the whole enclosure)."""
    walls, lamp = [], []
    for axis in range(3):
        b, c = [0.0] * 3, [0.0] * 3
        b[(axis + 1) % 3], c[(axis + 2) % 3] = 1.0, 1.0
        for side in (0.0, 1.0):
            u, v = (b, c) if side == 0.0 else (c, b)
            tiles = 3 if axis == 1 and side == 1.0 else 1
            t = 1.0 / tiles
            for i in range(tiles):
                for j in range(tiles):
                    corner = [side if k == axis else 0.0 for k in range(3)]
                    corner = [corner[k] + i * t * u[k] + j * t * v[k] for k in range(3)]
                    quad = [
                        corner,
                        [corner[k] + t * u[k] for k in range(3)],
                        [corner[k] + t * (u[k] + v[k]) for k in range(3)],
                        [corner[k] + t * v[k] for k in range(3)],
                    ]
                    (lamp if tiles == 3 and i == j == 1 else walls).append(quad)
    grey = [rho] * 3
    return {
        "walls": ("grey", grey, [0.0] * 3, walls),
        "lamp": ("lamp", grey, [1.0] * 3, lamp),
    }


def scene_dict(shapes, directory, metered, params):
    """The Mitsuba scene of `shapes` with an irradiance meter on the object `metered`."""
    d = {
        "type": "scene",
        "integrator": {
            "type": "path",
            "max_depth": params["max_depth"],
            "rr_depth": params["rr_depth"],
        },
    }
    for name, (_, reflectance, emission, polygons) in shapes.items():
        filename = os.path.join(directory, f"{name}.obj")
        write_obj(filename, polygons)
        shape = {
            "type": "obj",
            "filename": filename,
            "face_normals": True,
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": reflectance}},
        }
        if any(emission):
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": emission}}
        if name == metered:
            shape["sensor"] = {
                "type": "irradiancemeter",
                "film": {
                    "type": "hdrfilm",
                    "width": 1,
                    "height": 1,
                    "pixel_format": "rgb",
                    "rfilter": {"type": "box"},
                },
                "sampler": {"type": "independent", "sample_count": params["spp"]},
            }
        d[name] = shape
    return d


def mean_irradiance(task):
    """Mean irradiance (r, g, b) over one object for one seed: `passes` renders of `spp`."""
    shapes, metered, seed, params = task
    mi.set_variant(params["variant"])
    with tempfile.TemporaryDirectory() as directory:
        scene = mi.load_dict(scene_dict(shapes, directory, metered, params))
    total = np.zeros(3)
    for p in range(params["passes"]):
        img = mi.render(scene, spp=params["spp"], seed=seed * 1_000_003 + p)
        total += np.array(img, dtype=np.float64).reshape(-1)[:3]
    return total / params["passes"]


def measure(shapes, params, jobs):
    """{object: (mean irradiance, its standard error)} over `params["seeds"]` seeds each."""
    seeds = range(params["first_seed"], params["first_seed"] + params["seeds"])
    tasks = [(shapes, name, seed, params) for name in shapes for seed in seeds]
    with multiprocessing.get_context("spawn").Pool(jobs) as pool:
        runs = pool.map(mean_irradiance, tasks, chunksize=1)
    out = {}
    for i, name in enumerate(shapes):
        per_seed = np.array(runs[i * len(seeds) : (i + 1) * len(seeds)])
        h = per_seed.mean(axis=0)
        se = per_seed.std(axis=0, ddof=1) / math.sqrt(len(seeds))
        out[name] = (h, se)
    return out


def furnace_check(params, jobs):
    """The integrating-sphere check of this very setup: (exact, measured, standard error)."""
    rho = 0.5
    shapes = furnace_shapes(rho)
    measured = measure(shapes, params, jobs)
    areas = {name: sum(polygon_area(p) for p in s[3]) for name, s in shapes.items()}
    total = sum(areas.values())
    mean = sum(areas[n] * measured[n][0][0] for n in shapes) / total
    se = math.sqrt(sum((areas[n] * measured[n][1][0]) ** 2 for n in shapes)) / total
    return math.pi / 9.0 / (6.0 * (1.0 - rho)), mean, se


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="scalar_rgb", help="Mitsuba variant (an *_rgb one)")
    parser.add_argument("--spp", type=int, default=1 << 22, help="samples per render")
    parser.add_argument("--passes", type=int, default=1, help="renders per seed")
    parser.add_argument("--seeds", type=int, default=10, help="independent seeds per object")
    parser.add_argument("--seed", type=int, default=1, help="first seed")
    parser.add_argument("--max-depth", type=int, default=256)
    parser.add_argument("--rr-depth", type=int, default=5)
    parser.add_argument("--jobs", type=int, default=os.cpu_count(), help="worker processes")
    args = parser.parse_args()
    params = {
        "variant": args.variant,
        "spp": args.spp,
        "passes": args.passes,
        "seeds": args.seeds,
        "first_seed": args.seed,
        "max_depth": args.max_depth,
        "rr_depth": args.rr_depth,
    }
    mi.set_variant(args.variant)

    shapes = cornell_shapes()
    measured = measure(shapes, params, args.jobs)
    out = {}
    for name, (material, reflectance, emission, polygons) in shapes.items():
        h, h_se = measured[name]
        rho = np.array(reflectance)
        b = math.pi * np.array(emission) + rho * h
        b_se = rho * h_se
        out[name] = {
            "material": material,
            "area_mm2": sum(polygon_area(p) for p in polygons) / MM_TO_M**2,
            "radiosity": b.tolist(),
            "radiosity_standard_error": b_se.tolist(),
            "irradiance": h.tolist(),
            "irradiance_standard_error": h_se.tolist(),
            "irradiance_relative_standard_error": (h_se / h).tolist(),
        }
    check_params = dict(params, spp=1 << 18, passes=1, seeds=4)
    exact, mean, se = furnace_check(check_params, args.jobs)
    result = {
        "scene": "scenes/cornell/scene.toml",
        "quantity": "per object: mean radiosity B = pi L_e + rho H (W/m^2, RGB) and mean "
        "irradiance H over the object's faces, each with the standard error of the mean over "
        "independent seeds",
        "renderer": f"Mitsuba {mi.__version__}",
        "variant": args.variant,
        "integrator": "path (next-event estimation + MIS, Russian roulette)",
        "sensor": "irradiancemeter",
        "max_depth": args.max_depth,
        "rr_depth": args.rr_depth,
        "spp_per_seed": args.spp * args.passes,
        "seeds": args.seeds,
        "first_seed": args.seed,
        "date": datetime.date.today().isoformat(),
        "command": " ".join(["python3", "benches/cornell_reference.py", *sys.argv[1:]]),
        "self_check": {
            "case": "CIE 171 TC 5.8 integrating cube, rho = 0.5, mean irradiance "
            f"({check_params['seeds']} seeds x {check_params['spp']} spp per object)",
            "exact": exact,
            "measured": mean,
            "standard_error": se,
        },
        "objects": out,
    }
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
