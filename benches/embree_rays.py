#!/usr/bin/env python3
"""Trace ray workloads with Intel Embree (PyPI `embreex`) for comparison with our BVH, and
put both side by side.

Usage:
  python3 benches/embree_rays.py WORKLOAD.bin [...] [--out EMBREE.jsonl]
  python3 benches/embree_rays.py --table OURS.json [...] EMBREE.jsonl [...]

A workload file is written by `cargo xtask bench --workload DIR` (see
`crates/xtask/src/throughput/mod.rs`), little-endian: u32 triangle count N, u32 ray-set count S,
N*9 f32 (a, b, c of each triangle), then S ray sets, each a 16-byte NUL-padded name, a u32 ray
count M and M*7 f32 (origin, direction, t_max). Ray k is traced with t in (0, t_max[k]), as the
Rust side does.

`EmbreeScene.run` loops over the rays in Cython, one `rtcIntersect1`/`rtcOccluded1` call per
ray, on the calling thread: Embree's own threads (TBB) are used for the scene build only. The
script reports the CPU time next to the wall time so that this can be checked.

The first form prints (and with --out appends to a file) one JSON object per workload: the
build time (best of 3), the resident memory a first build adds in a fresh process (Embree's
copy of the vertices and indices, its BVH, and the library's own first allocations), and for each ray set best-of-3 rays/s for occlusion and
closest hit with the occluded/hit counts (to compare with the Rust figures).

The second form reads any number of our reports (`cargo xtask bench --json`, `.json`) and of
Embree's (`.jsonl`), from interleaved runs, and prints the Markdown table of the best figure of
each (scene, rays, query) over the runs, with the per-core ratio ours / Embree.
"""

import json
import os
import struct
import subprocess
import sys
import time

import numpy as np

REPETITIONS = 3


def load(path):
    """Triangles and a list of (name, origins, directions, t_max) of a workload file."""
    with open(path, "rb") as f:
        data = f.read()
    n_tris, n_sets = struct.unpack_from("<II", data, 0)
    at = 8
    tris = np.frombuffer(data, dtype="<f4", count=n_tris * 9, offset=at)
    tris = tris.reshape(n_tris, 3, 3).astype(np.float32)
    at += n_tris * 36
    sets = []
    for _ in range(n_sets):
        name = data[at : at + 16].rstrip(b"\0").decode("ascii")
        (m,) = struct.unpack_from("<I", data, at + 16)
        at += 20
        rays = np.frombuffer(data, dtype="<f4", count=m * 7, offset=at).reshape(m, 7)
        at += m * 28
        sets.append(
            (
                name,
                np.ascontiguousarray(rays[:, :3], dtype=np.float32),
                np.ascontiguousarray(rays[:, 3:6], dtype=np.float32),
                np.ascontiguousarray(rays[:, 6], dtype=np.float32),
            )
        )
    if at != len(data):
        raise ValueError(f"{path}: size does not match its counts")
    return tris, sets


def best_of(f):
    """Best wall time over REPETITIONS (after one warm-up), the CPU time of that run, result."""
    result = f()
    best = (float("inf"), 0.0)
    for _ in range(REPETITIONS):
        wall, cpu = time.perf_counter(), time.process_time()
        result = f()
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        best = min(best, (wall, cpu))
    return best[0], best[1], result


def resident_bytes():
    """Resident set size of this process (Linux)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096


def memory(path):
    """Resident bytes the first build of `path`'s scene adds, measured in a fresh process (a
    process that has built before reuses freed pages)."""
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); import embree_rays as e; "
        "print(e.build_memory(sys.argv[2]))"
    )
    here = os.path.dirname(os.path.abspath(__file__))
    run = subprocess.run(
        [sys.executable, "-c", code, here, path], capture_output=True, text=True, check=True
    )
    return int(run.stdout)


def build_memory(path):
    """Resident bytes added by building `path`'s scene in this process."""
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    tris, sets = load(path)
    origins, dirs = sets[0][1][:1], sets[0][2][:1]
    before = resident_bytes()
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, tris)
    scene.run(origins, dirs, dists=1e30, query="OCCLUDED")
    return resident_bytes() - before


def bench(path):
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    tris, sets = load(path)
    probe = (sets[0][1][:1], sets[0][2][:1]) if sets and len(sets[0][1]) else None

    def build():
        scene = rtcore_scene.EmbreeScene()
        TriangleMesh(scene, tris)
        # The scene is committed (the BVH built) on the first query.
        if probe is not None:
            scene.run(probe[0], probe[1], dists=1e30, query="OCCLUDED")
        return scene

    build_s, build_cpu, scene = best_of(build)
    out = {
        "workload": path,
        "triangles": len(tris),
        "embree_build_seconds": build_s,
        "build_cpu_over_wall": build_cpu / build_s,
        "resident_bytes_per_triangle": memory(path) / max(len(tris), 1),
        "sets": [],
    }
    for name, origins, dirs, t_max in sets:
        n = len(origins)
        occl_s, occl_cpu, occl = best_of(
            lambda: scene.run(origins, dirs, dists=t_max, query="OCCLUDED")
        )
        hit_s, hit_cpu, prim = best_of(
            lambda: scene.run(origins, dirs, dists=t_max, query="INTERSECT")
        )
        out["sets"].append(
            {
                "name": name,
                "rays": n,
                "occlusion_rays_per_second": n / occl_s,
                "closest_hit_rays_per_second": n / hit_s,
                "occlusion_cpu_over_wall": occl_cpu / occl_s,
                "closest_hit_cpu_over_wall": hit_cpu / hit_s,
                # Occluded rays report geomID 0 (the one mesh), unoccluded ones -1.
                "occluded": int(np.count_nonzero(occl != -1)),
                "hits": int(np.count_nonzero(prim != -1)),
            }
        )
    return out


