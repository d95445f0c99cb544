#!/usr/bin/env python3
"""The error of a rendered image against a reference: RMS of the relative luminance error over
4 x 4-pixel blocks (the picture measure of docs/raytracing.md), and the mean relative error (bias).

Luminance Y = 0.2126 R + 0.7152 G + 0.0722 B of linear radiance; the block means are compared,
so pixel noise finer than a block averages out as it does for the eye, and blocks whose reference
is darker than 1e-3 of the image's mean are left out (relative errors of black are noise).
Images: EXR, PFM or HDR (linear), of the same size.

`--inner K` leaves out the K rows and columns of blocks along each border (where a scene seen
from outside shows one-pixel rims against black, whose blocks' relative errors are coverage
noise).

Usage: python3 benches/image/error.py IMAGE REFERENCE [--block 4] [--inner K]
"""

import argparse
import sys

import mitsuba as mi
import numpy as np


def luminance_of(rgb):
    """Luminance of an H x W x 3 (or more channels) array of linear RGB."""
    return np.asarray(rgb, dtype=np.float64)[..., :3] @ np.array([0.2126, 0.7152, 0.0722])


def luminance(path):
    mi.set_variant("scalar_rgb")
    return luminance_of(np.array(mi.Bitmap(path), dtype=np.float64))


def blocks(y, k):
    h, w = (y.shape[0] // k) * k, (y.shape[1] // k) * k
    return y[:h, :w].reshape(h // k, k, w // k, k).mean(axis=(1, 3))


def block_relative_errors(a, b, k=4, inner=0):
    """The relative errors (A - B) / B of the K x K-block means of two luminance arrays, over
    the blocks kept (B brighter than 1e-3 of its mean; `inner` border blocks left out)."""
    a, b = blocks(a, k), blocks(b, k)
    if inner > 0:
        a, b = a[inner:-inner, inner:-inner], b[inner:-inner, inner:-inner]
    keep = b > 1e-3 * b.mean()
    return (a[keep] - b[keep]) / b[keep]


def error(image, reference, k=4, inner=0):
    a, b = luminance(image), luminance(reference)
    if a.shape != b.shape:
        sys.exit(f"sizes differ: {a.shape} vs {b.shape}")
    rel = block_relative_errors(a, b, k, inner)
    return float(np.sqrt(np.mean(rel ** 2))), float(np.mean(rel))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("image")
    p.add_argument("reference")
    p.add_argument("--block", type=int, default=4)
    p.add_argument("--inner", type=int, default=0)
    args = p.parse_args()
    rms, bias = error(args.image, args.reference, args.block, args.inner)
    print(f"{args.image}: RMS {rms * 100:.2f} %, mean {bias * 100:+.2f} %")


if __name__ == "__main__":
    main()
