#!/usr/bin/env bash
# Issue 12's time to converge: for each GI solver, the object workload on
# the Cornell box at 128x128 with a 10 fps cap (one session, open loop at
# 10 Hz, EXR frames); once the block stops, the frames and ms until relMSE
# against a pathtrace reference (REFERENCE_SPP spp) stays within 5 % of a
# full solve's, both rendered on a fresh copy of the scene in the final
# state (gistream bench --reference-spp).
#
# WORKLOAD is any of bench's (object by default, or a script's .json: the
# references replay every update sent up to each frame's seq).
#
#   docs/bench/converge_10fps.sh [BUILD_DIR] [OUT_DIR] [GISTREAMD] [DURATION] [REFERENCE_SPP] [SOLVERS] [WORKLOAD] [SIZE]
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/bench-converge-10fps}
SERVER_BIN=${3:-$BUILD/gistreamd}
DURATION=${4:-10s}
SPP=${5:-256}
SOLVERS=${6:-"sh_probes avg implicit_visibility antiradiance"}
WORKLOAD=${7:-object}
SIZE=${8:-128x128}
source "$(dirname "$0")/start_server.sh"
start_server "$SERVER_BIN" "$OUT"
SCENE="$(cd "$(dirname "$0")/../../scenes" && pwd)/cornell_box.gltf"
for solver in $SOLVERS; do
  echo "== $solver" >&2
  "$BUILD/gistream" --server "$ADDR" bench --scene "$SCENE" --solver "$solver" --size "$SIZE" \
    --format exr --workload "$WORKLOAD" --fps 10 --update-hz 10 --sessions 1 --duration "$DURATION" \
    --warmup 2s --reference-spp "$SPP" --out "$OUT/$solver" >"$OUT/$solver.log" 2>&1 ||
    { cat "$OUT/$solver.log" >&2; exit 1; }
  grep "converge:" "$OUT/$solver.log" | sed "s/^/$solver /"
done
