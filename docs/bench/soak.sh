#!/usr/bin/env bash
# Soak: 8 sessions for 10 minutes (direct, 128x128, mixed workload: camera,
# light and object updates in turn) while GetServerStatus is sampled every
# 30 s; prints RSS over time, its growth per minute, frames, dropped frames
# and the errors the bench saw. Not part of CI.
#
#   docs/bench/soak.sh [BUILD_DIR] [OUT_DIR] [MINUTES]
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/soak}
MINUTES=${3:-10}
source "$(dirname "$0")/start_server.sh"
start_server "$BUILD/gistreamd" "$OUT"
C="$BUILD/gistream --server $ADDR"

$C bench --solver direct --size 128x128 --workload mixed --sessions 8 --duration "${MINUTES}m" \
  --warmup 5s --out "$OUT/bench" >"$OUT/bench.log" 2>&1 &
BENCH=$!
: >"$OUT/rss.csv"
START=$(date +%s)
while kill -0 $BENCH 2>/dev/null; do
  rss=$($C status | sed -n 's/^memory *RSS \([0-9.]*\) MiB.*/\1/p')
  echo "$(( $(date +%s) - START )),$rss" >>"$OUT/rss.csv"
  sleep 30
done
wait $BENCH
python3 - "$OUT" <<'PY'
import csv, json, sys
out = sys.argv[1]
samples = [(int(t), float(r)) for t, r in csv.reader(open(f"{out}/rss.csv")) if r]
step = json.load(open(f"{out}/bench/results.json"))["steps"][0]
errors = [s["error"] for s in step["per_session"] if s["error"]]
# Growth from the first sample after the warm-up minute to the last.
steady = [s for s in samples if s[0] >= 60] or samples
growth = (steady[-1][1] - steady[0][1]) / max((steady[-1][0] - steady[0][0]) / 60, 1e-9)
print("| minute | RSS MiB |")
print("|---|---|")
for t, r in samples:
    if t % 60 < 30:
        print(f"| {t / 60:.1f} | {r:.1f} |")
print()
print(f"RSS growth after the first minute: {growth:+.2f} MiB/min; frames {step['frames']}, "
      f"fps/session {step['fps_mean']:.1f} (min {step['fps_min']:.1f}), dropped {step['dropped_frames']}, "
      f"updates answered {step['updates_answered']}/{step['updates_sent']}, "
      f"rejected {step['updates_rejected']}, failed sessions {step['failed_sessions']}, "
      f"errors: {errors or 'none'}")
PY
