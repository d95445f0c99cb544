#!/usr/bin/env python3
"""Per-object reference radiosities of the scenes in scenes/suite/ from Mitsuba 3.

A generalisation of benches/cornell_reference.py to TOML (polygon and OBJ-mesh objects), bare
OBJ and glTF scenes, two-sided materials and an adaptive, vectorised estimator.

Geometry. The scene files are read here, independently of our Rust code: TOML with `tomllib`
(`polygon` objects and `mesh` objects naming an OBJ; no `box`/`sphere`/`transform`, which
the suite does not use), OBJ/MTL with a small parser (a bare OBJ scene: one object per `o`/`g`
name, every material two-sided, `Kd` = rho, `Ke` = emitted radiance; a TOML `mesh`: all faces one
object with the TOML material), glTF with a small JSON + buffer reader (node TRS/matrix
hierarchy of the default scene, indexed or plain TRIANGLES, object = node name, rho =
baseColorFactor RGB, L_e = emissiveFactor * KHR_materials_emissive_strength, doubleSided ->
two-sided; a mirroring node transform reverses the triangles, as our importer does).
Polygons are fanned from their first corner (our loader keeps slightly non-planar quads whole
and fans strongly non-planar ones from the first corner too). A scene in millimetres
(bounding-box diagonal > 100 units: cornell-faces) is scaled to metres for Mitsuba (radiance is
invariant; areas are reported in scene units).

Mitsuba scene. One `obj` shape per (object, material), face normals; one-sided materials are
`diffuse`, two-sided ones `twosided` wrapping `diffuse` (same rho both sides); emitting
materials get an `area` emitter with the material's radiance (Mitsuba's area emitter emits from
the front only, as ours). Integrator `path`, max_depth 256, Russian roulette from depth 5
(unbiased; the truncation is nil).

Estimator. For each object and side (front; back too for objects with two-sided faces) the mean
outgoing reflected radiosity over the object is

    B_side = mean over the object's area of  rho(x) * H_side(x),   H = pi * E[L_in]

estimated exactly as Mitsuba's `irradiancemeter` does it (a point uniform by area over the
object's triangles, a cosine-distributed direction about the side's normal, the incoming
radiance L_in along it by the path integrator, times pi), but vectorised: the rays of all
object sides are built with numpy and traced in one wavefront by `integrator.sample` in the
`llvm_ad_rgb` variant (≈ 3x the throughput of `scalar_rgb` here). The ray origin is lifted off
the surface along the side's normal by Mitsuba's own spawn offset (1 + max|p|) * 1500 * 2^-24.
Metering the back by cosine directions about the reversed normal is the same as Mitsuba's
irradiance meter on a copy of the faces with reversed winding put in place of the object (the
BSDF is `twosided`, so the transport is unchanged). The front adds the emitted exitance
E = pi * L_e (emitters: B = E + rho * H_front, like cornell_reference.py). An object's
`radiosity` is B_front + B_back (power leaving all its sides over its geometric one-side
area: the definition of `radiosity solve --stats`); for one-sided objects B_back = 0.

Every sample is independent (one independent-sampler stream per lane, a fresh seed per
wavefront), so the standard error of each mean is the sample standard deviation over
sqrt(samples); `se` of the radiosity is sqrt(se_front^2 + se_back^2). Samples are allocated
adaptively: a pilot of `--pilot` wavefronts split evenly over the object sides gives each side's
variance, then wavefronts are split in proportion to the samples still missing for a relative
standard error of `--target` (default 0.2 %) on every channel of every object (a side that is
always 0, e.g. the inside of a closed mesh or a wall's outer face, needs none), until all targets
are met or `--budget` seconds are spent. The achieved errors are recorded.

Checks (`--check`): the CIE 171:2006 TC 5.8 integrating cube (rho = 0.5, exact mean irradiance
pi / 27) with this estimator, and one object measured by Mitsuba's own `irradiancemeter` in
`scalar_rgb` (cornell_reference.py's method) against this estimator.

Time: all nine scenes at the default target, 15 min on 2 cores (shared), 16-150 s per scene.

Usage (Mitsuba 3 with the LLVM back end: `apt-get install libllvm19`):
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
    nice -n 10 python3 benches/suite/reference.py [SCENE ...] [--budget 140] [--target 0.002]
    python3 benches/suite/reference.py --check
Writes benches/suite/reference/<scene>.json (all scenes when none is named).
"""

