#!/usr/bin/env python3
"""Illuminance on the work plane of the built-in office (`scenes/office/scene.toml`: six LED
panels from `panel.ies`, a window under a CIE overcast sky, a desk), measured by Mitsuba 3,
against what `radiosity solve office --grids DIR` wrote for it.

The room is read from the TOML with `tomllib`: each `polygon` a one-sided triangle fan
(`write_obj` of `benches/cornell_reference.py`), the desk `box` a Mitsuba `cube`, both with a
`diffuse` BSDF of the material's RGB reflectance (black from the back, as our one-sided
surfaces). The sky is the envmap bitmap of `benches/grids/mitsuba_daylight.py` (its
`sky_check` runs first: open meters against E_h = 7 pi L_z / 9 and E_v).

Mitsuba 3 has no goniometric emitter, so the luminaires are written here as a Python plugin,
`PointSources` (`mi.Emitter` with the `DeltaPosition` flag): a set of points, each shining
I(gamma) times a scale, I read from the IES file by a reader of its own (LM-63 type C with one
horizontal angle: rotationally symmetric; the candela multiplier and ballast factor applied)
and interpolated linearly in gamma, the angle from the nadir (-y: the scene's luminaires keep
the default aim), zero above the last angle of the file. `sample_direction` picks one of the
N points uniformly (the first sample coordinate) and returns the weight N I(gamma) s / r^2
(the receiver's cosine is the integrator's): an unbiased estimate of the sum over the points.
Each `opening = true` luminaire is the 8 x 8 points at the cell centres of its luminous opening (length along
+x, width along the C90 axis; the panel's opening is square), each with 1/64 of the intensity
times the scene's `multiplier`: the model our scene format defines, not an approximation of it.
`--check` compares the plugin with Mitsuba's own `point` emitter (an isotropic table) on one
meter of a closed room: same sample streams, so the two must agree to rounding.

Light is linear, so the two emitters are measured apart, in two scenes holding the same room
and the same meters:

* luminaires: a meter never samples a delta emitter from the sensor itself, so the meter
  reads only their interreflected light (the path tracer's next-event estimation at surface
  bounces samples `PointSources`); their direct light is added in closed form, the sum over
  the 384 points of I cos theta / r^2 where Mitsuba's `ray_test` finds the segment free (in
  the room without meters);
* sky: the meter reads all of it, direct and interreflected.

At each grid point a black one-sided square of side `--meter` (1 mm) facing up carries an
`irradiancemeter` (`meter` of mitsuba_daylight.py); the integrator is `path` with
`--max-depth` 64 and Russian roulette from `--rr-depth`. Each part is rendered in passes of
its own `--spp-*` with independent seeds, `--min-passes` each, then one more pass at a time
for the part with the larger standard error until the standard error of the total (the
parts' in quadrature) is below `--target` of the total, at most `--max-passes` per part. Lux
is the Rec. 709 luminance of the RGB irradiance. Points are measured in the order and under
the `--budget` of mitsuba_daylight.py.

Our side: the CSV of the full office (with `grids.json` and, when `--stats` wrote it there,
`stats.json` beside it: our statistics and timings go into the JSON); `--ours-luminaires` and
`--ours-sky` optionally take the CSVs of the office without its `[sky]` and without its
luminaires (`--write-parts DIR` writes the two scenes), compared with Mitsuba's parts (`parts`
in the JSON). `--mitsuba-from JSON` reuses Mitsuba's side of an earlier output and reads only
ours again (a refined solve against the same reference).

Usage (from the repository's root, `radiosity` the release build):
    python3 benches/grids/mitsuba_office.py --write-parts /tmp/office-parts
    mkdir -p /tmp/office/full
    radiosity solve office --grids /tmp/office/full --stats /tmp/office/full/stats.json
    radiosity solve /tmp/office-parts/office-luminaires.toml --grids /tmp/office/luminaires
    radiosity solve /tmp/office-parts/office-sky.toml --grids /tmp/office/sky
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
        python3 benches/grids/mitsuba_office.py /tmp/office/full/work_plane.csv \\
        --ours-luminaires /tmp/office/luminaires/work_plane.csv \\
        --ours-sky /tmp/office/sky/work_plane.csv > benches/figures/grid-office.json
"""

