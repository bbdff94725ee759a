#!/usr/bin/env bash
# Issue 29: gistream's pathtrace against an independent renderer, Blender
# Cycles (Debian 12's blender 3.4 package; apt-get install blender
# python3-numpy), on Cornell box variants whose materials both renderers
# model alike (variants.py: Lambertian through KHR_materials_specular or
# KHR_materials_ior, a double-sided lamp a centimetre under the ceiling, a
# gold block).
# Each variant is rendered by gistream twice (seeds 1 and 2, the noise
# baseline) and by Cycles once, SPP samples per pixel at SIZE x SIZE, and
# compared by compare.py.
#
#   docs/bench/cycles/compare_cycles.sh [BUILD_DIR] [OUT_DIR] [SPP] [SIZE] [VARIANTS]
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
BUILD=${1:-build}
OUT=${2:-out/cycles}
SPP=${3:-1024}
SIZE=${4:-128}
VARIANTS=${5:-"lambert ior_1 near_2s gold"}
command -v blender >/dev/null || { echo "needs blender: apt-get install blender python3-numpy" >&2; exit 1; }
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"
python3 "$HERE/variants.py" "$HERE/../../../scenes/cornell_box.gltf" "$OUT" >/dev/null
source "$HERE/../start_server.sh"
start_server "$BUILD/gistreamd" "$OUT/server" "$OUT"
for v in $VARIANTS; do
  for seed in 1 2; do
    "$BUILD/gistream" --server "$ADDR" render --scene "$v" --solver pathtrace --size "${SIZE}x${SIZE}" \
      --param "spp=$SPP" --param "seed=$seed" --format exr --out "$OUT/${v}_gistream_$seed.exr" \
      >"$OUT/${v}_gistream_$seed.log" 2>&1 || { cat "$OUT/${v}_gistream_$seed.log" >&2; exit 1; }
  done
  SECONDS=0
  blender -b --factory-startup --python "$HERE/render_cycles.py" -- "$OUT/$v.gltf" \
    "$OUT/${v}_cycles.exr" "$SPP" 1 "$SIZE" >"$OUT/${v}_cycles.log" 2>&1 ||
    { tail -20 "$OUT/${v}_cycles.log" >&2; exit 1; }
  echo "== $v ($SPP spp, ${SIZE}x$SIZE; Cycles took ${SECONDS} s)"
  python3 "$HERE/compare.py" "$OUT/${v}_gistream_1.exr" "$OUT/${v}_gistream_2.exr" "$OUT/${v}_cycles.exr"
done
