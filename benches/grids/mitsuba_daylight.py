#!/usr/bin/env python3
"""Illuminance on the desk grid of the daylight room (`benches/grids/daylight_window.toml`),
measured by Mitsuba 3, against what `radiosity solve SCENE --grids DIR` wrote for it.

The room is read from the TOML with `tomllib` (every object a one-sided `polygon`, fanned into
triangles as in `benches/cornell_reference.py`, with a `diffuse` BSDF of the material's RGB
reflectance: Mitsuba's diffuse BSDF is black from the back, as our one-sided surfaces). The sky
is written here, independently of our code, as a latitude-longitude `envmap` bitmap from its
definition:

    cie-overcast:  L(Z) = L_z (1 + 2 cos Z) / 3  above the horizon (+y up), 0 below.

Mitsuba's envmap maps a direction d (+y up) to v = acos(d.y) / pi and interpolates linearly
between rows placed at v = j / (H - 1) (row 0 the zenith, row H - 1 the nadir; see
`direction_to_uv` and `eval_spectrum` in src/emitters/envmap.cpp). With H odd the middle row
lies exactly on the horizon; it holds half the horizon luminance so that the linear ramp into
the black ground loses above the horizon what it adds below. The sky is azimuthally uniform, so
the column convention does not matter.

Self-check first (JSON `sky_check`): an open meter facing up, and one facing +z, under the sky
alone must read E_h = 7 pi L_z / 9 and E_v = L_z (pi / 6 + 4 / 9).

At each grid point a square of side `--meter` (default 1 mm) facing +y carries an
`irradiancemeter` (as `benches/grids/mitsuba_grid.py`): all meters are in one scene (black,
one-sided, 1 mm^2 each, 0.25 m apart: their mutual shading is < 1e-4). The integrator is
`path` with `--max-depth` 64 and Russian roulette only from `--rr-depth` on (unbiased; the
paths it cuts carry a throughput below rho^rr_depth). Each point is rendered in passes of
`--spp` samples with independent seeds, at least `--min-passes` and until the standard error
of the mean (spread of the passes over sqrt(passes)) is below `--target` relative, at most
`--max-passes`. Lux is the Rec. 709 luminance of the RGB irradiance (the sky is white: every
channel is the same).

Points are measured in this order: the darkest and brightest point of our CSV, every
`--stride`-th point, then the others; no new point starts after `--budget` seconds, so the
JSON says which points were measured (`points`) and the summary is over those.

With `--mitsuba-from JSON` (an earlier output of this script) nothing is rendered: Mitsuba's
side (the sky check, each point's passes, mean and standard error, the timings) is taken from
that file, which must have measured the same points, and only our side is read again. Mitsuba's
numbers do not depend on our code, so this compares a changed engine against the same
reference without the half hour of rendering.

Usage:
    radiosity solve benches/grids/daylight_window.toml --grids /tmp/day
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
        python3 benches/grids/mitsuba_daylight.py /tmp/day/desk.csv \\
        > benches/figures/grid-daylight.json
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
import tomllib

import mitsuba as mi
import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from cornell_reference import write_obj  # noqa: E402

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def sky_bitmap(sky, width, height):
    """The sky's radiance as a latitude-longitude RGB bitmap in Mitsuba's envmap convention."""
    assert sky["type"] == "cie-overcast", "only the CIE overcast sky is written here"
    assert height % 2 == 1, "an odd height puts a row on the horizon"
    lz = float(sky["zenith_luminance"])
    theta = math.pi * np.arange(height) / (height - 1)  # row j at v = j / (H - 1)
    lum = lz * (1.0 + 2.0 * np.cos(theta)) / 3.0
    horizon = height // 2
    lum[horizon + 1 :] = 0.0
    lum[horizon] *= 0.5
    img = np.ascontiguousarray(np.broadcast_to(lum[:, None, None], (height, width, 3)))
    return mi.Bitmap(img.astype(np.float32)), lz


def meter(point, normal, side):
    """A one-sided black square of `side` centred on `point` facing `normal`, carrying an
    irradiance meter."""
    n = np.array(normal, dtype=float)
    n /= np.linalg.norm(n)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t = np.cross(n, helper)
    t /= np.linalg.norm(t)
    b = np.cross(n, t)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = t * side / 2, b * side / 2, n, point
    return {
        "type": "rectangle",  # [-1, 1]^2 in the xy plane facing +z
        "to_world": mi.ScalarTransform4f(m.tolist()),
        "bsdf": {"type": "diffuse", "reflectance": 0.0},
        "sensor": {
            "type": "irradiancemeter",
            "film": {
                "type": "hdrfilm",
                "width": 1,
                "height": 1,
                "pixel_format": "rgb",
                "rfilter": {"type": "box"},
            },
        },
    }


def room(data, directory, check_normals=True):
    """{name: Mitsuba shape} of the TOML's polygons; checks that they face into the room."""
    shapes = {}
    verts = np.array([v for o in data["objects"] for v in o["vertices"]], dtype=float)
    centre = 0.5 * (verts.min(axis=0) + verts.max(axis=0))
    for o in data["objects"]:
        assert o["shape"] == "polygon", "the daylight room is made of polygons"
        assert not o.get("two_sided", False), "one-sided surfaces only"
        poly = np.array(o["vertices"], dtype=float)
        if check_normals:
            for i in range(1, len(poly) - 1):
                n = np.cross(poly[i] - poly[0], poly[i + 1] - poly[0])
                assert n @ (centre - poly[0]) > 0, f"{o['name']} faces out of the room"
        filename = os.path.join(directory, f"{o['name']}.obj")
        write_obj(filename, [o["vertices"]])
        material = data["materials"][o["material"]]
        assert set(material) <= {"reflectance"}, f"{o['material']}: reflectance only"
        shapes[o["name"]] = {
            "type": "obj",
            "filename": filename,
            "face_normals": True,
            "bsdf": {"type": "diffuse",
                     "reflectance": {"type": "rgb", "value": material["reflectance"]}},
        }
    return shapes