import argparse
import csv
import json
import math
import os
import pathlib
import shutil
import sys
import tempfile
import time
import tomllib

import drjit as dr
import mitsuba as mi
import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))
from cornell_reference import write_obj  # noqa: E402
from mitsuba_daylight import lux, meter, order, sky_bitmap, sky_check  # noqa: E402

OPENING_SIDE = 8


def read_ies(path):
    """(gamma step in degrees, I at 0, step, 2 step, ... in cd, opening (length, width) in m) of
    a rotationally symmetric LM-63 type C file with evenly spaced vertical angles from 0."""
    lines = pathlib.Path(path).read_text().splitlines()
    tilt = next(i for i, line in enumerate(lines) if line.startswith("TILT="))
    assert lines[tilt].strip() == "TILT=NONE", "no tilt table"
    numbers = [float(x) for line in lines[tilt + 1:] for x in line.replace(",", " ").split()]
    _, _, multiplier, n_vert, n_horiz, kind, units, width, length, _ = numbers[:10]
    ballast, _, _ = numbers[10:13]
    n_vert, n_horiz = int(n_vert), int(n_horiz)
    assert kind == 1, "type C photometry"
    assert n_horiz == 1, "one horizontal angle: rotationally symmetric"
    gamma = np.array(numbers[13:13 + n_vert])
    values = np.array(numbers[13 + n_vert + n_horiz:13 + 2 * n_vert + n_horiz])
    assert len(values) == n_vert and len(numbers) == 13 + 2 * n_vert + n_horiz
    step = gamma[1] - gamma[0]
    assert gamma[0] == 0 and np.allclose(np.diff(gamma), step), "even steps from the nadir"
    metres = 1.0 if units == 2 else 0.3048
    assert width > 0 and length > 0, "a rectangular opening"
    return float(step), values * multiplier * ballast, (length * metres, width * metres)


def define_point_sources():
    """The `PointSources` emitter class (module docs); Mitsuba's classes exist once a variant
    is set."""

    class PointSources(mi.Emitter):
        """Points shining I(gamma) * scale each, gamma the angle from -y (module docs)."""

        def __init__(self, props, points, scale, table, step):
            super().__init__(props)
            self.m_flags = mi.EmitterFlags.DeltaPosition
            pts = np.asarray(points, dtype=np.float64)
            self.n = len(pts)
            self.p = mi.Point3f(*(mi.Float(pts[:, i]) for i in range(3)))
            self.table = mi.Float(np.asarray(table, dtype=np.float64))
            self.m = len(table)
            self.step = float(step)
            self.scale = float(scale)
            self.bounds = (pts.min(axis=0).tolist(), pts.max(axis=0).tolist())

        def intensity(self, cos_gamma):
            """I at the angle of cosine `cos_gamma` from the nadir, linear between table rows."""
            g = dr.acos(dr.clip(cos_gamma, -1.0, 1.0)) * (180.0 / math.pi) / self.step
            j = dr.minimum(mi.UInt32(dr.floor(g)), self.m - 2)
            t = g - mi.Float(j)
            i = dr.lerp(dr.gather(mi.Float, self.table, j),
                        dr.gather(mi.Float, self.table, j + 1), t)
            return dr.select(g <= self.m - 1, i, 0.0)

        def sample_direction(self, it, sample, active=True):
            # One point, uniformly; the weight N I s / r^2 estimates the sum over all of them.
            idx = dr.minimum(mi.UInt32(sample.x * self.n), self.n - 1)
            p = dr.gather(mi.Point3f, self.p, idx, active)
            d = p - it.p
            dist2 = dr.squared_norm(d)
            dist = dr.sqrt(dist2)
            d = d / dist
            ds = dr.zeros(mi.DirectionSample3f)
            ds.p = p
            ds.n = mi.Normal3f(0.0)
            ds.uv = mi.Point2f(0.0)
            ds.time = it.time
            ds.pdf = mi.Float(1.0)
            ds.delta = mi.Bool(True)
            ds.emitter = mi.EmitterPtr(self)
            ds.d = d
            ds.dist = dist
            # d points from the surface to the lamp: cos gamma = (-d) . (-y) = d.y.
            w = self.intensity(d.y) * (self.scale * self.n) / dist2
            return ds, mi.Spectrum(dr.select(active, w, 0.0))

        def pdf_direction(self, it, ds, active=True):
            return mi.Float(0.0)

        def eval_direction(self, it, ds, active=True):
            w = self.intensity(ds.d.y) * self.scale / dr.square(ds.dist)
            return mi.Spectrum(dr.select(active, w, 0.0))

        def eval(self, si, active=True):
            return mi.Spectrum(0.0)

        def bbox(self):
            return mi.ScalarBoundingBox3f(*self.bounds)

        def to_string(self):
            return f"PointSources[{self.n} points]"

    return PointSources


