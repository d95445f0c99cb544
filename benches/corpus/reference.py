#!/usr/bin/env python3
"""Mitsuba 3 references for the published scenes of the corpus, every BSDF made diffuse.

For one scene folder of the corpus (`scene_mi3.xml` if present, else `scene.xml`), this script
writes a *diffuse variant* of the file into an output folder (the corpus is never modified):
every BSDF replaced by the diffuse approximation below, the integrator `path` (max_depth 256,
rr_depth 5, nothing hidden), a box pixel filter of one pixel, the film `--width` wide at the
film's aspect ratio. Emitters, shapes, transforms and the camera are kept. It then renders the
variant in independent passes (seeds SEED, SEED + 1000, ...), measures the reference's own
noise from two half-sets of passes, and writes `<scene>.exr` (half float) and `<scene>.json`.

The diffuse approximation (the contract our Mitsuba reader implements too; `approximate`):

- `diffuse`, `roughdiffuse`: rho = `reflectance` (default 0.5);
- `twosided`: the nested BSDF's approximation, two-sided;
- `plastic`, `roughplastic`, `pplastic`: rho = `diffuse_reflectance` (default 0.5);
- `conductor`, `roughconductor`: rho = `specular_reflectance` (default 1) x R0(`material`)
  (table `R0`: none 1; Ag, Al, Au, Cu, Cr, Fe; any other name or explicit eta/k 0.9 grey),
  at most 0.99;
- `dielectric`, `thindielectric`, `roughdielectric`, `null`: transparent: Mitsuba's `null`;
- `mask`, `bumpmap`, `normalmap`, `coating`, `roughcoating`: the nested BSDF's approximation;
- `blendbsdf`: (1 - w) rho0 + w rho1, w = `weight`;
- `principled`, `principledthin`: rho = `base_color` (default 0.5);
- any other BSDF: 0.5 grey.

A value is rgb, or a float/spectrum (grey), or a texture: `bitmap` -> the image's mean in linear
RGB (Mitsuba's Bitmap, sRGB-decoded unless `raw`), `checkerboard` -> mean of color0 and color1.
Every reflectance is clamped to [0, 0.99]. A `sunsky` emitter is replaced by an `envmap` of
`--environment FILE` when given; without it the scene is reported as "needs environment" and
not rendered.

Usage (LLVM back end: apt-get install libllvm19;
DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1):
    python3 benches/corpus/reference.py CORPUS/cornell-box --spp 1024 --passes 8
    python3 benches/corpus/reference.py CORPUS/cornell-box --ladder-only
    python3 benches/corpus/reference.py CORPUS/cornell-box --variant-only
    python3 benches/corpus/reference.py --time-to-error 0.02 benches/corpus/reference/cornell-box.json
benches/corpus/README.md describes the committed references.
"""

import argparse
import collections
import importlib.util
import json
import math
import os
import pathlib
import re
import sys
import time
import xml.etree.ElementTree as ET

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "image"))
try:
    import numpy as np
    import error as image_error  # benches/image/error.py (imports mitsuba)
except ImportError:  # --time-to-error needs neither
    np = image_error = None

DEFAULT_OUT = HERE / "reference"

# Normal-incidence reflectance (linear RGB) of a conductor's `material`.
R0 = {
    "none": (1.0, 1.0, 1.0),
    "Ag": (0.95, 0.93, 0.88),
    "Al": (0.91, 0.92, 0.92),
    "Au": (1.00, 0.71, 0.29),
    "Cu": (0.95, 0.64, 0.54),
    "Cr": (0.55, 0.56, 0.55),
    "Fe": (0.56, 0.57, 0.58),
}
R0_OTHER = (0.9, 0.9, 0.9)  # any other material name, or explicit eta/k
RHO_MAX = 0.99
DEFAULT_RHO = (0.5, 0.5, 0.5)

DIFFUSE = {"diffuse", "roughdiffuse"}
PLASTIC = {"plastic", "roughplastic", "pplastic"}
CONDUCTOR = {"conductor", "roughconductor"}
TRANSPARENT = {"dielectric", "thindielectric", "roughdielectric", "null"}
WRAPPER = {"mask", "bumpmap", "normalmap", "coating", "roughcoating"}
PRINCIPLED = {"principled", "principledthin"}
ANTICIPATED_BSDF = DIFFUSE | PLASTIC | CONDUCTOR | TRANSPARENT | WRAPPER | PRINCIPLED | {
    "twosided", "blendbsdf"}
