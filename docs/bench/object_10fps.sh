#!/usr/bin/env bash
# Issue 12's moving-object figure: for each GI solver, a 30 s object
# workload on the Cornell box at 128x128 with a 10 fps cap (one session,
# open loop at 10 Hz): frame intervals while the block moves, and the time
# to converge once it stops (settle: the first frame with the last update
# and its GI update complete, which equals a full solve's image).
#
#   docs/bench/object_10fps.sh [BUILD_DIR] [OUT_DIR] [GISTREAMD]
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/bench-object-10fps}
SERVER_BIN=${3:-$BUILD/gistreamd}
source "$(dirname "$0")/start_server.sh"
start_server "$SERVER_BIN" "$OUT"
for solver in sh_probes avg implicit_visibility antiradiance; do
  echo "== $solver" >&2
  "$BUILD/gistream" --server "$ADDR" bench --solver "$solver" --size 128x128 --workload object \
    --fps 10 --update-hz 10 --sessions 1 --duration 30s --warmup 2s \
    --out "$OUT/$solver" >"$OUT/$solver.log" 2>&1 || { cat "$OUT/$solver.log" >&2; exit 1; }
done
python3 "$(dirname "$0")/summarize.py" "$OUT"
