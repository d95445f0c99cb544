#!/usr/bin/env python3
"""Illuminance on the floor grid of `benches/grids/point_room.toml` (a closed room lit by one
point light), measured by Mitsuba 3, against what `radiosity solve ... --grids DIR` wrote.

The room is written here with Mitsuba's own plugins, from the same numbers as the TOML: the
room a `cube` of two-sided diffuse ρ = 0.7, the table a `cube` of diffuse ρ = 0.5, the lamp a
`point` emitter of intensity 100 W/sr per channel (our white luminaire's candela fill the three
channels). At each point of the grid's CSV a black one-sided square of side `--meter` (1 mm)
facing up carries an `irradiancemeter` (the `path` integrator, 256 bounces); lux is the
Rec. 709 luminance of its irradiance, as ours. A meter's rays leave from the sensor, never a
surface, so the path tracer never samples the point light from it: the meter reads the
interreflected light alone, and the lamp's own light is added in closed form, I cos θ / r²
where Mitsuba's `ray_test` finds the segment to the lamp free. Each point is rendered
`--seeds` times with independent seeds: the value is the mean, its standard error the spread
over sqrt(seeds). Points inside the table (ours 0) are skipped.

Usage:
    radiosity solve benches/grids/point_room.toml --grids /tmp/lux
    python3 benches/grids/mitsuba_luminaire.py /tmp/lux/floor.csv > point_room.json
"""

import argparse
import csv
import json
import math
import sys
import time

import mitsuba as mi
import numpy as np

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
LAMP = np.array([2.0, 2.5, 2.0])
INTENSITY = 100.0


def cube(lo, hi, reflectance, two_sided):
    """A Mitsuba cube over the box [lo, hi] with a diffuse BSDF."""
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    diffuse = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [reflectance] * 3}}
    return {
        "type": "cube",
        "to_world": mi.ScalarTransform4f().translate(((lo + hi) / 2).tolist())
        @ mi.ScalarTransform4f().scale(((hi - lo) / 2).tolist()),
        "bsdf": {"type": "twosided", "bsdf": diffuse} if two_sided else diffuse,
    }


def meter(point, side):
    """A black square of `side` centred on `point`, facing up, carrying an irradiance meter."""
    return {
        "type": "rectangle",
        "to_world": mi.ScalarTransform4f().translate(list(point))
        @ mi.ScalarTransform4f().rotate([1, 0, 0], -90)
        @ mi.ScalarTransform4f().scale([side / 2, side / 2, 1]),
        "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.0] * 3}},
        "sensor": {
            "type": "irradiancemeter",
            "film": {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
        },
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv", help="the floor grid's CSV written by `radiosity solve --grids`")
    ap.add_argument("--meter", type=float, default=0.001, help="meter square side, m")
    ap.add_argument("--spp", type=int, default=1 << 16)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    args = ap.parse_args()
    mi.set_variant(args.variant)
    with open(args.csv) as f:
        rows = [(np.array([float(r["x"]), float(r["y"]), float(r["z"])]), float(r["lux"]))
                for r in csv.DictReader(f)]
    base = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 256, "rr_depth": 5},
        "room": cube([0, 0, 0], [4, 3, 4], 0.7, True),
        "table": cube([1.2, 0, 1.2], [2.4, 0.8, 2.0], 0.5, False),
        "lamp": {"type": "point", "position": LAMP.tolist(),
                 "intensity": {"type": "rgb", "value": [INTENSITY] * 3}},
    }
    points = []
    start = time.time()
    for k, (p, ours) in enumerate(rows):
        if ours == 0.0:
            continue
        scene = mi.load_dict(dict(base, meter=meter(p, args.meter)))
        runs = []
        for seed in range(args.seeds):
            img = mi.render(scene, spp=args.spp, seed=1_000_003 * (k + 1) + seed)
            runs.append(float(np.array(img, dtype=np.float64).reshape(-1)[:3] @ LUMINANCE))
        runs = np.array(runs)
        w = LAMP - p
        r = float(np.linalg.norm(w))
        ray = mi.Ray3f(mi.Point3f(*map(float, p)), mi.Vector3f(*map(float, w / r)))
        ray.maxt = r * (1 - 1e-6)
        free = not bool(np.array(scene.ray_test(ray)).reshape(-1)[0])
        direct = INTENSITY * (w[1] / r) / r ** 2 if free else 0.0
        theirs = runs.mean() + direct
        se = runs.std(ddof=1) / math.sqrt(len(runs))
        points.append({"point_m": p.tolist(), "ours_lux": ours, "mitsuba_lux": theirs,
                       "mitsuba_standard_error": se, "relative_error": ours / theirs - 1.0})
        print(f"{k}: ours {ours:.4f} mitsuba {theirs:.4f} +- {se:.4f}", file=sys.stderr)
    errors = np.array([q["relative_error"] for q in points])
    mean = lambda key: float(np.mean([q[key] for q in points]))  # noqa: E731
    print(json.dumps({
        "csv": args.csv,
        "mitsuba": mi.__version__,
        "variant": args.variant,
        "spp_per_seed": args.spp,
        "seeds": args.seeds,
        "seconds": time.time() - start,
        "average_ours_lux": mean("ours_lux"),
        "average_mitsuba_lux": mean("mitsuba_lux"),
        "average_relative_error": mean("ours_lux") / mean("mitsuba_lux") - 1.0,
        "rms_relative_error": float(np.sqrt(np.mean(errors ** 2))),
        "max_relative_error": float(np.max(np.abs(errors))),
        "median_standard_error": float(np.median(
            [q["mitsuba_standard_error"] / q["mitsuba_lux"] for q in points])),
        "points": points,
    }, indent=1))


if __name__ == "__main__":
    main()