ANTICIPATED = {
    "bsdf": ANTICIPATED_BSDF,
    "texture": {"bitmap", "checkerboard"},
    "emitter": {"area", "constant", "envmap", "sunsky"},
    "shape": {"obj", "ply", "rectangle", "cube", "disk", "sphere", "cylinder", "shapegroup",
              "instance"},
}
# Parameters of anticipated plugins that the approximation reads or knowingly ignores.
KNOWN_PARAMS = {
    "diffuse": {"reflectance"}, "roughdiffuse": {"reflectance", "alpha", "use_fast_approx"},
    "bitmap": {"filename", "filter_type", "wrap_mode", "raw", "to_uv", "format"},
    "checkerboard": {"color0", "color1", "to_uv"},
}


def snake(name):
    """Mitsuba 3's upgrade of a 0.x parameter name: camelCase -> snake_case."""
    return re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", name).lower() if name else name


class Mapper:
    """Reads one scene file and maps its BSDFs (`approximate`), recording what it met."""

    def __init__(self, path):
        self.path = pathlib.Path(path).resolve()
        self.dir = self.path.parent
        self.tree = ET.parse(self.path)
        self.root = self.tree.getroot()
        self.defaults = {d.get("name"): d.get("value") for d in self.root.iter("default")}
        self.ids = {}
        for e in self.root.iter():
            if e.get("id") is not None and e.tag != "ref":
                self.ids[e.get("id")] = e
        self.met = {k: collections.Counter() for k in ANTICIPATED}
        self.notes = []
        for e in self.root.iter():
            if e.tag in self.met and e.get("type") is not None:
                self.met[e.tag][self.resolve(e.get("type"))] += 1
        for kind, types in self.met.items():
            for t in types:
                if t not in ANTICIPATED[kind]:
                    self.note(f"{kind} type `{t}` not anticipated by the mapping")
        self.means = {}

    def note(self, text):
        if text not in self.notes:
            self.notes.append(text)

    def resolve(self, value):
        """A value with `$name` references replaced by their <default> values."""
        if value is None:
            return None
        return re.sub(r"\$(\w+)", lambda m: self.defaults.get(m.group(1), m.group(0)), value)

    def deref(self, e):
        while e is not None and e.tag == "ref":
            e = self.ids.get(e.get("id"))
        return e

    def param(self, e, name):
        """The child of plugin `e` that sets parameter `name` (0.x camelCase names too)."""
        for c in e:
            if snake(c.get("name")) == name:
                return c
        return None

    # Values ----------------------------------------------------------------------------------

    def value(self, e, default, where):
        """The mean linear RGB of a parameter element (rgb, float, spectrum, texture, ref)."""
        if e is None:
            return tuple(default)
        e = self.deref(e)
        if e is None:
            self.note(f"{where}: dangling ref; default used")
            return tuple(default)
        if e.tag == "rgb":
            v = [float(x) for x in re.split(r"[,\s]+", self.resolve(e.get("value")).strip())]
            return tuple(v * 3) if len(v) == 1 else tuple(v[:3])
        if e.tag == "float":
            return (float(self.resolve(e.get("value"))),) * 3
        if e.tag == "spectrum":
            text = self.resolve(e.get("value", "")).strip()
            if ":" in text:
                vals = [float(p.split(":")[1]) for p in re.split(r"[,\s]+", text) if p]
                self.note(f"{where}: spectrum given per wavelength: mean of its values, as grey")
                return (float(np.mean(vals)),) * 3
            if e.get("filename") or not text:
                self.note(f"{where}: spectrum from a file: default used")
                return tuple(default)
            return (float(text),) * 3
        if e.tag == "texture":
            return self.texture_mean(e, where)
        self.note(f"{where}: a `{e.tag}` value is not anticipated: default used")
        return tuple(default)

    def texture_mean(self, e, where):
        t = self.resolve(e.get("type"))
        for c in e:
            n = snake(c.get("name"))
            if n is not None and n not in KNOWN_PARAMS.get(t, set()):
                self.note(f"{t} texture parameter `{n}` ignored")
        if t == "checkerboard":
            c0 = self.value(self.param(e, "color0"), (0.4,) * 3, where)
            c1 = self.value(self.param(e, "color1"), (0.2,) * 3, where)
            return tuple((a + b) / 2 for a, b in zip(c0, c1))
        if t == "bitmap":
            name = self.resolve(self.param(e, "filename").get("value"))
            raw_e = self.param(e, "raw")
            raw = raw_e is not None and self.resolve(raw_e.get("value")).lower() == "true"
            key = (name, raw)
            if key not in self.means:
                self.means[key] = bitmap_mean(self.dir / name, raw)
            return self.means[key]
        self.note(f"{where}: texture `{t}`: no mean defined by the mapping, 0.5 grey used")
        return DEFAULT_RHO

    # BSDFs -----------------------------------------------------------------------------------

    def approximate(self, e):
        """(kind, rho, two_sided, chain) of a BSDF element: kind "diffuse" or "null"."""
        e = self.deref(e)
        t = self.resolve(e.get("type"))
        where = f"bsdf {e.get('id') or ''} ({t})".replace("  ", " ")
        nested = [self.deref(c) for c in e if c.tag == "bsdf" or (
            c.tag == "ref" and self.deref(c) is not None and self.deref(c).tag == "bsdf")]
        if t in DIFFUSE:
            return self.diffuse(self.value(self.param(e, "reflectance"), DEFAULT_RHO, where),
                                False, [t])
        if t in PLASTIC:
            return self.diffuse(self.value(self.param(e, "diffuse_reflectance"), DEFAULT_RHO,
                                           where), False, [t])
        if t in CONDUCTOR:
            spec = self.value(self.param(e, "specular_reflectance"), (1.0,) * 3, where)
            m = self.param(e, "material")
            if self.param(e, "eta") is not None or self.param(e, "k") is not None:
                r0 = R0_OTHER
            elif m is None:
                r0 = R0["none"]
            else:
                r0 = R0.get(self.resolve(m.get("value")), R0_OTHER)
            return self.diffuse(tuple(min(a * b, RHO_MAX) for a, b in zip(spec, r0)), False,
                                [t])
        if t in TRANSPARENT:
            return ("null", None, False, [t])
        if t in PRINCIPLED:
            return self.diffuse(self.value(self.param(e, "base_color"), DEFAULT_RHO, where),
                                False, [t])
        if t == "twosided" or t in WRAPPER:
            if not nested:
                self.note(f"{where}: no nested BSDF: 0.5 grey")
                return self.diffuse(DEFAULT_RHO, t == "twosided", [t])
            if len(nested) > 1:
                self.note(f"{where}: {len(nested)} nested BSDFs: the first one's approximation")
            kind, rho, two, chain = self.approximate(nested[0])
            return (kind, rho, two or t == "twosided", [t] + chain)
        if t == "blendbsdf":
            w = self.value(self.param(e, "weight"), (0.5,) * 3, where)
            parts = [self.approximate(n) for n in nested[:2]]
            if len(parts) != 2:
                self.note(f"{where}: {len(parts)} nested BSDFs instead of 2: 0.5 grey")
                return self.diffuse(DEFAULT_RHO, False, [t])
            if any(p[0] == "null" for p in parts):
                self.note(f"{where}: a transparent part of a blend counts as rho 0")
            r = [p[1] if p[0] != "null" else (0.0,) * 3 for p in parts]
            rho = tuple((1 - wi) * a + wi * b for wi, a, b in zip(w, r[0], r[1]))
            return self.diffuse(rho, any(p[2] for p in parts),
                                [t, "(" + ", ".join("/".join(p[3]) for p in parts) + ")"])
        self.note(f"bsdf type `{t}`: 0.5 grey")
        return self.diffuse(DEFAULT_RHO, False, [t])

    @staticmethod
    def diffuse(rho, two_sided, chain):
        return ("diffuse", tuple(min(max(float(x), 0.0), RHO_MAX) for x in rho), two_sided,
                chain)