import argparse
import base64
import datetime
import json
import math
import os
import pathlib
import struct
import sys
import tempfile
import time
import tomllib

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")

import mitsuba as mi  # noqa: E402
import numpy as np  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
SUITE = ROOT / "scenes" / "suite"
OUT = pathlib.Path(__file__).resolve().parent / "reference"
# Rooms closed on every side, whose surfaces must absorb all the power they emit (the window of
# `emitter-near-wall-facing` has an unmodelled back that absorbs too, so it is left out).
CLOSED = {"partitions", "emitter-near-wall-away", "furnished-room"}
SCENES = {
    "cornell-faces": "cornell-faces/scene.toml",
    "obj-box": "obj-box/scene.obj",
    "closed-mesh": "closed-mesh/scene.toml",
    "partitions": "partitions/scene.toml",
    "emitter-near-wall-facing": "emitter-near-wall-facing/scene.toml",
    "emitter-near-wall-away": "emitter-near-wall-away/scene.toml",
    "blender-gltf": "blender-gltf/scene.gltf",
    "bare-obj-many": "bare-obj-many/scene.obj",
    "furnished-room": "furnished-room/scene.toml",
}
RAY_EPSILON = 1500 * 2.0**-24


# ---------------------------------------------------------------------------------------------
# Scene readers. An object is {name, tris (T,3,3), rho (T,3), emission (T,3), two_sided (T,)}.


class Objects:
    def __init__(self):
        self.order, self.parts = [], {}

    def add(self, name, polygons, rho, emission, two_sided):
        """polygons: lists of corners; each fanned from its first corner."""
        if name not in self.parts:
            self.order.append(name)
            self.parts[name] = []
        tris = []
        for poly in polygons:
            for i in range(1, len(poly) - 1):
                tris.append([poly[0], poly[i], poly[i + 1]])
        tris = np.array(tris, dtype=np.float64).reshape(-1, 3, 3)
        # skip degenerate triangles (zero area), as a loader would
        cross = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
        tris = tris[np.linalg.norm(cross, axis=1) > 0]
        self.parts[name].append((tris, tuple(rho), tuple(emission), bool(two_sided)))

    def finish(self):
        out = []
        for name in self.order:
            merged = {}
            for tris, rho, em, ts in self.parts[name]:
                merged.setdefault((rho, em, ts), []).append(tris)
            groups = [(np.concatenate(v), *k) for k, v in merged.items()]
            tris = np.concatenate([g[0] for g in groups])
            rho = np.concatenate([np.tile(g[1], (len(g[0]), 1)) for g in groups])
            em = np.concatenate([np.tile(g[2], (len(g[0]), 1)) for g in groups])
            ts = np.concatenate([np.full(len(g[0]), g[3]) for g in groups])
            out.append({"name": name, "tris": tris, "rho": rho, "emission": em,
                        "two_sided": ts, "groups": groups})
        return out


def image_size(scene, width, height):
    """The image size asked for, else the TOML scene's [render] size (as our `render` takes it),
    else 512 x 512 (our default for scenes without one)."""
    size = {}
    if pathlib.Path(scene).suffix.lower() == ".toml":
        size = tomllib.loads(pathlib.Path(scene).read_text()).get("render", {})
    return (width or int(size.get("width", 512)), height or int(size.get("height", 512)))


def read_mtl(path):
    mats = {}
    cur = None
    for line in path.read_text().splitlines():
        t = line.split("#", 1)[0].split()
        if not t:
            continue
        if t[0] == "newmtl":
            cur = mats.setdefault(" ".join(t[1:]), {"Kd": (0.5, 0.5, 0.5), "Ke": (0.0, 0.0, 0.0)})
        elif t[0] in ("Kd", "Ke") and cur is not None:
            v = [float(x) for x in t[1:4]]
            cur[t[0]] = tuple(v if len(v) == 3 else v[:1] * 3)
    return mats