def lux(img):
    return float(np.array(img, dtype=np.float64).reshape(-1)[:3] @ LUMINANCE)


def sky_check(bitmap, lz, args):
    """Open meters under the sky alone against the closed forms."""
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": args.max_depth, "rr_depth": args.rr_depth},
        "sky": {"type": "envmap", "bitmap": bitmap},
        "up": meter([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 1e-3),
        "south": meter([10.0, 0.0, 0.0], [0.0, 0.0, 1.0], 1e-3),
    }
    scene = mi.load_dict(d, optimize=False)
    out = {}
    for k, (name, exact) in enumerate([
        ("horizontal", 7.0 * math.pi * lz / 9.0),
        ("vertical", lz * (math.pi / 6.0 + 4.0 / 9.0)),
    ]):
        runs = np.array([lux(mi.render(scene, sensor=k, spp=1 << 20, seed=s)) for s in range(4)])
        out[name] = {
            "mitsuba_lux": runs.mean(),
            "standard_error": runs.std(ddof=1) / 2.0,
            "exact_lux": exact,
            "relative_error": runs.mean() / exact - 1.0,
        }
        print(f"sky check {name}: {runs.mean():.2f} lx, exact {exact:.2f} "
              f"({runs.mean() / exact - 1:+.5f})", file=sys.stderr)
    return out


