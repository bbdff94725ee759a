#!/usr/bin/env bash
# Issue 19's cost against triangle count through `gistream eval`: the
# Cornell box at 1x, 4x, 16x and 64x the triangles (tools/make_scale_scenes.py,
# generated into OUT_DIR/scenes) with every solver at its defaults:
# first-frame, full-update, light-only and camera-only times and the error
# against a 1024-spp path-traced reference of each size
# (docs/bench/eval_scale.json).
#   docs/bench/scale_eval.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/bench-scale-eval}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT/scenes"
[ -f "$OUT/scenes/cornell_box_x64.gltf" ] ||
  /usr/bin/python3 "$here/../../tools/make_scale_scenes.py" "$OUT/scenes" 1 >"$OUT/scenes.txt"
cp "$here/../../scenes/cornell_box.gltf" "$OUT/scenes/"
source "$here/start_server.sh"
start_server "$BUILD/gistreamd" "$OUT" "$OUT/scenes"
addr=$ADDR
"$BUILD/gistream" --server "$addr" eval "$here/eval_scale.json" --out "$OUT/eval" \
  --cache "$OUT/reference-cache"