def read_obj(path):
    """[(group name, material name or None, polygon corners)] and {material: (Kd, Ke)}."""
    verts, faces, mats = [], [], {}
    group, material = "default", None
    text = path.read_text().replace("\\\n", " ")
    for line in text.splitlines():
        t = line.split("#", 1)[0].split()
        if not t:
            continue
        if t[0] == "v":
            verts.append([float(x) for x in t[1:4]])
        elif t[0] == "f":
            idx = []
            for c in t[1:]:
                i = int(c.split("/")[0])
                idx.append(i - 1 if i > 0 else len(verts) + i)
            faces.append((group, material, [verts[i] for i in idx]))
        elif t[0] in ("o", "g"):
            group = " ".join(t[1:]) or "default"
        elif t[0] == "usemtl":
            material = " ".join(t[1:])
        elif t[0] == "mtllib":
            for name in t[1:]:
                p = path.parent / name
                if p.exists():
                    mats.update(read_mtl(p))
    return faces, mats


def load_obj_scene(path):
    """A bare OBJ scene: every material two-sided. A face with exactly the corners of an earlier
    face (in any order: two-sided) is the same surface written twice, a defect of the file (the
    widespread Cornell-box OBJ repeats a block's side face as its bottom); it is dropped, so the
    reference is the scene the file means, not a z-fighting double surface."""
    faces, mats = read_obj(path)
    objs = Objects()
    seen = set()
    for group, material, poly in faces:
        key = tuple(sorted(tuple(c) for c in poly))
        if key in seen:
            continue
        seen.add(key)
        m = mats.get(material, {"Kd": (0.5, 0.5, 0.5), "Ke": (0.0, 0.0, 0.0)})
        objs.add(group, [poly], m["Kd"], m["Ke"], True)
    return objs.finish()


def load_toml_scene(path):
    data = tomllib.loads(path.read_text())
    mats = {}
    for name, m in data["materials"].items():
        assert not (set(m) - {"reflectance", "emission", "two_sided"}), name

        def col(v):
            return tuple(v) if isinstance(v, list) else (float(v),) * 3

        mats[name] = (col(m.get("reflectance", 0.0)), col(m.get("emission", 0.0)),
                      bool(m.get("two_sided", False)))
    objs = Objects()
    for i, o in enumerate(data["objects"]):
        assert "transform" not in o, "the suite uses explicit geometry only"
        name = o.get("name", f"object{i}")
        if o["shape"] == "polygon":
            objs.add(name, [o["vertices"]], *mats[o["material"]])
        elif o["shape"] == "mesh":
            faces, file_mats = read_obj(path.parent / o["path"])
            for _, material, poly in faces:
                if "material" in o:
                    objs.add(name, [poly], *mats[o["material"]])
                else:
                    m = file_mats.get(material, {"Kd": (0.5,) * 3, "Ke": (0.0,) * 3})
                    objs.add(name, [poly], m["Kd"], m["Ke"], False)
        else:
            raise ValueError(f"{name}: shape {o['shape']} is not explicit geometry")
    return objs.finish()


def quat_matrix(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def load_gltf_scene(path):
    g = json.loads(path.read_text())
    buffers = []
    for b in g["buffers"]:
        uri = b["uri"]
        if uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            buffers.append((path.parent / uri).read_bytes())
    fmt = {5120: "b", 5121: "B", 5122: "h", 5123: "H", 5125: "I", 5126: "f"}
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}

    def accessor(i):
        a = g["accessors"][i]
        v = g["bufferViews"][a["bufferView"]]
        n, w, f = a["count"], width[a["type"]], fmt[a["componentType"]]
        size = struct.calcsize(f)
        stride = v.get("byteStride", size * w)
        base = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        data = buffers[v["buffer"]]
        return np.array([struct.unpack_from(f"<{w}{f}", data, base + k * stride) for k in range(n)])

    mats = []
    for m in g.get("materials", []):
        pbr = m.get("pbrMetallicRoughness", {})
        base = pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]
        rho = tuple(min(float(np.float32(c)), 0.999) for c in base)  # our importer clamps rho < 1
        strength = m.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get(
            "emissiveStrength", 1.0)
        em = tuple(float(np.float32(c)) * float(np.float32(strength))
                   for c in m.get("emissiveFactor", [0, 0, 0]))
        mats.append((rho, em, bool(m.get("doubleSided", False))))
    default = ((1.0, 1.0, 1.0), (0.0, 0.0, 0.0), False)
    objs = Objects()

    def local(n):
        if "matrix" in n:
            return np.array(n["matrix"], dtype=np.float64).reshape(4, 4).T
        m = np.eye(4)
        s = np.diag(n.get("scale", [1, 1, 1]))
        r = quat_matrix(n.get("rotation", [0, 0, 0, 1]))
        m[:3, :3] = r @ s
        m[:3, 3] = n.get("translation", [0, 0, 0])
        return m

    def visit(i, parent):
        n = g["nodes"][i]
        m = parent @ local(n)
        if "mesh" in n:
            mesh = g["meshes"][n["mesh"]]
            name = n.get("name") or mesh.get("name") or f"node{i}"
            for prim in mesh["primitives"]:
                assert prim.get("mode", 4) == 4, "TRIANGLES only"
                pos = accessor(prim["attributes"]["POSITION"])
                pos = (m[:3, :3] @ pos.T).T + m[:3, 3]
                idx = (accessor(prim["indices"]).reshape(-1) if "indices" in prim
                       else np.arange(len(pos)))
                tris = idx.reshape(-1, 3)
                if np.linalg.det(m[:3, :3]) < 0:
                    tris = tris[:, ::-1]
                mat = mats[prim["material"]] if "material" in prim else default
                objs.add(name, [pos[t].tolist() for t in tris], *mat)
        for c in n.get("children", []):
            visit(c, m)

    scene = g["scenes"][g.get("scene", 0)]
    for i in scene["nodes"]:
        visit(i, np.eye(4))
    return objs.finish()