def order(rows, stride):
    """Darkest and brightest of ours, every `stride`-th, then the rest."""
    lux_ours = [r[1] for r in rows]
    first = [int(np.argmin(lux_ours)), int(np.argmax(lux_ours))]
    first += [k for k in range(0, len(rows), stride) if k not in first]
    return first + [k for k in range(len(rows)) if k not in first]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv", help="the grid's CSV written by `radiosity --grids` (x,y,z,lux)")
    ap.add_argument("--scene", default=str(HERE / "daylight_window.toml"))
    ap.add_argument("--grids-json", help="our grids.json (default: next to the CSV)")
    ap.add_argument("--normal", default="0,1,0", help="the grid's normal (default up)")
    ap.add_argument("--meter", type=float, default=1e-3, help="meter square side, scene units")
    ap.add_argument("--spp", type=int, default=1 << 18, help="samples per pass")
    ap.add_argument("--min-passes", type=int, default=4)
    ap.add_argument("--max-passes", type=int, default=16)
    ap.add_argument("--target", type=float, default=0.004, help="relative standard error")
    ap.add_argument("--max-depth", type=int, default=64)
    ap.add_argument("--rr-depth", type=int, default=16)
    ap.add_argument("--stride", type=int, default=4)
    ap.add_argument("--budget", type=float, default=2400.0, help="seconds; no new point after")
    ap.add_argument("--sky-width", type=int, default=2048)
    ap.add_argument("--sky-height", type=int, default=1025)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--mitsuba-from", help="reuse Mitsuba's side of this earlier output")
    args = ap.parse_args()
    mi.set_variant(args.variant)
    start = time.time()
    with open(args.scene, "rb") as f:
        data = tomllib.load(f)
    normal = [float(x) for x in args.normal.split(",")]
    with open(args.csv) as f:
        rows = [(np.array([float(r["x"]), float(r["y"]), float(r["z"])]), float(r["lux"]))
                for r in csv.DictReader(f)]
    grids_json = args.grids_json or os.path.join(os.path.dirname(args.csv), "grids.json")
    ours_stats = None
    if os.path.exists(grids_json):
        with open(grids_json) as f:
            ours_stats = json.load(f)

    if args.mitsuba_from:
        with open(args.mitsuba_from) as f:
            earlier = json.load(f)
        print(json.dumps(reused(earlier, rows, normal, ours_stats, args), indent=1))
        return

    bitmap, lz = sky_bitmap(data["sky"], args.sky_width, args.sky_height)
    check = sky_check(bitmap, lz, args)

    directory = tempfile.mkdtemp()
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": args.max_depth, "rr_depth": args.rr_depth},
        "sky": {"type": "envmap", "bitmap": bitmap},
    }
    d.update(room(data, directory))
    for k, (p, _) in enumerate(rows):
        d[f"meter{k}"] = meter(p, normal, args.meter)
    # optimize=False: the loader would otherwise merge the identical sensors into one.
    scene = mi.load_dict(d, optimize=False)
    sensors = scene.sensors()
    assert len(sensors) == len(rows)

    points = []
    measure_start = time.time()
    for k in order(rows, args.stride):
        if time.time() - measure_start > args.budget:
            break
        p, ours = rows[k]
        t0 = time.time()
        runs = []
        while len(runs) < args.max_passes:
            runs.append(lux(mi.render(scene, sensor=k, spp=args.spp,
                                      seed=1_000_003 * (k + 1) + len(runs))))
            if len(runs) >= args.min_passes:
                r = np.array(runs)
                if r.std(ddof=1) / math.sqrt(len(r)) <= args.target * r.mean():
                    break
        runs = np.array(runs)
        theirs = runs.mean()
        se = runs.std(ddof=1) / math.sqrt(len(runs))
        points.append({
            "index": k,
            "position": p.tolist(),
            "ours_lux": ours,
            "mitsuba_lux": theirs,
            "mitsuba_standard_error": se,
            "mitsuba_relative_standard_error": se / theirs,
            "passes": len(runs),
            "relative_error": ours / theirs - 1.0,
            "seconds": time.time() - t0,
        })
        print(f"{len(points)}/{len(rows)} #{k} {p.round(3).tolist()}: ours {ours:.1f} "
              f"mitsuba {theirs:.1f} +- {se / theirs:.2%} ({len(runs)} passes) "
              f"err {ours / theirs - 1:+.2%}  {time.time() - t0:.1f} s", file=sys.stderr)
    measure_seconds = time.time() - measure_start

    points.sort(key=lambda q: q["index"])
    print(json.dumps({
        "scene": os.path.relpath(args.scene, HERE.parent.parent),
        "csv": os.path.basename(args.csv),
        "normal": normal,
        "ours_grids_json": ours_stats,
        "mitsuba": mi.__version__,
        "variant": args.variant,
        "integrator": {"type": "path", "max_depth": args.max_depth, "rr_depth": args.rr_depth},
        "sky_bitmap": [args.sky_width, args.sky_height],
        "meter_side": args.meter,
        "spp_per_pass": args.spp,
        "min_passes": args.min_passes,
        "max_passes": args.max_passes,
        "target_relative_standard_error": args.target,
        "stride": args.stride,
        "sky_check": check,
        "mitsuba_seconds": time.time() - start,
        "mitsuba_measure_seconds": measure_seconds,
        "summary": summarize(points, rows),
        "points": points,
    }, indent=1))