def bitmap_mean(path, raw):
    """The mean linear RGB of an image file, as Mitsuba reads it (sRGB-decoded unless raw)."""
    import mitsuba as mi
    b = mi.Bitmap(str(path))
    if raw:
        b.set_srgb_gamma(False)
    b = b.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    return tuple(float(x) for x in np.array(b, dtype=np.float64).reshape(-1, 3).mean(axis=0))


def rgb_text(rho):
    return ", ".join(f"{x:.6g}" for x in rho)


def scene_file(folder):
    folder = pathlib.Path(folder)
    for name in ("scene_mi3.xml", "scene.xml"):
        if (folder / name).exists():
            return folder / name
    sys.exit(f"{folder}: no scene_mi3.xml or scene.xml")


def make_variant(src, width, max_depth, environment=None, environment_to_world=None):
    """The diffuse variant of scene file `src`: (ElementTree, info dict). See the module doc."""
    m = Mapper(src)
    root = m.root
    parents = {c: p for p in root.iter() for c in p}
    counts = collections.Counter()
    out_counts = collections.Counter()
    materials = []
    for e in root.iter("bsdf"):
        counts[m.resolve(e.get("type"))] += 1
    # Only the outermost BSDFs are replaced (the nested ones live inside them).
    outer = [e for e in root.iter("bsdf") if parents.get(e) is not None
             and parents[e].tag != "bsdf"]

    def replacement(e, attrs):
        kind, rho, two, chain = m.approximate(e)
        new = ET.Element("bsdf", {"type": "null" if kind == "null" else
                                  ("twosided" if two else "diffuse")})
        for a in attrs:
            if e.get(a) is not None:
                new.set(a, e.get(a))
        if kind == "diffuse":
            d = ET.SubElement(new, "bsdf", {"type": "diffuse"}) if two else new
            ET.SubElement(d, "rgb", {"name": "reflectance", "value": rgb_text(rho)})
        new.tail = e.tail
        label = "null" if kind == "null" else ("twosided diffuse" if two else "diffuse")
        out_counts[label] += 1
        p = parents[e]
        where = "top level" if p is root else f"in {p.tag} {p.get('id') or ''}".strip()
        materials.append({"id": e.get("id") or f"(unnamed, {where})",
                          "chain": "/".join(chain), "result": label,
                          "rho": None if rho is None else [round(x, 6) for x in rho]})
        return new

    for e in outer:
        p = parents[e]
        # A nested BSDF with an id of its own can be referenced by itself (Mitsuba's ids are
        # global): it is kept, approximated, as a sibling of the outer one.
        for inner in e.iter("bsdf"):
            if inner is not e and inner.get("id") is not None:
                m.note(f"nested bsdf `{inner.get('id')}` ({m.resolve(inner.get('type'))}) "
                       f"inside a {m.resolve(e.get('type'))} has an id of its own: "
                       "references to it get it without its wrapper")
                p.insert(list(p).index(e), replacement(inner, ("id",)))
        p[list(p).index(e)] = replacement(e, ("id", "name"))
    shapes_without_bsdf = 0
    for s in root.iter("shape"):
        has = any(c.tag == "bsdf" or (c.tag == "ref" and m.deref(c) is not None
                                      and m.deref(c).tag == "bsdf") for c in s)
        if not has and m.resolve(s.get("type")) not in ("shapegroup", "instance"):
            shapes_without_bsdf += 1
    if shapes_without_bsdf:
        m.note(f"{shapes_without_bsdf} shapes without a BSDF (Mitsuba's default: one-sided "
               "diffuse 0.5)")
    # Every file name made absolute: the variant lives outside the scene's folder.
    for e in root.iter("string"):
        if snake(e.get("name")) == "filename":
            e.set("value", str((m.dir / m.resolve(e.get("value"))).resolve()))
    # Integrator.
    for e in list(root):
        if e.tag == "integrator":
            root.remove(e)
    integ = ET.Element("integrator", {"type": "path"})
    ET.SubElement(integ, "integer", {"name": "max_depth", "value": str(max_depth)})
    ET.SubElement(integ, "integer", {"name": "rr_depth", "value": "5"})
    ET.SubElement(integ, "boolean", {"name": "hide_emitters", "value": "false"})
    root.insert(0, integ)
    # Sensor: the film's size and filter.
    sensors = root.findall("sensor")
    if len(sensors) != 1:
        m.note(f"{len(sensors)} sensors at the top level")
    film = sensors[0].find("film")
    fw, fh = 768, 576  # Mitsuba's film default
    for c in list(film):
        n = snake(c.get("name"))
        if n == "width":
            fw = int(m.resolve(c.get("value")))
        elif n == "height":
            fh = int(m.resolve(c.get("value")))
        if n in ("width", "height", "pixel_format") or c.tag == "rfilter":
            film.remove(c)
        elif n is not None and n.startswith("crop"):
            m.note(f"film parameter `{n}` kept")
    height = max(1, round(width * fh / fw))
    ET.SubElement(film, "integer", {"name": "width", "value": str(width)})
    ET.SubElement(film, "integer", {"name": "height", "value": str(height)})
    ET.SubElement(film, "string", {"name": "pixel_format", "value": "rgb"})
    ET.SubElement(film, "rfilter", {"type": "box"})
    for smp in sensors[0].findall("sampler"):
        for c in smp:
            if snake(c.get("name")) == "sample_count":
                c.set("value", "1")  # set at render time
    # Emitters: sunsky -> envmap of the given file, or the scene needs one.
    needs_environment = False
    for e in root.iter("emitter"):
        if m.resolve(e.get("type")) in ("sunsky", "sun", "sky"):
            if environment is None:
                needs_environment = True
                continue
            keep_tail, keep_id = e.tail, e.get("id")
            e.clear()
            e.tail = keep_tail
            e.set("type", "envmap")
            if keep_id:
                e.set("id", keep_id)
            ET.SubElement(e, "string", {"name": "filename",
                                        "value": str(pathlib.Path(environment).resolve())})
            if environment_to_world:
                t = ET.SubElement(e, "transform", {"name": "to_world"})
                ET.SubElement(t, "matrix", {"value": environment_to_world})
    for d in root.findall("default"):
        if d.get("name") in ("integrator", "spp", "resx", "resy", "max_depth"):
            root.remove(d)  # the values now set by the variant, or no longer used
    ET.indent(m.tree, "  ")
    info = {
        "source": str(src),
        "film_size": [fw, fh], "width": width, "height": height,
        "bsdfs": dict(sorted(counts.items())),
        "mapped": dict(sorted(out_counts.items())),
        "materials": materials,
        "met": {k: dict(sorted(v.items())) for k, v in m.met.items()},
        "notes": m.notes,
        "needs_environment": needs_environment,
        "environment": str(environment) if environment else None,
    }
    return m.tree, info


