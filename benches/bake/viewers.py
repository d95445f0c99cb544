#!/usr/bin/env python3
"""Checks a bake in the viewers people will open it in: Blender (bpy) and three.js (headless
Chromium), each rendering the .glb from the file's own camera, against our own render of the
same view, and runs the Khronos glTF validator on the file.

For SCENE (a built-in scene name or a scene file):

1. `radiosity bake SCENE -o DIR/baked.glb --lightmap-size N` (the exposure of its picture, in
   stops, is read back from `materials[0].extras.lightmap.exposure`);
2. `radiosity render SCENE -o DIR/ours.pfm` at W × H (the scene's render size unless given):
   linear radiance of the default camera;
3. Blender: `blender_render.py` beside this file imports baked.glb with Blender's glTF importer
   and renders its camera with Cycles (Standard view, box filter) to DIR/blender.png;
4. three.js: `page.html` beside this file, served over http from 127.0.0.1, loads baked.glb
   with GLTFLoader and draws it from `gltf.cameras[0]` (sRGB output, no tone mapping);
   Chromium's screenshot is DIR/three.png;
5. the comparison, for each viewer: its PNG sRGB-decoded to linear against ours × 2^stops,
   each channel clipped to [0, 1] as the 8-bit texture is, in luminance Y = 0.2126 R +
   0.7152 G + 0.0722 B over 4 × 4-pixel blocks: the RMS of the blocks' relative errors
   (Y − Y_ours) / Y_ours, their mean (bias) and 99th percentile, over the blocks whose
   reference is brighter than 10⁻³ of its mean (`radiosity::render::block_error`). The row
   `ours-8bit` is our render itself through 8-bit sRGB: the floor that quantisation sets.
   DIR/<viewer>-error.png maps each block's relative error (red too bright, blue too dark,
   full at ±10 %);
6. `validate.mjs` beside this file: the Khronos validator's counts on baked.glb, and with
   `--lit` also on the lit-mesh export `radiosity solve SCENE --export DIR/lit.glb`.

Prints one JSON object (also written to DIR/summary.json).

Setup (once): python3.11 -m venv V && V/bin/pip install bpy==5.0.1 pillow   (bpy brings
numpy); node/npm and Debian's chromium; the npm packages `three` and `gltf-validator` are
installed into --node-dir on first use.

Usage: V/bin/python benches/bake/viewers.py [SCENE] --out DIR [--lightmap-size 1024]
       [--width W --height H] [--radiosity target/release/radiosity] [--threads 1] [--lit]
       [--reuse]  (keeps DIR/baked.glb, ours.pfm and lit.glb when they exist)
"""

import argparse
import base64
import functools
import http.server
import io
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent
THREE = "0.187.0"
VALIDATOR = "2.0.0-dev.3.10"
LUMA = np.array([0.2126, 0.7152, 0.0722])


def run(cmd, **kw):
    """Runs `cmd` (niced), returning (stdout, seconds); exits with its stderr on failure."""
    start = time.perf_counter()
    p = subprocess.run(["nice", *map(str, cmd)], capture_output=True, text=True, **kw)
    seconds = time.perf_counter() - start
    if p.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({p.returncode}):\n{p.stderr[-4000:]}")
    return p.stdout, seconds


def glb_json(path):
    data = Path(path).read_bytes()
    magic, _, _ = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67:
        sys.exit(f"{path}: not a .glb")
    length, kind = struct.unpack_from("<II", data, 12)
    return json.loads(data[20:20 + length])


def read_pfm(path):
    """A PFM as an H × W × 3 float64 array, top row first."""
    data = Path(path).read_bytes()
    parts = data.split(b"\n", 3)
    if parts[0] != b"PF":
        sys.exit(f"{path}: not a colour PFM")
    w, h = map(int, parts[1].split())
    scale = float(parts[2])
    dtype = "<f4" if scale < 0 else ">f4"
    pixels = np.frombuffer(parts[3], dtype=dtype, count=w * h * 3).reshape(h, w, 3)
    return pixels[::-1].astype(np.float64)