def reused(earlier, rows, normal, ours_stats, args):
    """The output of an earlier run with our side read again from `rows` (module docs)."""
    for key, value in [("csv", os.path.basename(args.csv)), ("normal", normal),
                       ("scene", os.path.relpath(args.scene, HERE.parent.parent))]:
        assert earlier[key] == value, f"--mitsuba-from measured another {key}: {earlier[key]}"
    points = []
    for q in earlier["points"]:
        p, ours = rows[q["index"]]
        assert np.allclose(p, q["position"], atol=1e-6), f"point {q['index']} moved"
        points.append(dict(q, ours_lux=ours, relative_error=ours / q["mitsuba_lux"] - 1.0))
    out = {k: v for k, v in earlier.items() if k != "ours"}
    out.update(ours_grids_json=ours_stats, summary=summarize(points, rows), points=points,
               mitsuba_from=os.path.basename(args.mitsuba_from))
    return out


def summarize(points, rows):
    """The errors over the measured points, and our statistics over all of them."""
    err = np.array([q["relative_error"] for q in points])
    worst = points[int(np.argmax(np.abs(err)))]
    m_lux = np.array([q["mitsuba_lux"] for q in points])
    o_lux = np.array([q["ours_lux"] for q in points])
    all_ours = np.array([r[1] for r in rows])
    summary = {
        "points_measured": len(points),
        "points_in_grid": len(rows),
        "all_points": len(points) == len(rows),
        "mean_relative_error": float(err.mean()),
        "rms_relative_error": float(np.sqrt(np.mean(err ** 2))),
        "worst": {k: worst[k] for k in ("index", "position", "ours_lux", "mitsuba_lux",
                                        "mitsuba_relative_standard_error", "relative_error")},
        "median_relative_standard_error": float(np.median(
            [q["mitsuba_relative_standard_error"] for q in points])),
        "max_relative_standard_error": float(np.max(
            [q["mitsuba_relative_standard_error"] for q in points])),
        "average_ours_lux_measured_points": float(o_lux.mean()),
        "average_mitsuba_lux_measured_points": float(m_lux.mean()),
        "average_relative_error": float(o_lux.mean() / m_lux.mean() - 1.0),
        "minimum_ours_lux_measured_points": float(o_lux.min()),
        "minimum_mitsuba_lux_measured_points": float(m_lux.min()),
        "minimum_relative_error": float(o_lux.min() / m_lux.min() - 1.0),
        "maximum_ours_lux_measured_points": float(o_lux.max()),
        "maximum_mitsuba_lux_measured_points": float(m_lux.max()),
        "maximum_relative_error": float(o_lux.max() / m_lux.max() - 1.0),
        "average_ours_lux_all_points": float(all_ours.mean()),
        "minimum_ours_lux_all_points": float(all_ours.min()),
        "maximum_ours_lux_all_points": float(all_ours.max()),
    }
    return summary


if __name__ == "__main__":
    main()