def load(path):
    path = pathlib.Path(path)
    ext = path.suffix.lower()
    if ext == ".toml":
        return load_toml_scene(path)
    if ext == ".obj":
        return load_obj_scene(path)
    if ext in (".gltf",):
        return load_gltf_scene(path)
    raise ValueError(path)


def tri_areas(tris):
    return 0.5 * np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)


def scene_scale(objects):
    pts = np.concatenate([o["tris"].reshape(-1, 3) for o in objects])
    diag = np.linalg.norm(pts.max(axis=0) - pts.min(axis=0))
    return 1e-3 if diag > 100 else 1.0


# ---------------------------------------------------------------------------------------------
# Mitsuba


def write_obj(path, tris):
    lines = []
    for k, t in enumerate(tris):
        lines += [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in t]
        lines.append(f"f {3 * k + 1} {3 * k + 2} {3 * k + 3}")
    pathlib.Path(path).write_text("\n".join(lines) + "\n")


def scene_dict(objects, scale, directory, max_depth, rr_depth, meter=None):
    """`meter`: optional (object index, side) for an irradiancemeter (scalar check): the
    object's faces (side +1) or a reversed copy of them (side -1) carry the sensor."""
    d = {"type": "scene",
         "integrator": {"type": "path", "max_depth": max_depth, "rr_depth": rr_depth}}
    for oi, o in enumerate(objects):
        for gi, (tris, rho, em, ts) in enumerate(o["groups"]):
            t = tris * scale
            if meter and meter[0] == oi and meter[1] < 0:
                assert ts and not any(em)
                t = t[:, ::-1]
            fn = os.path.join(directory, f"o{oi}_{gi}.obj")
            write_obj(fn, t)
            bsdf = {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(rho)}}
            if ts:
                bsdf = {"type": "twosided", "bsdf": bsdf}
            shape = {"type": "obj", "filename": fn, "face_normals": True, "bsdf": bsdf}
            if any(em):
                shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": list(em)}}
            d[f"o{oi}_{gi}"] = shape
    return d


