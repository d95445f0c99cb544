#!/usr/bin/env python3
"""Error against refinement on the reference suite, measured, as a table and an SVG plot.

For each setting of one refinement knob it runs benches/suite/compare.py (our solver against the
Mitsuba references) and records every scene's worst object error (worst channel) and the RMS
of the errors over the scene's objects; then prints a Markdown table and plots both against the
knob (log axes). The errors must fall with refinement towards the references' own noise (about
0.2 % per object); an error that rises is a bug.

Usage: python3 benches/suite/convergence.py --knob epsilon --values 1e-3 1e-4 1e-5 \\
           --solver hierarchical -o docs/convergence-hierarchical.svg [SCENE ...]
       python3 benches/suite/convergence.py --knob elements --values 1000 4000 16000 \\
           -o docs/convergence.svg [SCENE ...]
"""

import argparse
import json
import math
import pathlib
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenes", nargs="*")
    p.add_argument("--knob", required=True, help="the option refined, e.g. elements or epsilon")
    p.add_argument("--values", nargs="+", required=True)
    p.add_argument("--solver", help="passed as --solver")
    p.add_argument("-o", "--output", required=True, help="the SVG")
    p.add_argument("--json", help="also write the measurements here")
    args = p.parse_args()
    runs = {}
    for value in args.values:
        extra = ["--" + args.knob, value] + (["--solver", args.solver] if args.solver else [])
        with tempfile.TemporaryDirectory() as d:
            out = pathlib.Path(d) / "c.json"
            subprocess.run([sys.executable, str(HERE / "compare.py"), "--json", str(out),
                            *args.scenes, "--", *extra], check=True, capture_output=True)
            runs[value] = json.loads(out.read_text())
    scenes = sorted({s for r in runs.values() for s in r})
    table = {}
    for s in scenes:
        for v in args.values:
            r = runs[v].get(s)
            if not r:
                continue
            errors = [o["rel_error"] for o in r["objects"].values()]
            worst = r["worst_rel_error"]
            rms = math.sqrt(sum(e * e for e in errors) / len(errors))
            table.setdefault(s, {})[v] = (worst, rms, r["solve_seconds"], r["worst"])
    knob = args.knob
    print(f"| scene | " + " | ".join(f"{knob} {v}" for v in args.values) + " |")
    print("|---|" + "---|" * len(args.values))
    for s in scenes:
        cells = []
        for v in args.values:
            if v in table.get(s, {}):
                w, rms, t, _ = table[s][v]
                cells.append(f"{w * 100:+.2f} % (RMS {rms * 100:.2f} %, {t:.1f} s)")
            else:
                cells.append("—")
        print(f"| {s} | " + " | ".join(cells) + " |")
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.5))
    xs = [float(v) for v in args.values]
    for s in scenes:
        pts = [(float(v), table[s][v]) for v in args.values if v in table.get(s, {})]
        axes[0].plot([x for x, _ in pts], [abs(t[0]) * 100 for _, t in pts], "o-", label=s)
        axes[1].plot([x for x, _ in pts], [t[1] * 100 for _, t in pts], "o-", label=s)
    for ax, title in zip(axes, ["worst object (worst channel)", "RMS over objects"]):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(knob + (" (finer to the left)" if knob == "epsilon" else ""))
        ax.set_ylabel("error against Mitsuba 3 (%)")
        ax.set_title(title)
        ax.axhline(1.0, color="grey", lw=0.8, ls="--")
        ax.axhline(0.2, color="grey", lw=0.8, ls=":")
        if knob == "epsilon":
            ax.invert_xaxis()
        ax.set_xticks(xs)
        ax.set_xticklabels(args.values)
    axes[1].legend(fontsize=7)
    fig.suptitle(f"{args.solver or 'default solver'}: error against {knob} "
                 "(dashed 1 %, dotted: the references' noise)")
    fig.tight_layout()
    fig.savefig(args.output)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(table, indent=1) + "\n")


if __name__ == "__main__":
    main()