def opening_points(position, length, width):
    """The 8 x 8 cell centres of a `length` (x) by `width` (z) opening about `position`."""
    c = (np.arange(OPENING_SIDE) + 0.5) / OPENING_SIDE * 2.0 - 1.0
    return [np.array(position, dtype=float) + [0.5 * length * u, 0.0, 0.5 * width * v]
            for v in c for u in c]


def diffuse(reflectance):
    value = reflectance if isinstance(reflectance, list) else [float(reflectance)] * 3
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": value}}


def office(data, scene_dir, directory):
    """({name: Mitsuba shape}, luminaire source points, their common scale, gamma table, step)
    of the scene description (module docs)."""
    shapes, points, luminaire = {}, [], None
    for k, o in enumerate(data["objects"]):
        assert not o.get("transform") and not o.get("two_sided", False), o["name"]
        if o["shape"] == "luminaire":
            assert o.get("aim", [0.0, -1.0, 0.0]) == [0.0, -1.0, 0.0] and not o.get("rotation")
            assert o.get("opening", False) and "colour" not in o
            ies = read_ies(scene_dir / o["file"])
            assert luminaire is None or luminaire == (o["file"], o.get("multiplier", 1.0))
            luminaire = (o["file"], o.get("multiplier", 1.0))
            points += opening_points(o["position"], *ies[2])
            continue
        material = data["materials"][o["material"]]
        assert set(material) <= {"reflectance"}, f"{o['material']}: reflectance only"
        if o["shape"] == "polygon":
            filename = os.path.join(directory, f"{k}-{o['name']}.obj")
            write_obj(filename, [o["vertices"]])
            shape = {"type": "obj", "filename": filename, "face_normals": True}
        elif o["shape"] == "box":
            lo, hi = np.array(o["min"], dtype=float), np.array(o["max"], dtype=float)
            shape = {"type": "cube",
                     "to_world": mi.ScalarTransform4f().translate(((lo + hi) / 2).tolist())
                     @ mi.ScalarTransform4f().scale(((hi - lo) / 2).tolist())}
        else:
            raise AssertionError(f"{o['name']}: shape {o['shape']} not written here")
        shapes[f"{k}-{o['name']}"] = dict(shape, bsdf=diffuse(material["reflectance"]))
    step, table, _ = read_ies(scene_dir / luminaire[0])
    return shapes, np.array(points), luminaire[1] / OPENING_SIDE ** 2, table, step


