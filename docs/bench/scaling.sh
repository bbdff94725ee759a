#!/usr/bin/env bash
# The gistream bench figures of docs/RESULTS.md: concurrency sweeps for
# `direct` and two GI solvers at two sizes and two workloads, and the
# isolation run (a direct stream's frame intervals with and without a
# pathtrace Render looping beside it). Not part of CI: it takes about
# 10 minutes on 2 cores.
#
#   docs/bench/scaling.sh [BUILD_DIR] [OUT_DIR] [GISTREAMD]
#
# Starts its own gistreamd (GISTREAMD, default BUILD_DIR/gistreamd) on a
# free loopback port, writes one folder per run under OUT_DIR (default
# out/bench-scaling) and prints the markdown tables (docs/bench/summarize.py).
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/bench-scaling}
SERVER_BIN=${3:-$BUILD/gistreamd}
source "$(dirname "$0")/start_server.sh"
start_server "$SERVER_BIN" "$OUT"
C="$BUILD/gistream --server $ADDR"

run() {  # name, then bench arguments
  local name=$1
  shift
  echo "== $name: gistream bench $*" >&2
  $C bench "$@" --out "$OUT/$name" >"$OUT/$name.log" 2>&1 || { cat "$OUT/$name.log" >&2; return 1; }
}

# Cheap GI settings, so 4 sessions still get frames on llvmpipe.
IV="--param bins_per_face=8"
AR="--param bins=64 --param iterations=2"
for size in 128x128 320x240; do
  for workload in orbit object; do
    run "direct-$size-$workload" --solver direct --size "$size" --workload "$workload" \
      --sessions 1,2,4,8,16 --duration 5s --warmup 1s
    run "implicit_visibility-$size-$workload" --solver implicit_visibility $IV --size "$size" \
      --workload "$workload" --sessions 1,2,4 --duration 5s --warmup 1s
    run "antiradiance-$size-$workload" --solver antiradiance $AR --size "$size" \
      --workload "$workload" --sessions 1,2,4 --duration 5s --warmup 1s
  done
done
# Isolation: one direct stream at 10 fps, alone and beside a looping
# 256x256 256-spp pathtrace Render.
run "isolation-solo" --solver direct --size 128x128 --fps 10 --sessions 1 --duration 15s --warmup 2s
run "isolation-interfered" --solver direct --size 128x128 --fps 10 --sessions 1 --duration 15s \
  --warmup 2s --interfere "render --solver pathtrace --param spp=256 --size 256x256"
python3 "$(dirname "$0")/summarize.py" "$OUT"