def srgb_to_linear(v):
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(v):
    v = np.clip(v, 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def read_png_linear(path):
    """An 8-bit PNG decoded from sRGB to linear, H × W × 3."""
    rgb = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
    return srgb_to_linear(rgb)


def blocks(y, k):
    h, w = (y.shape[0] // k) * k, (y.shape[1] // k) * k
    return y[:h, :w].reshape(h // k, k, w // k, k).mean(axis=(1, 3))


def stats(r):
    mags = np.sort(np.abs(r))
    rank = min(max(int(np.ceil(0.99 * len(mags))), 1), len(mags)) - 1
    return {
        "rms": round(float(np.sqrt(np.mean(r ** 2))), 5),
        "bias": round(float(np.mean(r)), 5),
        "p99": round(float(mags[rank]), 5),
        "blocks": len(r),
        "over_3pct": int((mags > 0.03).sum()),
    }


def block_error(image, reference, clipped, k=4):
    """`radiosity::render::block_error` on two linear RGB arrays (`block_rms`, `bias`, `p99`,
    the ratio of the kept blocks' summed luminances), the same over the `inner` blocks only,
    and the per-block relative errors (NaN where a block is left out).

    `inner` leaves out, besides the black blocks, the blocks where the reference has a clipped
    pixel (the light's face and rim: our picture clips after averaging a pixel's samples, a
    viewer averages clipped texels) or a pixel with no surface (a silhouette against the empty
    background, whose block error is the difference of two coverage estimates)."""
    a, b = blocks(image @ LUMA, k), blocks(reference @ LUMA, k)
    keep = b > 1e-3 * b.mean()
    rel = np.full(b.shape, np.nan)
    rel[keep] = (a[keep] - b[keep]) / b[keep]
    full = stats(rel[keep])
    empty = (reference @ LUMA) <= 0.0
    inner = keep & (blocks((clipped | empty).astype(np.float64), k) == 0)
    return {
        "block_rms": full["rms"],
        "bias": full["bias"],
        "p99": full["p99"],
        "mean_ratio": round(float(a[keep].sum() / b[keep].sum()), 5),
        "blocks": full["blocks"],
        "blocks_over_3pct": full["over_3pct"],
        "inner": stats(rel[inner]),
    }, rel


def error_map(rel, k, path):
    """Each block's relative error as a colour: red too bright, blue too dark (full at ±10 %),
    grey where left out."""
    t = np.clip(np.nan_to_num(rel, nan=0.0) / 0.10, -1, 1)
    img = np.ones(rel.shape + (3,))
    img[..., 1] = 1 - np.abs(t)
    img[..., 0] = np.where(t < 0, 1 + t, 1)
    img[..., 2] = np.where(t > 0, 1 - t, 1)
    img[np.isnan(rel)] = 0.5
    img = np.repeat(np.repeat(img, k, axis=0), k, axis=1)
    Image.fromarray((img * 255).round().astype(np.uint8)).save(path)


def node_modules(folder):
    """A node_modules with three.js and the validator, installed on first use."""
    folder = Path(folder)
    ok = all((folder / "node_modules" / p / "package.json").exists()
             for p in ("three", "gltf-validator"))
    if not ok:
        folder.mkdir(parents=True, exist_ok=True)
        run(["npm", "install", "--silent", "--prefix", folder,
             f"three@{THREE}", f"gltf-validator@{VALIDATOR}"])
    return folder / "node_modules"


def validate(glb, modules):
    out, seconds = run(["node", HERE / "validate.mjs", glb],
                       env={**os.environ, "NODE_MODULES_DIR": str(modules)})
    report = json.loads(out)
    report["seconds"] = round(seconds, 2)
    # Infos and hints by code, not one line each.
    codes = {}
    for m in report.pop("messages"):
        key = f"{m['severity']}:{m['code']}"
        codes[key] = codes.get(key, 0) + 1
    report["codes"] = codes
    return report


def threejs(glb, png, w, h, modules, work, ss=1):
    """Screenshots page.html drawing `glb` in headless Chromium; returns what the page reported
    (with `canvas_vs_screenshot`: the largest byte difference between the canvas's own pixels
    and the screenshot)."""
    site = Path(work) / "site"
    site.mkdir(parents=True, exist_ok=True)
    shutil.copy(HERE / "page.html", site / "page.html")
    shutil.copy(glb, site / "model.glb")
    link = site / "node_modules"
    if not link.exists():
        link.symlink_to(Path(modules).resolve())
    state = {"done": threading.Event(), "report": None}
    handler = functools.partial(PageHandler, state, directory=str(site))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        url = (f"http://127.0.0.1:{server.server_port}/page.html?f=model.glb&w={w}&h={h}"
               f"&ss={ss}")
        cmd = ["nice", "chromium", "--headless", "--no-sandbox", "--disable-gpu",
               "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
               "--virtual-time-budget=5000", f"--window-size={w},{h}",
               f"--screenshot={Path(png).resolve()}", url]
        start = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        seconds = time.perf_counter() - start
    finally:
        state["done"].set()
        server.shutdown()
    facts = state["report"]
    if p.returncode != 0 or facts is None or not Path(png).exists():
        sys.exit(f"chromium failed ({p.returncode}):\n{p.stderr[-4000:]}")
    if "error" in facts:
        sys.exit(f"three.js: {facts['error']}")
    canvas = facts.pop("canvas")
    raw = base64.b64decode(canvas.split(",", 1)[1])
    a = np.asarray(Image.open(io.BytesIO(raw)).convert("RGB"), dtype=np.int16)
    facts["chromium_s"] = round(seconds, 2)
    if ss > 1:
        # The canvas's N × N pixels per pixel, averaged in linear light.
        lin = srgb_to_linear(a / 255.0)
        lin = lin.reshape(h, ss, w, ss, 3).mean(axis=(1, 3))
        return facts, lin
    b = np.asarray(Image.open(png).convert("RGB"), dtype=np.int16)
    facts["canvas_vs_screenshot"] = int(np.abs(a - b).max()) if a.shape == b.shape else "sizes differ"
    return facts, read_png_linear(png)


class PageHandler(http.server.SimpleHTTPRequestHandler):
    """Files, plus `GET hold` (answered once the page has reported) and `POST done` (the
    page's report)."""

    def __init__(self, state, *args, **kw):
        self.state = state
        super().__init__(*args, **kw)

    def do_GET(self):
        if self.path.split("?")[0] == "/hold":
            self.state["done"].wait(timeout=300)
            self.send_response(204)
            self.end_headers()
        else:
            super().do_GET()

    def do_POST(self):
        body = self.rfile.read(int(self.headers.get("Content-Length", 0)))
        if self.path.split("?")[0] == "/done":
            self.state["report"] = json.loads(body)
            self.state["done"].set()
        self.send_response(204)
        self.end_headers()

    def log_message(self, *args):
        pass


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene", nargs="?", default="cornell")
    p.add_argument("--out", required=True, help="folder for the files (created)")
    p.add_argument("--lightmap-size", type=int, default=1024)
    p.add_argument("--width", type=int)
    p.add_argument("--height", type=int)
    p.add_argument("--radiosity", default=shutil.which("radiosity") or "target/release/radiosity")
    p.add_argument("--threads", type=int, default=1, help="Blender's render threads")
    p.add_argument("--samples", type=int, default=16, help="Cycles samples per pixel")
    p.add_argument("--node-dir", default=str(Path.home() / ".cache/radiosity-bench/node"))
    p.add_argument("--viewers", default="blender,threejs")
    p.add_argument("--supersample", type=int, default=8,
                   help="also draw three.js at N x N pixels per pixel, averaged in linear "
                        "light (a diagnostic row; 1: not; at most 4096 pixels a side)")
    p.add_argument("--lit", action="store_true",
                   help="also export the lit mesh (solve --export DIR/lit.glb) and validate it")
    p.add_argument("--reuse", action="store_true",
                   help="keep DIR/baked.glb and DIR/ours.pfm when they exist")
    args = p.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    glb, ours_pfm = out / "baked.glb", out / "ours.pfm"
    summary = {"scene": args.scene, "lightmap_size": args.lightmap_size}
    times = {}

    if not (args.reuse and glb.exists()):
        _, times["bake_s"] = run([args.radiosity, "bake", args.scene, "-o", glb,
                                  "--lightmap-size", args.lightmap_size, "--quiet"])
    size = []
    if args.width:
        size += ["--width", args.width]
    if args.height:
        size += ["--height", args.height]
    if not (args.reuse and ours_pfm.exists()):
        _, times["ours_s"] = run([args.radiosity, "render", args.scene, "-o", ours_pfm,
                                  "--quiet", *size])
    ours = read_pfm(ours_pfm)
    h, w = ours.shape[:2]
    doc = glb_json(glb)
    stops = doc["materials"][0]["extras"]["lightmap"]["exposure"]
    summary.update({"width": w, "height": h, "exposure_stops": stops,
                    "glb_bytes": glb.stat().st_size,
                    "camera_aspect": doc.get("cameras", [{}])[0].get("perspective", {})
                    .get("aspectRatio")})
    reference = np.clip(ours * 2.0 ** stops, 0.0, 1.0)
    quantised = srgb_to_linear(np.round(linear_to_srgb(reference) * 255) / 255)
    clipped = (ours * 2.0 ** stops >= 1.0).any(axis=2)
    results = {"ours-8bit": block_error(quantised, reference, clipped)[0]}

    modules = node_modules(args.node_dir)
    summary["validator"] = validate(glb, modules)
    if args.lit:
        lit = out / "lit.glb"
        if not (args.reuse and lit.exists()):
            _, times["lit_export_s"] = run([args.radiosity, "solve", args.scene, "--export", lit,
                                            "--quiet"])
        summary["lit_glb_bytes"] = lit.stat().st_size
        summary["lit_validator"] = validate(lit, modules)
    viewers = args.viewers.split(",")
    if "blender" in viewers:
        png = out / "blender.png"
        stdout, seconds = run([sys.executable, HERE / "blender_render.py", glb, png,
                               "--width", w, "--height", h, "--threads", args.threads,
                               "--samples", args.samples])
        facts = json.loads(stdout.strip().splitlines()[-1])
        facts["wall_s"] = round(seconds, 2)
        err, rel = block_error(read_png_linear(png), reference, clipped)
        error_map(rel, 4, out / "blender-error.png")
        results["blender"] = {**err, **facts}
    if "threejs" in viewers:
        png = out / "three.png"
        facts, image = threejs(glb, png, w, h, modules, out)
        if image.shape[:2] != (h, w):
            sys.exit(f"three.js screenshot is {image.shape[1]} x {image.shape[0]}, not {w} x {h}")
        err, rel = block_error(image, reference, clipped)
        error_map(rel, 4, out / "three-error.png")
        results["threejs"] = {**err, **facts}
    # A WebGL canvas larger than 4096 pixels a side may be cut down by the browser.
    ss = min(args.supersample, 4096 // max(w, h))
    if ss > 1 and "threejs" in viewers:
        # The same page drawn at N × N pixels per pixel without multisampling and averaged
        # in linear light: the textures alone, without the resolve of sRGB-encoded samples.
        png = out / "three-ss.png"
        facts, image = threejs(glb, png, w, h, modules, out, ss)
        Image.fromarray((linear_to_srgb(image) * 255).round().astype(np.uint8)).save(png)
        err, rel = block_error(image, reference, clipped)
        error_map(rel, 4, out / "three-ss-error.png")
        results[f"threejs-ss{ss}"] = {**err, **facts}
    summary["viewers"] = results
    summary["times"] = {k: round(v, 2) for k, v in times.items()}
    text = json.dumps(summary, indent=1)
    (out / "summary.json").write_text(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
