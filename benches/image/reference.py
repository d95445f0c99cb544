#!/usr/bin/env python3
"""A path-traced reference image of a TOML or OBJ scene, from the scene's own camera (Mitsuba 3).

The geometry, materials and emitters are read as benches/suite/reference.py reads them (its
`load` and `scene_dict`: the same Mitsuba scene the per-object references use), and the camera
from the TOML file's [camera] table (eye, target, up, fov_y). Integrator `path`, max_depth 256,
Russian roulette from depth 5; a box pixel filter of one pixel, as our renderer's pixels are the
mean over their square. The image is linear radiance (W m^-2 sr^-1), written as EXR, or as PFM
when the output name ends in `.pfm` (the standard Portable Float Map that our renderer's
`read_pfm` reads: `PF\n{w} {h}\n-1.0\n`, then little-endian f32 RGB, bottom row first).
The committed references made with it are in benches/image/reference/ (README.md there).

Usage (LLVM back end: apt-get install libllvm19):
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
    python3 benches/image/reference.py scenes/cornell/scene.toml --spp 4096 -o ref.exr
    (or `-o ref.pfm` for PFM)
"""

import argparse
import pathlib
import sys
import tempfile
import time
import tomllib

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "suite"))

import mitsuba as mi  # noqa: E402
import numpy as np  # noqa: E402
import reference as suite  # noqa: E402


def write_pfm(path, bitmap):
    """Standard colour PFM: header `PF\\n{w} {h}\\n-1.0\\n` (negative scale: little-endian),
    then float32 RGB, rows from the bottom of the image to the top."""
    rgb = np.array(bitmap, dtype=np.float32)[..., :3]  # rows top to bottom
    h, w = rgb.shape[:2]
    with open(path, "wb") as f:
        f.write(f"PF\n{w} {h}\n-1.0\n".encode("ascii"))
        f.write(np.ascontiguousarray(rgb[::-1]).astype("<f4").tobytes())


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene")
    p.add_argument("--width", type=int, help="default: the scene's [render] width, else 512")
    p.add_argument("--height", type=int, help="default: the scene's [render] height, else 512")
    p.add_argument("--spp", type=int, default=4096)
    p.add_argument("--variant", default="llvm_ad_rgb")
    p.add_argument("--seed", type=int, default=0, help="sampler seed (a reference and a "
                   "cheaper render compared with it need different seeds)")
    p.add_argument("--passes", type=int, default=1, help="independent renders averaged, of "
                   "seeds SEED, SEED + 1000, ... (each of --spp samples): the noise falls as "
                   "1/sqrt(passes) where one render of passes x spp would not fit in memory")
    p.add_argument("-o", "--output", required=True)
    args = p.parse_args()
    args.width, args.height = suite.image_size(args.scene, args.width, args.height)
    mi.set_variant(args.variant)
    objects = suite.load(args.scene)
    scale = suite.scene_scale(objects)
    cam = tomllib.loads(pathlib.Path(args.scene).read_text())["camera"]
    with tempfile.TemporaryDirectory() as d:
        sd = suite.scene_dict(objects, scale, d, 256, 5)
        sd["sensor"] = {
            "type": "perspective", "fov": float(cam.get("fov_y", 39.3)), "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[c * scale for c in cam["eye"]],
                target=[c * scale for c in cam["target"]], up=cam.get("up", [0, 1, 0])),
            "film": {"type": "hdrfilm", "width": args.width, "height": args.height,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": args.spp},
        }
        scene = mi.load_dict(sd)
        t = time.time()
        total = None
        for k in range(args.passes):
            # Evaluated here, not lazily later.
            image = np.array(mi.render(scene, spp=args.spp, seed=args.seed + 1000 * k),
                             dtype=np.float64)
            total = image if total is None else total + image
        bitmap = mi.Bitmap((total / args.passes).astype(np.float32))
        seconds = time.time() - t
    if args.output.lower().endswith(".pfm"):
        write_pfm(args.output, bitmap)
    else:
        bitmap.write(args.output)
    print(f"{args.output}: {args.width}x{args.height}, {args.passes} x {args.spp} spp, "
          f"{seconds:.2f} s")


if __name__ == "__main__":
    main()
