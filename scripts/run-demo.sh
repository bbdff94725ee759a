#!/usr/bin/env bash
# Used by `make run`: start the server, stream a scripted Cornell box
# sequence into out/, print the timing table, stop the server.
set -euo pipefail
BUILD_DIR=${1:-build}
ADDR=${2:-127.0.0.1:50051}
mkdir -p out
LOG=out/gistreamd.log
"$BUILD_DIR/gistreamd" --listen "$ADDR" --scenes scenes >"$LOG" 2>&1 &
PID=$!
trap 'kill -TERM $PID 2>/dev/null; wait $PID 2>/dev/null || true' EXIT
for _ in $(seq 1 300); do
  grep -q "^listening on" "$LOG" && break
  kill -0 $PID 2>/dev/null || { cat "$LOG"; echo "gistreamd exited" >&2; exit 1; }
  sleep 0.1
done
grep -q "^listening on" "$LOG" || { cat "$LOG"; echo "gistreamd did not start" >&2; exit 1; }
head -n 5 "$LOG"
"$BUILD_DIR/gistream" --server "$ADDR" script scenes/cornell_orbit.json --out out
