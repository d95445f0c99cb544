#!/usr/bin/env python3
"""Compares `radiosity solve SCENE --stats` with the Mitsuba references of the suite.

For every scene with a reference JSON (benches/suite/reference/<scene>.json) it runs our solver
(default options unless given after `--`), matches objects by name and prints, per object, our
radiosity, the reference, the relative error of the worst channel and that error in reference
standard errors, plus the area ratio (ours / reference: catches geometry read differently).
Emitters are compared like the rest (their B includes E = pi L_e, so their errors are small).

Usage: python3 benches/suite/compare.py [--bin target/release/radiosity] [--json out.json]
                                        [SCENE ...] [-- solver options]
"""

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent


def main():
    argv = sys.argv[1:]
    extra = []
    if "--" in argv:
        i = argv.index("--")
        argv, extra = argv[:i], argv[i + 1:]
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenes", nargs="*")
    p.add_argument("--bin", default=str(ROOT / "target" / "release" / "radiosity"))
    p.add_argument("--json", help="write the comparison here")
    p.add_argument("--verbose", "-v", action="store_true", help="every object, not only the worst")
    args = p.parse_args(argv)
    refs = sorted((HERE / "reference").glob("*.json"))
    summary = {}
    for ref_path in refs:
        name = ref_path.stem
        if args.scenes and name not in args.scenes:
            continue
        ref = json.loads(ref_path.read_text())
        with tempfile.TemporaryDirectory() as d:
            stats = pathlib.Path(d) / "s.json"
            t = time.time()
            r = subprocess.run([args.bin, "solve", str(ROOT / ref["scene"]), "--stats", str(stats),
                                "-q", *extra], capture_output=True, text=True)
            dt = time.time() - t
            if r.returncode != 0:
                print(f"{name}: solve failed: {r.stderr.strip()}")
                continue
            ours = {o["name"]: o for o in json.loads(stats.read_text())["objects"]}
        rows = []
        for o in ref["objects"]:
            mine = ours.get(o["name"])
            if mine is None:
                rows.append((o["name"], None))
                continue
            errs = []
            for c in range(3):
                b, e, s = mine["radiosity"][c], o["radiosity"][c], o["se"][c]
                errs.append(((b - e) / e if e else float("inf"), (b - e) / s if s else float("inf")))
            worst = max(range(3), key=lambda c: abs(errs[c][0]))
            rows.append((o["name"], {
                "ours": mine["radiosity"], "reference": o["radiosity"], "se": o["se"],
                "rel_error": errs[worst][0], "in_se": errs[worst][1], "channel": "rgb"[worst],
                "area_ratio": mine["area"] / o["area"]}))
        missing = [n for n, r in rows if r is None] + [n for n in ours if n not in
                                                        {o["name"] for o in ref["objects"]}]
        rows = [(n, r) for n, r in rows if r is not None]
        rows.sort(key=lambda x: -abs(x[1]["rel_error"]))
        print(f"== {name} (solve {dt:.1f} s; reference worst rel. SE "
              f"{ref['worst_rel_se'] * 100:.2f} %)")
        for n, r in rows if args.verbose else rows[:3]:
            print(f"  {n:22s} err {r['rel_error'] * 100:+8.2f} % ({r['channel']}, "
                  f"{r['in_se']:+8.1f} SE)  ours {r['ours'][1]:.4g} ref {r['reference'][1]:.4g} (g)"
                  f"  area ratio {r['area_ratio']:.5f}")
        if missing:
            print(f"  names not matched: {missing}")
        summary[name] = {"solve_seconds": round(dt, 2), "objects": dict(rows), "unmatched": missing,
                         "worst": rows[0][0] if rows else None,
                         "worst_rel_error": rows[0][1]["rel_error"] if rows else None}
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(summary, indent=1) + "\n")


if __name__ == "__main__":
    main()