class Estimator:
    """Vectorised metering of many (object, side) tasks in one wavefront (llvm variant)."""

    def __init__(self, objects, scale, max_depth=256, rr_depth=5, variant="llvm_ad_rgb"):
        mi.set_variant(variant)
        self.objects, self.scale = objects, scale
        with tempfile.TemporaryDirectory() as directory:
            self.scene = mi.load_dict(scene_dict(objects, scale, directory, max_depth, rr_depth))
        self.integrator = mi.load_dict({"type": "path", "max_depth": max_depth,
                                        "rr_depth": rr_depth})
        self.sampler = mi.load_dict({"type": "independent"})
        self.tasks = []
        for oi, o in enumerate(objects):
            self.tasks.append((oi, +1))
            if o["two_sided"].any():
                self.tasks.append((oi, -1))
        self.area = [tri_areas(o["tris"]) for o in objects]
        self.cdf = [np.cumsum(a) / a.sum() for a in self.area]
        self.normal = []
        for o in objects:
            n = np.cross(o["tris"][:, 1] - o["tris"][:, 0], o["tris"][:, 2] - o["tris"][:, 0])
            self.normal.append(n / np.linalg.norm(n, axis=1)[:, None])
        T = len(self.tasks)
        self.sum = np.zeros((T, 3))
        self.sumsq = np.zeros((T, 3))
        self.n = np.zeros(T, dtype=np.int64)
        self.launches = 0

    def launch(self, counts, seed):
        """Traces counts[t] samples of every task t (one wavefront)."""
        rng = np.random.default_rng([seed, 12345])
        P, D, W, task_of = [], [], [], []
        for t, c in enumerate(counts):
            if c == 0:
                continue
            oi, side = self.tasks[t]
            o = self.objects[oi]
            f = np.searchsorted(self.cdf[oi], rng.random(c), side="right")
            f = np.minimum(f, len(self.cdf[oi]) - 1)
            u, v = rng.random(c), rng.random(c)
            su = np.sqrt(u)
            b0, b1 = 1 - su, su * (1 - v)
            tr = o["tris"][f] * self.scale
            p = b0[:, None] * tr[:, 0] + b1[:, None] * tr[:, 1] + (1 - b0 - b1)[:, None] * tr[:, 2]
            n = self.normal[oi][f] * side
            # cosine-distributed direction about n
            r1, r2 = rng.random(c), rng.random(c)
            rr, phi = np.sqrt(r1), 2 * np.pi * r2
            a = np.where(np.abs(n[:, 0:1]) > 0.9, [[0.0, 1.0, 0.0]], [[1.0, 0.0, 0.0]])
            s = np.cross(n, a)
            s /= np.linalg.norm(s, axis=1)[:, None]
            tt = np.cross(n, s)
            d = (rr * np.cos(phi))[:, None] * s + (rr * np.sin(phi))[:, None] * tt \
                + np.sqrt(np.maximum(0, 1 - r1))[:, None] * n
            off = (1 + np.abs(p).max(axis=1)) * RAY_EPSILON
            P.append(p + off[:, None] * n)
            D.append(d)
            w = o["rho"][f] * np.pi
            if side < 0:
                w = w * o["two_sided"][f][:, None]
            W.append(w)
            task_of.append(np.full(c, t))
        P, D, W, task_of = (np.concatenate(x) for x in (P, D, W, task_of))
        N = len(P)
        self.sampler.seed(seed, N)
        o = mi.Point3f(*(P[:, k].astype(np.float32) for k in range(3)))
        d = mi.Vector3f(*(D[:, k].astype(np.float32) for k in range(3)))
        L, _, _ = self.integrator.sample(self.scene, self.sampler, mi.RayDifferential3f(mi.Ray3f(o, d)))
        L = np.array(L, dtype=np.float64).reshape(3, -1).T
        val = W * L
        for k in range(3):
            self.sum[:, k] += np.bincount(task_of, val[:, k], minlength=len(self.tasks))
            self.sumsq[:, k] += np.bincount(task_of, val[:, k] ** 2, minlength=len(self.tasks))
        self.n += np.bincount(task_of, minlength=len(self.tasks))
        self.launches += 1

    def stats(self):
        """(mean, standard error) per task, shape (T, 3)."""
        n = np.maximum(self.n, 2)[:, None]
        mean = self.sum / n
        var = np.maximum(self.sumsq / n - mean**2, 0) * n / (n - 1)
        return mean, np.sqrt(var / n), np.sqrt(var)

    def needed(self, target):
        """Samples each task needs in total for a relative SE `target` on every object."""
        mean, _, sd = self.stats()
        need = np.zeros(len(self.tasks))
        for oi, o in enumerate(self.objects):
            ts = [t for t, (j, _) in enumerate(self.tasks) if j == oi]
            em = (np.pi * o["emission"] * self.area[oi][:, None]).sum(0) / self.area[oi].sum()
            mu = sum(mean[t] for t in ts) + em
            tau = target * np.maximum(mu, 1e-12)
            ssum = sum(sd[t] for t in ts)
            for t in ts:
                # optimal split of the error between the sides: n_t = sd_t (sum sd) / tau^2
                need[t] = np.max(sd[t] * ssum / tau**2)
        return need