def direct(scene, points, grid, emitter):
    """The luminaires' direct light at each grid point (facing up), shadowed by `scene`."""
    p = np.repeat(grid, len(points), axis=0)
    w = np.tile(points, (len(grid), 1)) - p
    r = np.linalg.norm(w, axis=1)
    w /= r[:, None]
    ray = mi.Ray3f(mi.Point3f(*(mi.Float(p[:, i]) for i in range(3))),
                   mi.Vector3f(*(mi.Float(w[:, i]) for i in range(3))))
    ray.maxt = mi.Float(r * (1.0 - 1e-6))
    free = ~np.array(scene.ray_test(ray), dtype=bool)
    intensity = np.array(emitter.intensity(mi.Float(w[:, 1])), dtype=np.float64)
    e = np.where(free & (w[:, 1] > 0), intensity * emitter.scale * w[:, 1] / r ** 2, 0.0)
    return e.reshape(len(grid), len(points)).sum(axis=1), int((~free).sum())


def check_plugin(args):
    """PointSources with an isotropic table against Mitsuba's `point`, one meter (docs)."""
    lamp = [2.0, 2.5, 2.0]
    mi.register_emitter("iso_check", lambda props: PointSources(props, [lamp], 100.0,
                                                                [1.0] * 37, 5.0))
    out = {}
    for name, emitter in [("point", {"type": "point", "position": lamp,
                                     "intensity": {"type": "rgb", "value": [100.0] * 3}}),
                          ("PointSources", {"type": "iso_check"})]:
        box = {"type": "cube",
               "to_world": mi.ScalarTransform4f().translate([2.0, 1.5, 2.0])
               @ mi.ScalarTransform4f().scale([2.0, 1.5, 2.0]),
               "bsdf": {"type": "twosided", "bsdf": diffuse(0.7)}}
        scene = mi.load_dict({"type": "scene", "integrator": {"type": "path",
                              "max_depth": args.max_depth, "rr_depth": args.rr_depth},
                              "room": box, "lamp": emitter,
                              "meter": meter([0.8, 0.01, 0.8], [0.0, 1.0, 0.0], 1e-3)})
        out[name] = lux(mi.render(scene, spp=1 << 16, seed=7))
    out["relative_difference"] = out["PointSources"] / out["point"] - 1.0
    print(f"plugin check: point {out['point']:.5f} PointSources {out['PointSources']:.5f}",
          file=sys.stderr)
    assert abs(out["relative_difference"]) < 1e-4, out
    return out


def read_csv(path):
    with open(path) as f:
        return [(np.array([float(r["x"]), float(r["y"]), float(r["z"])]), float(r["lux"]))
                for r in csv.DictReader(f)]


def write_parts(scene, directory):
    """The office without its `[sky]` and without its luminaires, as two TOML files beside
    copies of the photometric files, for `--ours-luminaires` and `--ours-sky`."""
    scene, directory = pathlib.Path(scene), pathlib.Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    text = scene.read_text()
    head, *objects = text.split("[[objects]]\n")
    sky = head + "".join("[[objects]]\n" + o for o in objects
                         if 'shape = "luminaire"' not in o)
    lines = text.split("\n")
    k = lines.index("[sky]")
    end = next(i for i in range(k + 1, len(lines)) if not lines[i] or lines[i][0] == "[")
    luminaires = "\n".join(lines[:k] + lines[end:])
    assert "[sky]" not in luminaires and 'shape = "luminaire"' not in sky
    (directory / "office-luminaires.toml").write_text(luminaires)
    (directory / "office-sky.toml").write_text(sky)
    with open(scene, "rb") as f:
        files = {o["file"] for o in tomllib.load(f)["objects"] if "file" in o}
    for name in files:
        shutil.copy(scene.parent / name, directory / name)