# Rendering -------------------------------------------------------------------------------------

def relative_noise(half_a, half_b, k=4):
    """4 x 4-block RMS (and 99th percentile) of |A - B| / (A + B) of two half-set means: the
    relative standard deviation of the blocks of their mean (A + B) / 2."""
    a, b = image_error.luminance_of(half_a), image_error.luminance_of(half_b)
    a, b = image_error.blocks(a, k), image_error.blocks(b, k)
    s = a + b
    keep = s > 1e-3 * s.mean()
    rel = (a[keep] - b[keep]) / s[keep]
    return float(np.sqrt(np.mean(rel ** 2))), float(np.percentile(np.abs(rel), 99))


def block_error(image, reference, k=4):
    """4 x 4-block RMS, 99th percentile and mean of the relative luminance error."""
    rel = image_error.block_relative_errors(image_error.luminance_of(image),
                                            image_error.luminance_of(reference), k)
    return (float(np.sqrt(np.mean(rel ** 2))), float(np.percentile(np.abs(rel), 99)),
            float(np.mean(rel)))


def render(scene, spp, seed):
    """(image, wall seconds, CPU seconds of this process: every Dr.Jit thread's)."""
    import mitsuba as mi
    t, c = time.time(), time.process_time()
    img = np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)[..., :3]
    return img, time.time() - t, time.process_time() - c


