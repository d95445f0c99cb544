#!/usr/bin/env bash
# Time and error of our renders, Blender Cycles (with and without its denoiser) and Mitsuba 3,
# one after the other in one run on the same machine, against a converged reference image.
#
# Usage: benches/image/side_by_side.sh SCENE REFERENCE.exr [OUTDIR]
#   BIN (default target/release/radiosity), PY (a Python with mitsuba and numpy: /work/venv),
#   BPY (a Python 3.11 with bpy==5.0.1 and mitsuba: /work/bpyenv) may be set.
# The reference comes from benches/image/reference.py (Mitsuba, seed 0); Mitsuba's rows here use
# seed 1. Times are wall-clock of the render alone for Cycles and Mitsuba (scene build
# excluded) and of the whole command for ours (load, mesh, solve, render).
set -euo pipefail
scene=$1 ref=$2 out=${3:-$(mktemp -d)}
mkdir -p "$out"
BIN=${BIN:-target/release/radiosity}
PY=${PY:-/work/venv/bin/python}
BPY=${BPY:-/work/bpyenv/bin/python}
export DRJIT_LIBLLVM_PATH=${DRJIT_LIBLLVM_PATH:-/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1}
here=$(dirname "$0")
row() { printf '| %s | %s | %s |\n' "$1" "$2" "$3"; }
err() { "$PY" "$here/error.py" "$1" "$ref" | sed -E 's/.*RMS ([0-9.]+ %).*/\1/'; }
echo "| render | error (RMS rel. luminance, 4x4 blocks) | seconds |"
echo "|---|---|---|"
for mode in radiosity final; do
  s=$(date +%s.%N)
  "$BIN" render "$scene" --mode "$mode" -q -o "$out/ours-$mode.exr"
  t=$(echo "$(date +%s.%N) - $s" | bc)
  row "ours, --mode $mode" "$(err "$out/ours-$mode.exr")" "$(printf %.1f "$t")"
done
for spp in 4 16 64; do
  for dn in "" --denoise; do
    f="$out/cycles-$spp${dn:+-dn}.exr"
    t=$("$BPY" "$here/cycles_render.py" "$scene" --spp "$spp" $dn -o "$f" 2>/dev/null \
        | sed -nE 's/.* ([0-9.]+) s$/\1/p')
    row "Cycles $spp spp${dn:+ + OIDN}" "$(err "$f")" "$t"
  done
done
for spp in 32 128; do
  f="$out/mitsuba-$spp.exr"
  t=$("$PY" "$here/reference.py" "$scene" --spp "$spp" --seed 1 -o "$f" \
      | sed -nE 's/.* ([0-9.]+) s$/\1/p')
  row "Mitsuba 3 $spp spp" "$(err "$f")" "$t"
done
