#!/usr/bin/env python3
"""Illuminance at the points of one of our calculation grids, measured by Mitsuba 3, against
what `radiosity solve SCENE --grids DIR` wrote for them.

The scene is the built-in Cornell box (`scenes/cornell/scene.toml`, read by
`benches/cornell_reference.py`, so geometry, reflectances and emission are exactly ours). At
each point of the grid's CSV a square of side `--meter` (default 1 mm) facing the grid's
normal carries Mitsuba's `irradiancemeter` (its mean incident irradiance, per RGB channel,
from the `path` integrator); the square is black and one-sided and faces away from nothing it
could shade but itself. Lux is the Rec. 709 luminance of the irradiance, as ours. Each point is
rendered `--seeds` times with independent seeds: the value is the mean, its standard error the
per-seed spread over sqrt(seeds).

Usage:
    radiosity solve benches/grids/cornell_floor.toml --grids /tmp/lux
    python3 benches/grids/mitsuba_grid.py /tmp/lux/floor.csv > benches/grids/cornell_floor.json
"""

import argparse
import csv
import json
import math
import os
import pathlib
import sys
import tempfile
import time

import mitsuba as mi
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from cornell_reference import MM_TO_M, cornell_shapes, scene_dict  # noqa: E402

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def meter_square(point, normal, side):
    """The corners of a square of `side` centred on `point`, counter-clockwise about `normal`."""
    n = np.array(normal, dtype=float)
    n /= np.linalg.norm(n)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t = np.cross(n, helper)
    t /= np.linalg.norm(t)
    b = np.cross(n, t)
    h = side / 2
    p = np.array(point, dtype=float)
    corners = ((-1, -1), (1, -1), (1, 1), (-1, 1))
    return [[float(c) for c in p + h * (s * t + u * b)] for s, u in corners]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv", help="a grid's CSV written by `radiosity --grids` (x,y,z,lux, mm)")
    ap.add_argument("--normal", default="0,1,0", help="the grid's normal (default up)")
    ap.add_argument("--meter", type=float, default=1.0, help="meter square side, mm")
    ap.add_argument("--spp", type=int, default=1 << 18)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    args = ap.parse_args()
    mi.set_variant(args.variant)
    normal = [float(x) for x in args.normal.split(",")]
    with open(args.csv) as f:
        rows = [(np.array([float(r["x"]), float(r["y"]), float(r["z"])]), float(r["lux"]))
                for r in csv.DictReader(f)]
    params = {"max_depth": 256, "rr_depth": 5, "spp": args.spp}
    shapes = cornell_shapes()
    points = []
    start = time.time()
    for k, (p, ours) in enumerate(rows):
        metered = f"meter{k}"
        square = meter_square(p * MM_TO_M, normal, args.meter * MM_TO_M)
        with_meter = dict(shapes, **{metered: ("meter", [0.0] * 3, [0.0] * 3, [square])})
        with tempfile.TemporaryDirectory() as directory:
            scene = mi.load_dict(scene_dict(with_meter, directory, metered, params))
            runs = []
            for seed in range(args.seeds):
                img = mi.render(scene, spp=args.spp, seed=1_000_003 * (k + 1) + seed)
                runs.append(float(np.array(img, dtype=np.float64).reshape(-1)[:3] @ LUMINANCE))
        runs = np.array(runs)
        theirs = runs.mean()
        se = runs.std(ddof=1) / math.sqrt(len(runs)) if len(runs) > 1 else float("nan")
        points.append({
            "point_mm": p.tolist(),
            "ours_lux": ours,
            "mitsuba_lux": theirs,
            "mitsuba_standard_error": se,
            "relative_error": ours / theirs - 1.0 if theirs > 0 else None,
        })
        print(f"{k}: ours {ours:.5f} mitsuba {theirs:.5f} +- {se:.5f}", file=sys.stderr)
    lit = [q for q in points if q["mitsuba_lux"] > 0.05 * max(x["mitsuba_lux"] for x in points)]
    errors = np.array([q["relative_error"] for q in lit])
    mean = lambda key: float(np.mean([q[key] for q in points]))  # noqa: E731
    print(json.dumps({
        "csv": os.path.basename(args.csv),
        "normal": normal,
        "mitsuba": mi.__version__,
        "variant": args.variant,
        "spp_per_seed": args.spp,
        "seeds": args.seeds,
        "seconds": time.time() - start,
        "average_ours_lux": mean("ours_lux"),
        "average_mitsuba_lux": mean("mitsuba_lux"),
        "average_relative_error": mean("ours_lux") / mean("mitsuba_lux") - 1.0,
        "rms_relative_error_lit_points": float(np.sqrt(np.mean(errors ** 2))),
        "max_relative_error_lit_points": float(np.max(np.abs(errors))),
        "points": points,
    }, indent=1))


if __name__ == "__main__":
    main()