def read_json(path):
    """The JSON file at `path`, or None when there is none."""
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv", nargs="?",
                    help="the office's work_plane.csv from `radiosity solve --grids`")
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "office" / "scene.toml"))
    ap.add_argument("--ours-luminaires", help="work_plane.csv of the office without [sky]")
    ap.add_argument("--ours-sky", help="work_plane.csv of the office without luminaires")
    ap.add_argument("--ours-note", default="", help="how our CSVs were made (into the JSON)")
    ap.add_argument("--meter", type=float, default=1e-3, help="meter square side, m")
    ap.add_argument("--spp-luminaires", type=int, default=1 << 16, help="samples per pass")
    ap.add_argument("--spp-sky", type=int, default=1 << 17, help="samples per pass")
    ap.add_argument("--min-passes", type=int, default=4)
    ap.add_argument("--max-passes", type=int, default=16)
    ap.add_argument("--target", type=float, default=0.003, help="relative standard error")
    ap.add_argument("--max-depth", type=int, default=64)
    ap.add_argument("--rr-depth", type=int, default=5)
    ap.add_argument("--stride", type=int, default=4)
    ap.add_argument("--budget", type=float, default=3000.0, help="seconds; no new point after")
    ap.add_argument("--sky-width", type=int, default=2048)
    ap.add_argument("--sky-height", type=int, default=1025)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--mitsuba-from", help="reuse Mitsuba's side of this earlier output")
    ap.add_argument("--check", action="store_true", help="only the plugin check")
    ap.add_argument("--write-parts", metavar="DIR",
                    help="only write the office without sky and without luminaires into DIR")
    args = ap.parse_args()
    if args.write_parts:
        write_parts(args.scene, args.write_parts)
        return
    if args.csv is None and not args.check:
        ap.error("the office's work_plane.csv is required")
    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    global PointSources
    PointSources = define_point_sources()
    start = time.time()
    if args.check:
        print(json.dumps(check_plugin(args), indent=1))
        return
    rows = read_csv(args.csv)
    parts_ours = {name: read_csv(path) if path else None
                  for name, path in [("luminaires", args.ours_luminaires),
                                     ("sky", args.ours_sky)]}
    for name, part in parts_ours.items():
        assert part is None or all(np.allclose(a[0], b[0]) for a, b in zip(part, rows)), name
    beside = os.path.dirname(args.csv)
    ours_stats = read_json(os.path.join(beside, "grids.json"))
    ours_timings = (read_json(os.path.join(beside, "stats.json")) or {}).get("timings")

    if args.mitsuba_from:
        with open(args.mitsuba_from) as f:
            earlier = json.load(f)
        assert earlier["scene"] == os.path.relpath(args.scene, ROOT)
        points = [dict(q) for q in earlier["points"]]
        out = {k: v for k, v in earlier.items() if k not in ("summary", "parts", "points")}
        out["mitsuba_from"] = os.path.basename(args.mitsuba_from)
    else:
        points, out = measure(args, rows, start)
    for q in points:
        p, ours = rows[q["index"]]
        assert np.allclose(p, q["position"], atol=1e-6), f"point {q['index']} moved"
        q["ours_lux"] = ours
        q["relative_error"] = ours / q["mitsuba_lux"] - 1.0
        for name, part in parts_ours.items():
            if part is not None:
                q[f"ours_{name}_lux"] = part[q["index"]][1]
    out.update(csv=os.path.basename(args.csv), ours_grids_json=ours_stats,
               ours_timings=ours_timings, ours_note=args.ours_note, summary=summarize(points, rows),
               parts=parts(points, parts_ours), points=points)
    print(json.dumps(out, indent=1))


