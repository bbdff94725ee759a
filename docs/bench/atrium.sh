#!/usr/bin/env bash
# Issue 19's atrium specs: generates the atrium at detail 3 and 6 (149K and
# 594K triangles; tools/make_scale_scenes.py, not bundled) into
# OUT_DIR/scenes, serves them, and runs
#   - `gistream eval docs/bench/eval_atrium.json`: every GI solver's error
#     against a path-traced reference and its full-update, light-only and
#     camera-only times on both sizes (direct and avg also with
#     full_detail=true, the proxies' error against full detail);
#   - `gistream bench` with docs/bench/atrium_walk.json (the camera turns
#     around the hall while the skylight dims) for SOLVER at detail 3.
#
#   docs/bench/atrium.sh [BUILD_DIR] [OUT_DIR] [SOLVER] [eval|bench|both]
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/bench-atrium}
SOLVER=${3:-direct}
WHAT=${4:-both}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT/scenes"
/usr/bin/python3 "$here/../../tools/make_scale_scenes.py" --atrium-only "$OUT/scenes" 3 6 \
  >"$OUT/scenes.txt"
source "$here/start_server.sh"
start_server "$BUILD/gistreamd" "$OUT" "$OUT/scenes"
addr=$ADDR
if [ "$WHAT" != bench ]; then
  "$BUILD/gistream" --server "$addr" eval "$here/eval_atrium.json" --out "$OUT/eval"
fi
if [ "$WHAT" != eval ]; then
  "$BUILD/gistream" --server "$addr" bench --scene atrium_d3 --solver "$SOLVER" --size 128x128 \
    --workload "$here/atrium_walk.json" --sessions 1 --duration 20s --warmup 2s \
    --out "$OUT/bench_$SOLVER"
fi