def run_scene(name, args):
    path = SUITE / SCENES[name]
    objects = load(path)
    scale = scene_scale(objects)
    est = Estimator(objects, scale, args.max_depth, args.rr_depth)
    T = len(est.tasks)
    N = args.wavefront
    start = time.time()
    seed = args.seed * 1_000_000
    for _ in range(args.pilot):
        base = np.full(T, N // T)
        base[: N - base.sum()] += 1
        est.launch(base, seed)
        seed += 1
    while time.time() - start < args.budget:
        need = est.needed(args.target)
        missing = np.maximum(need - est.n, 0)
        if missing.sum() <= 0:
            break
        # cap the worst tasks so that one dark object does not starve the others
        share = missing / missing.sum()
        counts = np.floor(share * N).astype(np.int64)
        counts[np.argmax(share)] += N - counts.sum()
        est.launch(counts, seed)
        seed += 1
    elapsed = time.time() - start
    mean, se, _ = est.stats()
    out = []
    for oi, o in enumerate(objects):
        area = est.area[oi]
        A = area.sum()
        em = (np.pi * o["emission"] * area[:, None]).sum(0) / A
        tf = est.tasks.index((oi, +1))
        front, front_se = mean[tf] + em, se[tf]
        two = bool(o["two_sided"].any())
        if two:
            tb = est.tasks.index((oi, -1))
            back, back_se = mean[tb], se[tb]
        else:
            back, back_se = np.zeros(3), np.zeros(3)
        rad = front + back
        rad_se = np.sqrt(front_se**2 + back_se**2)
        out.append({
            "name": o["name"],
            "area": float(A / 1.0),
            "triangles": int(len(o["tris"])),
            "two_sided": two,
            "emission": (em.tolist() if any(em) else None),
            "radiosity": rad.tolist(),
            "se": rad_se.tolist(),
            "rel_se": (rad_se / np.maximum(rad, 1e-300)).tolist(),
            "front": front.tolist(),
            "front_se": front_se.tolist(),
            "back": back.tolist() if two else None,
            "back_se": back_se.tolist() if two else None,
            "samples_front": int(est.n[tf]),
            "samples_back": int(est.n[est.tasks.index((oi, -1))]) if two else 0,
        })
    worst = max(max(o["rel_se"]) for o in out)
    result = {
        "scene": f"scenes/suite/{SCENES[name]}",
        "closed": name in CLOSED,
        "renderer": f"Mitsuba {mi.__version__}",
        "variant": "llvm_ad_rgb",
        "integrator": "path (next-event estimation + MIS, Russian roulette)",
        "max_depth": args.max_depth,
        "rr_depth": args.rr_depth,
        "estimator": "per object side: point uniform by area, cosine direction about the side's "
                     "normal, pi * rho * L_in (the irradiancemeter's estimate), vectorised",
        "scale_to_metres": scale,
        "spp": int(est.n.sum()),
        "wavefront": N,
        "seeds": est.launches,
        "first_seed": args.seed * 1_000_000,
        "target_rel_se": args.target,
        "worst_rel_se": worst,
        "seconds": round(elapsed, 1),
        "date": datetime.date.today().isoformat(),
        "command": " ".join(["python3", "benches/suite/reference.py", *sys.argv[1:]]),
        "quantity": "radiosity = B_front + B_back (W/m^2 per unit of geometric one-side area; "
                    "B_front includes pi*L_e for emitters), se = standard error of the mean",
        "objects": out,
    }
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / f"{name}.json").write_text(json.dumps(result, indent=1) + "\n")
    print(f"{name}: {len(objects)} objects, {est.n.sum() / 1e6:.1f} M samples, "
          f"{elapsed:.0f} s, worst relative SE {worst * 100:.3f} %", flush=True)
    return result


# ---------------------------------------------------------------------------------------------
# Checks


def furnace_objects():
    """CIE 171:2006 TC 5.8, the closed 1 m cube of `benches/cornell_reference.py` (rho = 0.5,
    centre ninth of the ceiling emitting radiance 1), as suite objects."""
    sys.path.insert(0, str(ROOT / "benches"))
    from cornell_reference import furnace_shapes  # noqa: E402

    objs = Objects()
    for name, (_, rho, emission, polygons) in furnace_shapes(0.5).items():
        objs.add(name, polygons, rho, emission, False)
    return objs.finish()