def scene_of(workload):
    """`DIR/spheres.bin` -> `spheres`."""
    return workload.rsplit("/", 1)[-1].removesuffix(".bin")


def table(paths):
    """The Markdown comparison of the best figures over our reports and Embree's."""
    ours, embree, builds, memory, counts = {}, {}, {}, {}, {}

    def keep(table_, key, value):
        table_[key] = max(table_.get(key, 0.0), value)

    for path in paths:
        with open(path) as f:
            if path.endswith(".jsonl"):
                for line in f:
                    r = json.loads(line)
                    scene = scene_of(r["workload"])
                    builds.setdefault((scene, "embree"), []).append(r["embree_build_seconds"])
                    memory[(scene, "embree")] = r["resident_bytes_per_triangle"]
                    for s in r["sets"]:
                        for q in ("occlusion", "closest_hit"):
                            keep(embree, (scene, s["name"], q), s[f"{q}_rays_per_second"])
                        counts.setdefault((scene, s["name"], "embree"), set()).add(
                            (s["occluded"], s["hits"])
                        )
            else:
                for r in json.load(f):
                    scene = r["scene"]
                    memory[(scene, "ours")] = r["bytes_per_triangle"]
                    memory[(scene, "triangles")] = r["triangles"]
                    for b in r["builds"]:
                        builds.setdefault((scene, f"ours{b['threads']}"), []).append(b["seconds"])
                    for s in r["sets"]:
                        counts.setdefault((scene, s["name"], "ours"), set()).add(
                            (s["occluded"], s["hits"])
                        )
                        for rate in s["rates"]:
                            for q in ("occlusion", "closest_hit"):
                                keep(
                                    ours,
                                    (scene, s["name"], q, rate["threads"]),
                                    rate[f"{q}_rays_per_second"],
                                )
                                batched = rate.get(f"{q}_batched_rays_per_second")
                                if batched is not None:
                                    keep(ours, (scene, s["name"], q, rate["threads"], "b"), batched)
                                packet = rate.get(f"{q}_packet_rays_per_second")
                                if packet is not None:
                                    keep(ours, (scene, s["name"], q, rate["threads"], "p"), packet)
    lines = [
        "| scene | rays | query | ours 1 thread | ours 2 threads | Embree 1 thread | ratio "
        "| ours interleaved 1 / 2 threads | ratio interleaved "
        "| ours packets of 8 1 / 2 threads | ratio packets |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    mega = lambda x: f"{x / 1e6:.2f}" if x else "–"
    for (scene, name, q), e in embree.items():
        one = ours.get((scene, name, q, 1))
        if one is None:
            continue
        two = ours.get((scene, name, q, 2))
        one_b = ours.get((scene, name, q, 1, "b"))
        two_b = ours.get((scene, name, q, 2, "b"))
        one_p = ours.get((scene, name, q, 1, "p"))
        two_p = ours.get((scene, name, q, 2, "p"))
        ours_counts = counts.get((scene, name, "ours"))
        embree_counts = counts.get((scene, name, "embree"))
        shown = lambda c: ", ".join(f"{o} occluded, {h} hit" for o, h in sorted(c or ()))
        note = (
            ""
            if ours_counts == embree_counts
            else f" (counts: ours {shown(ours_counts)}; Embree {shown(embree_counts)})"
        )
        lines.append(
            f"| {scene} | {name} | {q.replace('_', ' ')} | {mega(one)} | {mega(two)} | "
            f"{mega(e)} | {one / e:.2f}{note} | {mega(one_b)} / {mega(two_b)} | "
            + (f"{one_b / e:.2f}" if one_b else "–")
            + f" | {mega(one_p)} / {mega(two_p)} | "
            + (f"{one_p / e:.2f}" if one_p else "–")
            + " |"
        )
    lines += [
        "",
        "| scene | triangles | build ours 1 / 2 threads (s) | build Embree (s) "
        "| bytes/triangle ours | resident bytes/triangle Embree |",
        "|---|---|---|---|---|---|",
    ]
    for scene in dict.fromkeys(k[0] for k in embree):
        b1 = min(builds.get((scene, "ours1"), [float("nan")]))
        b2 = min(builds.get((scene, "ours2"), [float("nan")]))
        be = min(builds.get((scene, "embree"), [float("nan")]))
        lines.append(
            f"| {scene} | {memory.get((scene, 'triangles'), '?')} | {b1:.3f} / {b2:.3f} | "
            f"{be:.3f} | {memory.get((scene, 'ours'), float('nan')):.1f} | "
            f"{memory.get((scene, 'embree'), float('nan')):.1f} |"
        )
    return "\n".join(lines)


def main():
    args = sys.argv[1:]
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    if args[0] == "--table":
        print(table(args[1:]))
        return 0
    out = None
    if "--out" in args:
        k = args.index("--out")
        out = args[k + 1]
        del args[k : k + 2]
    for path in args:
        line = json.dumps(bench(path))
        print(line)
        if out is not None:
            with open(out, "a") as f:
                f.write(line + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
