#!/usr/bin/env python3
"""Trace a ray workload with Intel Embree (PyPI `embreex`) for comparison with our BVH.

Usage: python3 benches/embree_rays.py WORKLOAD.bin [WORKLOAD.bin ...]

The workload file is written by `radiosity::accel::bench::write_workload` (little-endian):
u32 triangle count N, u32 ray count M, N*9 f32 (a, b, c of each triangle), M*6 f32 (origin,
direction). Every ray is traced with t in (0, 1e30), as the Rust side does.

`EmbreeScene.run` loops over the rays in Cython, one `rtcIntersect1`/`rtcOccluded1` call per
ray, on the calling thread: Embree's own threads (TBB) are used for the scene build only. The
script reports the CPU time next to the wall time so that this can be checked.

Prints one JSON object per workload: best-of-3 rays/s for occlusion and closest hit, the build
time and the occluded/hit counts (to compare with the Rust figures).
"""

import json
import struct
import sys
import time

import numpy as np
from embreex import rtcore_scene
from embreex.mesh_construction import TriangleMesh

T_MAX = 1e30
REPETITIONS = 3


def load(path):
    with open(path, "rb") as f:
        data = f.read()
    n_tris, n_rays = struct.unpack_from("<II", data, 0)
    floats = np.frombuffer(data, dtype="<f4", offset=8)
    if floats.size != n_tris * 9 + n_rays * 6:
        raise ValueError(f"{path}: size does not match its counts")
    tris = floats[: n_tris * 9].reshape(n_tris, 3, 3).astype(np.float32)
    rays = floats[n_tris * 9 :].reshape(n_rays, 6)
    origins = np.ascontiguousarray(rays[:, :3], dtype=np.float32)
    dirs = np.ascontiguousarray(rays[:, 3:], dtype=np.float32)
    return tris, origins, dirs


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


def bench(path):
    tris, origins, dirs = load(path)
    n = len(origins)

    def build():
        scene = rtcore_scene.EmbreeScene()
        TriangleMesh(scene, tris)
        # The scene is committed (the BVH built) on the first query.
        scene.run(origins[:1], dirs[:1], dists=T_MAX, query="OCCLUDED")
        return scene

    build_s, build_cpu, scene = best_of(build)
    occl_s, occl_cpu, occl = best_of(
        lambda: scene.run(origins, dirs, dists=T_MAX, query="OCCLUDED")
    )
    hit_s, hit_cpu, prim = best_of(
        lambda: scene.run(origins, dirs, dists=T_MAX, query="INTERSECT")
    )
    return {
        "workload": path,
        "triangles": len(tris),
        "rays": n,
        "embree_build_seconds": build_s,
        "build_cpu_over_wall": build_cpu / build_s,
        "occlusion_rays_per_second": n / occl_s,
        "closest_hit_rays_per_second": n / hit_s,
        "occlusion_cpu_over_wall": occl_cpu / occl_s,
        "closest_hit_cpu_over_wall": hit_cpu / hit_s,
        # Occluded rays report geomID 0 (the one mesh), unoccluded ones -1.
        "occluded": int(np.count_nonzero(occl != -1)),
        "hits": int(np.count_nonzero(prim != -1)),
    }


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    for path in sys.argv[1:]:
        print(json.dumps(bench(path)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
