#!/usr/bin/env bash
# Time and error of our renders, Blender Cycles (with and without its denoiser) and Mitsuba 3,
# one after the other in one run on the same machine, against a converged reference image.
#
# Usage: benches/image/side_by_side.sh SCENE REFERENCE [OUTDIR]
#   SCENE: a .toml/.obj scene file, or a built-in scene name NAME whose file is
#   scenes/NAME/scene.toml (e.g. `cornell`); every tool is given that same file, and the Python
#   scripts read its [camera] as our renderer does.
#   REFERENCE: .exr or .pfm (e.g. benches/image/reference/cornell_256.pfm), of the image size.
#   Environment: WIDTH, HEIGHT (image size; default the scene's [render] size, else 512),
#   BIN (default target/release/radiosity), PY (a Python with mitsuba and numpy; default python3),
#   BPY (a Python 3.11 with bpy==5.0.1 and mitsuba; required for the Cycles rows).
# The reference comes from benches/image/reference.py (Mitsuba, seeds 0, 1000, ..., 7000); Mitsuba's rows here use
# seed 1. Times are wall-clock of the render alone for Cycles (bpy.ops.render.render: scene sync,
# BVH, sampling, denoising, file write) and Mitsuba (mi.render, JIT compilation included; scene
# load excluded), and of the whole command for ours (load, mesh, form factors, solve, render).
# The last column is the 1-minute load average read just before each row (the machine may be
# shared). The rows are also written to OUTDIR/results.tsv (render, error %, seconds, load).
set -euo pipefail
scene=$1 ref=$2 out=${3:-$(mktemp -d)}
mkdir -p "$out"
here=$(dirname "$0")
if [[ ! -f $scene && -f $here/../../scenes/$scene/scene.toml ]]; then
  scene=$here/../../scenes/$scene/scene.toml
fi
BIN=${BIN:-target/release/radiosity}
PY=${PY:-python3}
BPY=${BPY:-python3.11}
export DRJIT_LIBLLVM_PATH=${DRJIT_LIBLLVM_PATH:-/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1}
size=()
[[ -n ${WIDTH:-} ]] && size+=(--width "$WIDTH")
[[ -n ${HEIGHT:-} ]] && size+=(--height "$HEIGHT")
tsv=$out/results.tsv
: >"$tsv"
load() { cut -d' ' -f1 /proc/loadavg; }
row() {
  printf '| %s | %s | %s | %s |\n' "$1" "$2" "$3" "$4"
  printf '%s\t%s\t%s\t%s\n' "$1" "${2% %}" "$3" "$4" >>"$tsv"
}
err() { "$PY" "$here/error.py" "$1" "$ref" | sed -E 's/.*RMS ([0-9.]+ %).*/\1/'; }
echo "scene $scene, size ${WIDTH:-scene}x${HEIGHT:-scene}, reference $ref, outputs in $out" >&2
echo "| render | error (RMS rel. luminance, 4x4 blocks) | seconds | load |"
echo "|---|---|---|---|"
ours() {  # ours NAME LABEL ARGS...
  local name=$1 label=$2 l s t
  shift 2
  l=$(load)
  s=$(date +%s.%N)
  "$BIN" render "$scene" "${size[@]}" "$@" -q --stats "$out/ours-$name.json" \
    -o "$out/ours-$name.exr"
  t=$(echo "$(date +%s.%N) - $s" | bc)
  row "ours, $label" "$(err "$out/ours-$name.exr")" "$(printf %.1f "$t")" "$l"
}
ours radiosity "--mode radiosity" --mode radiosity
ours final "--mode final" --mode final
ours quality-final "--quality final" --quality final
ours hierarchical "--solver hierarchical" --solver hierarchical
ours gauss-seidel "--solver gauss-seidel" --solver gauss-seidel
for spp in 4 16 64 256; do
  for dn in "" --denoise; do
    f="$out/cycles-$spp${dn:+-dn}.exr"
    l=$(load)
    t=$("$BPY" "$here/cycles_render.py" "$scene" "${size[@]}" --spp "$spp" $dn -o "$f" \
        2>/dev/null | sed -nE 's/.* ([0-9.]+) s$/\1/p')
    row "Cycles $spp spp${dn:+ + OIDN}" "$(err "$f")" "$t" "$l"
  done
done
for spp in 16 32 64 128 256 512; do
  f="$out/mitsuba-$spp.exr"
  l=$(load)
  t=$("$PY" "$here/reference.py" "$scene" "${size[@]}" --spp "$spp" --seed 1 -o "$f" \
      | sed -nE 's/.* ([0-9.]+) s$/\1/p')
  row "Mitsuba 3 $spp spp" "$(err "$f")" "$t" "$l"
done
echo
echo "Our stages (seconds, from --stats):"
for name in radiosity final quality-final hierarchical gauss-seidel; do
  "$PY" -c 'import json, sys
t = json.load(open(sys.argv[1]))["timings"]
print(f"- {sys.argv[2]}: " + ", ".join(f"{k} {v:.2f}" for k, v in t.items()))' \
    "$out/ours-$name.json" "$name"
done