def scalar_meter(task):
    """Mitsuba's irradiancemeter in scalar_rgb on one object side (a reversed copy for the
    back): mean of pi * L_in, times rho (uniform rho per object only)."""
    name, oi, side, spp, seed = task
    mi.set_variant("scalar_rgb")
    objects = load(SUITE / SCENES[name])
    scale = scene_scale(objects)
    with tempfile.TemporaryDirectory() as directory:
        d = scene_dict(objects, scale, directory, 256, 5, meter=(oi, side))
        key = f"o{oi}_0"
        assert len(objects[oi]["groups"]) == 1, "one material per checked object"
        d[key]["sensor"] = {
            "type": "irradiancemeter",
            "film": {"type": "hdrfilm", "width": 1, "height": 1, "pixel_format": "rgb",
                     "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": spp}}
        scene = mi.load_dict(d)
    t = time.time()
    img = mi.render(scene, spp=spp, seed=seed)
    return np.array(img, dtype=np.float64).reshape(-1)[:3], time.time() - t


def check(args):
    import multiprocessing
    # 1. furnace
    objs = furnace_objects()
    est = Estimator(objs, 1.0)
    for s in range(4):
        est.launch(np.array([1 << 19, 1 << 19]), s)
    mean, se, _ = est.stats()
    a = [tri_areas(o["tris"]).sum() for o in objs]
    h = sum(a[i] * mean[i][0] / 0.5 for i in range(2)) / sum(a)
    hse = math.sqrt(sum((a[i] * se[i][0] / 0.5) ** 2 for i in range(2))) / sum(a)
    print(f"furnace: exact {math.pi / 27:.6f}  measured {h:.6f} ± {hse:.6f}")
    # 2. scalar irradiancemeter vs vectorised estimator on single-group objects
    for name, obj, side in (("obj-box", "short_block", +1), ("partitions", "partition_panel", -1)):
        objects = load(SUITE / SCENES[name])
        oi = [o["name"] for o in objects].index(obj)
        rho = np.array(objects[oi]["groups"][0][1])
        spp, seeds = args.check_spp, 4
        with multiprocessing.get_context("spawn").Pool(2) as pool:
            runs = pool.map(scalar_meter, [(name, oi, side, spp, 10 * args.seed + s)
                                          for s in range(seeds)])
        hs = np.array([r[0] for r in runs])
        t_scalar = sum(r[1] for r in runs)
        b_s, b_se = rho * hs.mean(0), rho * hs.std(0, ddof=1) / math.sqrt(seeds)
        est = Estimator(objects, scene_scale(objects))
        t = est.tasks.index((oi, side))
        counts = np.zeros(len(est.tasks), dtype=np.int64)
        counts[t] = 1 << 20
        t0 = time.time()
        for s in range(seeds):
            est.launch(counts, 100 + 10 * args.seed + s)
        t_llvm = time.time() - t0
        mean, se, _ = est.stats()
        print(f"{name}/{obj} side {side:+d}: scalar irradiancemeter {b_s} ± {b_se} "
              f"({seeds * spp / t_scalar / 1e6:.2f} M/s per process); llvm estimator "
              f"{mean[t]} ± {se[t]} ({seeds * spp / t_llvm / 1e6:.2f} M/s, 2 threads)")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenes", nargs="*", help=f"any of {', '.join(SCENES)} (default: all)")
    p.add_argument("--budget", type=float, default=140.0, help="seconds per scene (after pilot)")
    p.add_argument("--target", type=float, default=0.002, help="relative standard error")
    p.add_argument("--wavefront", type=int, default=1 << 20, help="samples per launch")
    p.add_argument("--pilot", type=int, default=4, help="evenly split pilot launches")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--max-depth", type=int, default=256)
    p.add_argument("--rr-depth", type=int, default=5)
    p.add_argument("--check", action="store_true", help="run the checks only")
    p.add_argument("--check-spp", type=int, default=1 << 19, help="samples per seed of a check")
    args = p.parse_args()
    if args.check:
        check(args)
        return
    for name in args.scenes or SCENES:
        run_scene(name, args)


if __name__ == "__main__":
    main()