def measure(args, rows, start):
    """Mitsuba's side: the sky check, then every point's parts (module docs)."""
    scene_path = pathlib.Path(args.scene)
    with open(scene_path, "rb") as f:
        data = tomllib.load(f)
    plugin = check_plugin(args)
    bitmap, lz = sky_bitmap(data["sky"], args.sky_width, args.sky_height)
    check = sky_check(bitmap, lz, args)

    directory = tempfile.mkdtemp()
    shapes, sources, scale, table, step = office(data, scene_path.parent, directory)
    mi.register_emitter("office_luminaires",
                        lambda props: PointSources(props, sources, scale, table, step))
    integrator = {"type": "path", "max_depth": args.max_depth, "rr_depth": args.rr_depth}
    room = mi.load_dict(dict(shapes, type="scene"))
    grid = np.array([p for p, _ in rows])
    emitter = PointSources(mi.Properties(), sources, scale, table, step)
    # The plugin's table lookup is np.interp's linear interpolation in gamma.
    gamma = np.linspace(0.0, 180.0, 7201)
    plugin_i = np.array(emitter.intensity(mi.Float(np.cos(np.radians(gamma)))))
    angles = step * np.arange(len(table))
    expected = np.where(gamma <= angles[-1], np.interp(gamma, angles, table), 0.0)
    assert np.max(np.abs(plugin_i - expected)) < 1e-3 * table.max(), "table lookup"
    direct_lux, blocked = direct(room, sources, grid, emitter)
    meters = {f"meter{k}": meter(p, [0.0, 1.0, 0.0], args.meter) for k, (p, _) in enumerate(rows)}
    # optimize=False: the loader would otherwise merge the identical sensors into one.
    scenes = {
        "luminaires": mi.load_dict(dict(shapes, **meters, type="scene", integrator=integrator,
                                        lamps={"type": "office_luminaires"}), optimize=False),
        "sky": mi.load_dict(dict(shapes, **meters, type="scene", integrator=integrator,
                                 sky={"type": "envmap", "bitmap": bitmap}), optimize=False),
    }
    spp = {"luminaires": args.spp_luminaires, "sky": args.spp_sky}
    seed_offset = {"luminaires": 0, "sky": 500_000}

    points = []
    measure_start = time.time()
    for k in order(rows, args.stride):
        if time.time() - measure_start > args.budget:
            break
        p, ours = rows[k]
        t0 = time.time()
        runs = {name: [] for name in scenes}

        def render(name):
            seed = 1_000_003 * (k + 1) + seed_offset[name] + len(runs[name])
            runs[name].append(lux(mi.render(scenes[name], sensor=k, spp=spp[name], seed=seed)))

        def stats(name):
            r = np.array(runs[name])
            return r.mean(), r.std(ddof=1) / math.sqrt(len(r))

        for name in scenes:
            for _ in range(args.min_passes):
                render(name)
        while True:
            (ml, sl), (ms, ss) = stats("luminaires"), stats("sky")
            total = direct_lux[k] + ml + ms
            if math.hypot(sl, ss) <= args.target * total:
                break
            name = "luminaires" if sl > ss else "sky"
            if len(runs[name]) >= args.max_passes:
                name = "sky" if name == "luminaires" else "luminaires"
                if len(runs[name]) >= args.max_passes:
                    break
            render(name)
        se = math.hypot(sl, ss)
        points.append({
            "index": k,
            "position": p.tolist(),
            "mitsuba_lux": total,
            "mitsuba_standard_error": se,
            "mitsuba_relative_standard_error": se / total,
            "luminaires_direct_lux": float(direct_lux[k]),
            "luminaires_indirect_lux": ml,
            "luminaires_indirect_standard_error": sl,
            "sky_lux": ms,
            "sky_standard_error": ss,
            "passes": {name: len(r) for name, r in runs.items()},
            "seconds": time.time() - t0,
        })
        print(f"{len(points)}/{len(rows)} #{k} {p.round(3).tolist()}: ours {ours:.1f} "
              f"mitsuba {total:.1f} +- {se / total:.2%} (direct {direct_lux[k]:.1f}, "
              f"indirect {ml:.1f}, sky {ms:.1f}; passes {len(runs['luminaires'])}+"
              f"{len(runs['sky'])}) err {ours / total - 1:+.2%}  {time.time() - t0:.1f} s",
              file=sys.stderr)
    points.sort(key=lambda q: q["index"])
    return points, {
        "scene": os.path.relpath(args.scene, ROOT),
        "mitsuba": mi.__version__,
        "variant": args.variant,
        "threads": args.threads,
        "integrator": {"type": "path", "max_depth": args.max_depth, "rr_depth": args.rr_depth},
        "sky_bitmap": [args.sky_width, args.sky_height],
        "luminaire_points": len(sources),
        "luminaire_point_scale": scale,
        "direct_segments_blocked": blocked,
        "meter_side": args.meter,
        "spp_per_pass": spp,
        "min_passes": args.min_passes,
        "max_passes": args.max_passes,
        "target_relative_standard_error": args.target,
        "stride": args.stride,
        "plugin_check": plugin,
        "sky_check": check,
        "mitsuba_seconds": time.time() - start,
        "mitsuba_measure_seconds": time.time() - measure_start,
    }