def write_image(path, rgb):
    import mitsuba as mi
    path = pathlib.Path(path)
    if path.suffix.lower() == ".pfm":
        spec = importlib.util.spec_from_file_location(
            "image_reference", HERE.parent / "image" / "reference.py")
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        mod.write_pfm(path, mi.Bitmap(rgb.astype(np.float32)))
        return
    b = mi.Bitmap(rgb.astype(np.float32), mi.Bitmap.PixelFormat.RGB)
    b.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float16, srgb_gamma=False).write(
        str(path))


def write_png(path, rgb):
    """A tonemapped look at a linear image: exposure to put the 99th-percentile luminance at 1,
    clipped, sRGB-encoded."""
    import mitsuba as mi
    y = image_error.luminance_of(rgb)
    scale = 1.0 / max(np.percentile(y, 99), 1e-12)
    b = mi.Bitmap(np.clip(rgb * scale, 0, 1).astype(np.float32), mi.Bitmap.PixelFormat.RGB)
    b.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True).write(str(path))


def load_average():
    return float(open("/proc/loadavg").read().split()[0])


def time_to_error(ladder, e, key="error_net", clock="seconds"):
    """Mitsuba's time to reach block error `e`, by interpolation of the ladder on log-log
    (error proportional to t^(-1/k) between two rungs); beyond the ladder, the power law fitted
    over all rungs (least squares of log t on log e) extrapolates. `key`: the rungs' error
    with the reference's own noise removed in quadrature ("error_net"), or as measured
    ("error"); `clock`: "seconds" (wall) or "cpu_seconds". Rungs whose net error is 0
    (within the reference's noise) are left out. Returns (seconds, extrapolated)."""
    pts = sorted((r[clock], r.get(key, r["error"])) for r in ladder)
    pts = [p for p in pts if p[0] > 0 and p[1] > 0]  # a rung within the noise tells nothing
    if len(pts) < 2:
        raise ValueError("the ladder needs two rungs")
    lt = [math.log(p[0]) for p in pts]
    le = [math.log(p[1]) for p in pts]
    x = math.log(e)
    for i in range(len(pts) - 1):
        if min(le[i], le[i + 1]) <= x <= max(le[i], le[i + 1]) and le[i] != le[i + 1]:
            f = (x - le[i]) / (le[i + 1] - le[i])
            return math.exp(lt[i] + f * (lt[i + 1] - lt[i])), False
    n = len(pts)
    mx, my = sum(le) / n, sum(lt) / n
    slope = (sum((a - mx) * (b - my) for a, b in zip(le, lt))
             / sum((a - mx) ** 2 for a in le))  # -k
    return math.exp(my + slope * (x - mx)), True


