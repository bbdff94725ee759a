#!/usr/bin/env bash
# Issue 18's deforming-scene figure, next to object_10fps.sh's rigid one:
# for each solver, the animation workload (bending_tube's own animation,
# seeked 1/30 s further each tick) at 128x128 with a 10 fps cap (one
# session, open loop at 10 Hz): frame intervals while the tube bends, and
# the time to converge once it stops (settle).
#
#   [SOLVERS="..."] docs/bench/animation_10fps.sh [BUILD_DIR] [OUT_DIR] [GISTREAMD] [DURATION]
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/bench-animation-10fps}
SERVER_BIN=${3:-$BUILD/gistreamd}
DURATION=${4:-10s}
source "$(dirname "$0")/start_server.sh"
start_server "$SERVER_BIN" "$OUT"
for solver in ${SOLVERS:-direct sh_probes avg implicit_visibility antiradiance}; do
  echo "== $solver" >&2
  "$BUILD/gistream" --server "$ADDR" bench --scene bending_tube --solver "$solver" \
    --size 128x128 --workload animation --fps 10 --update-hz 10 --sessions 1 \
    --duration "$DURATION" --warmup 2s \
    --out "$OUT/$solver" >"$OUT/$solver.log" 2>&1 || { cat "$OUT/$solver.log" >&2; exit 1; }
done
python3 "$(dirname "$0")/summarize.py" "$OUT"