def summarize(points, rows):
    """The errors over the measured points, and our statistics over all of them."""
    err = np.array([q["relative_error"] for q in points])
    worst = points[int(np.argmax(np.abs(err)))]
    m_lux = np.array([q["mitsuba_lux"] for q in points])
    o_lux = np.array([q["ours_lux"] for q in points])
    all_ours = np.array([r[1] for r in rows])
    rse = [q["mitsuba_relative_standard_error"] for q in points]
    return {
        "points_measured": len(points),
        "points_in_grid": len(rows),
        "mean_relative_error": float(err.mean()),
        "rms_relative_error": float(np.sqrt(np.mean(err ** 2))),
        "worst": {k: worst[k] for k in ("index", "position", "ours_lux", "mitsuba_lux",
                                        "mitsuba_relative_standard_error", "relative_error")},
        "median_relative_standard_error": float(np.median(rse)),
        "max_relative_standard_error": float(np.max(rse)),
        "average_ours_lux": float(o_lux.mean()),
        "average_mitsuba_lux": float(m_lux.mean()),
        "average_relative_error": float(o_lux.mean() / m_lux.mean() - 1.0),
        "minimum_relative_error": float(o_lux.min() / m_lux.min() - 1.0),
        "maximum_relative_error": float(o_lux.max() / m_lux.max() - 1.0),
        "uniformity_ours": float(o_lux.min() / o_lux.mean()),
        "uniformity_mitsuba": float(m_lux.min() / m_lux.mean()),
        "average_ours_lux_all_points": float(all_ours.mean()),
    }


def parts(points, parts_ours):
    """Ours without the sky and without the luminaires against Mitsuba's parts: the
    luminaires' total, their interreflected light alone (ours minus the closed-form direct),
    the sky's total, and the sum of our two parts against our full office (linearity)."""
    out = {}

    def compare(name, ours, theirs, se):
        ours, theirs, se = np.array(ours), np.array(theirs), np.array(se)
        err = ours / theirs - 1.0
        out[name] = {
            "average_ours_lux": float(ours.mean()),
            "average_mitsuba_lux": float(theirs.mean()),
            "average_relative_error": float(ours.mean() / theirs.mean() - 1.0),
            "rms_relative_error": float(np.sqrt(np.mean(err ** 2))),
            "worst_relative_error": float(err[np.argmax(np.abs(err))]),
            "median_relative_standard_error": float(np.median(se / theirs)),
        }

    direct_lux = [q["luminaires_direct_lux"] for q in points]
    indirect = [q["luminaires_indirect_lux"] for q in points]
    indirect_se = [q["luminaires_indirect_standard_error"] for q in points]
    if parts_ours["luminaires"] is not None:
        ours = [q["ours_luminaires_lux"] for q in points]
        compare("luminaires", ours, np.add(direct_lux, indirect), indirect_se)
        compare("luminaires_indirect", np.subtract(ours, direct_lux), indirect, indirect_se)
    if parts_ours["sky"] is not None:
        compare("sky", [q["ours_sky_lux"] for q in points], [q["sky_lux"] for q in points],
                [q["sky_standard_error"] for q in points])
    if all(part is not None for part in parts_ours.values()):
        total = np.array([q["ours_luminaires_lux"] + q["ours_sky_lux"] for q in points])
        full = np.array([q["ours_lux"] for q in points])
        out["ours_parts_sum_vs_full"] = {
            "average_relative_difference": float(total.mean() / full.mean() - 1.0),
            "worst_relative_difference": float(np.max(np.abs(total / full - 1.0))),
        }
    return out


if __name__ == "__main__":
    main()