def table(folder):
    """The Markdown table of the references in `folder` (their JSON files)."""
    rows = ["| scene | size | file | spp (passes x spp) | noise (4x4 RMS, p99) | render s | "
            "load avg | ladder: spp: wall s (CPU s), error (net of the noise) |", "|---|---|---|---|---|---|---|---|"]
    for js in sorted(pathlib.Path(folder).glob("*.json")):
        d = json.loads(js.read_text())
        lad = "; ".join(f"{r['spp']}: {r['seconds']:.1f} s ({r.get('cpu_seconds', 0):.1f} "
                        f"CPU s), {r['error'] * 100:.2f} % ({r['error_net'] * 100:.2f} %)"
                        for r in d.get("ladder", []))
        la = d.get("load_average", [])
        rows.append(
            f"| {d['scene']} | {d['width']} x {d['height']} | {d['file_bytes']:,} B | "
            f"{d['spp']} ({d['passes']} x {d['spp_per_pass']}) | {d['noise'] * 100:.2f} %, "
            f"{d['noise_p99'] * 100:.1f} % | {d['render_seconds']:.0f} | "
            f"{'-'.join(f'{x:.1f}' for x in la)} | {lad} |")
    return "\n".join(rows)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene", help="a corpus scene folder (or, with --time-to-error, a .json)")
    p.add_argument("--width", type=int, default=256, help="film width; the height keeps the "
                   "film's aspect ratio (rounded)")
    p.add_argument("--spp", type=int, default=1024, help="samples per pixel of each pass")
    p.add_argument("--passes", type=int, default=8, help="independent passes (even; seeds "
                   "SEED, SEED + 1000, ...); the noise is measured between the even and odd ones")
    p.add_argument("--min-passes", type=int, default=2, help="with --target-noise or --budget: "
                   "passes rendered before stopping early")
    p.add_argument("--target-noise", type=float, default=0.005, help="stop once the measured "
                   "noise is at most this (4 x 4-block relative std of the mean; 0: never)")
    p.add_argument("--budget", type=float, default=0, help="seconds of rendering after which "
                   "no further pair of passes is started (0: none)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--resume", action="store_true", help="start from the passes a previous "
                   "run left in --work (same --spp, --seed and size) and add pairs to them")
    p.add_argument("--max-depth", type=int, default=256)
    p.add_argument("--ladder", default="16,64,256,1024", help="spp of the ladder renders")
    p.add_argument("--ladder-seed", type=int, default=1, help="seed of the ladder renders (not "
                   "one of the reference's)")
    p.add_argument("--ladder-budget", type=float, default=0, help="seconds: a rung predicted "
                   "to take longer is skipped (0: none)")
    p.add_argument("--no-ladder", action="store_true")
    p.add_argument("--ladder-only", action="store_true", help="keep the written reference; "
                   "render the ladder against it and add it to the JSON")
    p.add_argument("--variant-only", action="store_true", help="write the diffuse variant and "
                   "print its mapping; render nothing")
    p.add_argument("--environment", help="latitude-longitude EXR replacing a sunsky emitter "
                   "(an envmap; Mitsuba's convention: +y up)")
    p.add_argument("--environment-to-world", help="16 numbers: the envmap's to_world matrix")
    p.add_argument("--out", default=str(DEFAULT_OUT), help="folder of <scene>.exr/.json")
    p.add_argument("--format", default="exr", choices=("exr", "pfm"))
    p.add_argument("--work", default="/tmp/corpus-reference", help="folder of the diffuse "
                   "variants (<scene>/scene_diffuse.xml) and the PNG previews")
    p.add_argument("--mitsuba-variant", default="llvm_ad_rgb")
    p.add_argument("--time-to-error", type=float, metavar="E", help="print Mitsuba's time to "
                   "block error E (a fraction: 0.02) from the ladder of the JSON given")
    p.add_argument("--table", action="store_true", help="print the Markdown table of the "
                   "references whose JSON files are in the folder given")
    args = p.parse_args()

    if args.table:
        print(table(pathlib.Path(args.scene)))
        return
    if args.time_to_error is not None:
        js = pathlib.Path(args.scene)
        if js.is_dir():
            js = pathlib.Path(args.out) / f"{js.resolve().name}.json"
        d = json.loads(js.read_text())
        for clock in ("seconds", "cpu_seconds"):
            if all(clock in r for r in d["ladder"]):
                secs, extra = time_to_error(d["ladder"], args.time_to_error, clock=clock)
                print(f"{d['scene']}: {secs:.2f} {'s' if clock == 'seconds' else 'CPU s'} to "
                      f"{args.time_to_error * 100:.2f} %" + (" (extrapolated)" if extra else ""))
        return

    import mitsuba as mi
    import drjit as dr
    mi.set_variant(args.mitsuba_variant)
    folder = pathlib.Path(args.scene).resolve()
    name = folder.name
    src = scene_file(folder)
    tree, info = make_variant(src, args.width, args.max_depth, args.environment,
                              args.environment_to_world)
    work = pathlib.Path(args.work) / name
    work.mkdir(parents=True, exist_ok=True)
    variant = work / "scene_diffuse.xml"
    tree.write(variant, encoding="unicode")
    print(f"{name}: {src.name} -> {variant} ({info['width']}x{info['height']})", file=sys.stderr)
    print(f"  BSDFs {info['bsdfs']} -> {info['mapped']}", file=sys.stderr)
    for n in info["notes"]:
        print(f"  note: {n}", file=sys.stderr)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    js = out / f"{name}.json"
    if args.variant_only:
        print(json.dumps(info, indent=1))
        return
    if info["needs_environment"]:
        print(f"{name}: needs environment (a sunsky: give --environment FILE.exr); skipped",
              file=sys.stderr)
        return

    t = time.time()
    scene = mi.load_file(str(variant))
    load_seconds = time.time() - t
    image_path = out / f"{name}.{args.format}"
    if args.ladder_only:
        record = json.loads(js.read_text())
        ref = np.array(mi.Bitmap(str(image_path)), dtype=np.float64)[..., :3]
    else:
        if args.passes < 2 or args.passes % 2:
            sys.exit("--passes must be even and at least 2")
        halves = [np.zeros((info["height"], info["width"], 3)) for _ in range(2)]
        seeds, pass_seconds, pass_cpu, history = [], [], [], []
        load0 = load_average()
        noise = noise99 = None
        k = 0
        state = work / "passes.npz"  # the half-set sums, for --resume
        if args.resume and state.exists():
            st = np.load(state)
            meta = json.loads(str(st["meta"]))
            if (meta["spp"], meta["seed"], list(st["halves"].shape[1:3])) != (
                    args.spp, args.seed, [info["height"], info["width"]]):
                sys.exit(f"{state}: rendered with other --spp/--seed/--width: {meta}")
            halves = [st["halves"][0], st["halves"][1]]
            seeds, pass_seconds, history = meta["seeds"], meta["pass_seconds"], meta["history"]
            pass_cpu = meta.get("pass_cpu_seconds", [])
            load0 = meta["load_average"]
            k = len(seeds)
            print(f"  resumed: {k} passes", file=sys.stderr)
        spent, pairs_now = 0.0, 0
        while k < args.passes:
            for j in range(2):  # a pair: one pass into each half-set
                img, s, cpu = render(scene, args.spp, args.seed + 1000 * (k + j))
                pass_cpu.append(round(cpu, 2))
                halves[j] += img
                seeds.append(args.seed + 1000 * (k + j))
                pass_seconds.append(round(s, 2))
                spent += s
            k += 2
            pairs_now += 1
            n = k // 2
            noise, noise99 = relative_noise(halves[0] / n, halves[1] / n)
            history.append({"passes": k, "noise": round(noise, 6),
                            "load_average": load_average()})
            total = sum(pass_seconds)
            print(f"  {k} x {args.spp} spp: noise {noise * 100:.3f} % (p99 {noise99 * 100:.2f} "
                  f"%), {total:.1f} s", file=sys.stderr)
            np.savez(state, halves=np.stack(halves), meta=json.dumps({
                "spp": args.spp, "seed": args.seed, "seeds": seeds,
                "pass_seconds": pass_seconds, "pass_cpu_seconds": pass_cpu,
                "history": history, "load_average": load0}))
            if k >= args.min_passes:
                if args.target_noise and noise <= args.target_noise:
                    break
                if args.budget and spent + spent / pairs_now > args.budget:
                    break
        if noise is None:
            n = k // 2
            noise, noise99 = relative_noise(halves[0] / n, halves[1] / n)
        ref = (halves[0] + halves[1]) / k
        write_image(image_path, ref)
        record = {
            "scene": name,
            "source": str(src.relative_to(src.parent.parent)),
            "width": info["width"], "height": info["height"],
            "film_size": info["film_size"],
            "spp": args.spp * k, "spp_per_pass": args.spp, "passes": k, "seeds": seeds,
            "noise": round(noise, 6), "noise_p99": round(noise99, 6),
            "noise_by_passes": history,
            "render_seconds": round(sum(pass_seconds), 1), "pass_seconds": pass_seconds,
            "pass_cpu_seconds": pass_cpu,
            "load_seconds": round(load_seconds, 2),
            "load_average": [load0, load_average()],
            "mean_rgb": [round(float(x), 6) for x in ref.reshape(-1, 3).mean(axis=0)],
            "mitsuba": mi.__version__, "drjit": dr.__version__,
            "variant": args.mitsuba_variant,
            "integrator": {"type": "path", "max_depth": args.max_depth, "rr_depth": 5},
            "bsdfs": info["bsdfs"], "mapped": info["mapped"], "materials": info["materials"],
            "met": info["met"], "notes": info["notes"], "environment": info["environment"],
            "file": image_path.name, "file_bytes": image_path.stat().st_size,
        }
        write_png(work / f"{name}.png", ref)
        print(f"{image_path}: {record['spp']} spp, noise {noise * 100:.3f} %, "
              f"{record['render_seconds']} s, {record['file_bytes']} bytes", file=sys.stderr)
    if not args.no_ladder:
        warm = render(scene, 1, args.ladder_seed + 7)[1]
        cores = os.cpu_count()
        ladder = []
        noise = record["noise"]
        spent = 0.0
        for spp in [int(x) for x in args.ladder.split(",") if x]:
            if ladder and args.ladder_budget:
                guess = ladder[-1]["seconds"] * spp / ladder[-1]["spp"]
                if spent + guess > args.ladder_budget:
                    print(f"  ladder: {spp} spp skipped (about {guess:.0f} s)", file=sys.stderr)
                    break
            img, s, cpu = render(scene, spp, args.ladder_seed)
            spent += s
            e, e99, bias = block_error(img, ref)
            ladder.append({"spp": spp, "seconds": round(s, 3),
                           "cpu_seconds": round(cpu, 3), "error": round(e, 6),
                           "error_net": round(math.sqrt(max(e * e - noise * noise, 0)), 6),
                           "p99": round(e99, 6), "mean": round(bias, 6),
                           "load_average": load_average()})
            print(f"  ladder {spp} spp: {s:.2f} s, error {e * 100:.2f} % (p99 {e99 * 100:.1f} "
                  f"%, mean {bias * 100:+.2f} %)", file=sys.stderr)
        record["ladder"] = ladder
        record["ladder_seed"] = args.ladder_seed
        record["ladder_warmup_seconds"] = round(warm, 2)
        record["cores"] = cores
        record["ladder_load_average"] = load_average()
    js.write_text(json.dumps(record, indent=1) + "\n")


if __name__ == "__main__":
    main()
