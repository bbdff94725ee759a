#!/usr/bin/env bash
# End-to-end smoke test of the two binaries' command-line contract:
# gistreamd prints "listening on ADDR", gistream's subcommands work against
# it, errors exit non-zero with the server's message, SIGTERM stops cleanly.
set -euo pipefail
BIN=${1:?build dir}
SCENES=${2:?scene dir}
TMP=$(mktemp -d)
trap 'kill -9 $PID 2>/dev/null || true; rm -rf "$TMP"' EXIT

PID=""
# start_server NAME [FLAGS...]: starts gistreamd on a free loopback port,
# logs in $TMP/NAME.{out,err}, sets PID and ADDR once it listens.
start_server() {
  local name=$1
  shift
  "$BIN/gistreamd" --listen 127.0.0.1:0 --scenes "$SCENES" "$@" >"$TMP/$name.out" 2>"$TMP/$name.err" &
  PID=$!
  for _ in $(seq 1 300); do
    grep -q "^listening on" "$TMP/$name.out" && break
    sleep 0.1
  done
  ADDR=$(sed -n 's/^listening on //p' "$TMP/$name.out")
  [ -n "$ADDR" ] || { cat "$TMP/$name.err"; echo "FAIL: no 'listening on' line ($name)"; exit 1; }
}
# --version: "NAME VERSION" on stdout, exit 0, no server needed.
"$BIN/gistreamd" --version >"$TMP/v1.txt" || { echo "FAIL: gistreamd --version exited non-zero"; exit 1; }
grep -Eq '^gistreamd [0-9]+\.[0-9]+\.[0-9]+' "$TMP/v1.txt" || { cat "$TMP/v1.txt"; echo "FAIL: gistreamd --version"; exit 1; }
"$BIN/gistream" --version >"$TMP/v2.txt" || { echo "FAIL: gistream --version exited non-zero"; exit 1; }
grep -Eq '^gistream [0-9]+\.[0-9]+\.[0-9]+' "$TMP/v2.txt" || { cat "$TMP/v2.txt"; echo "FAIL: gistream --version"; exit 1; }
[ "$(cut -d' ' -f2 "$TMP/v1.txt")" = "$(cut -d' ' -f2 "$TMP/v2.txt")" ] ||
  { echo "FAIL: gistreamd and gistream report different versions"; exit 1; }

start_server main
[ "$(wc -l <"$TMP/main.out")" -eq 1 ] || { echo "FAIL: stdout has more than one line"; exit 1; }

C="$BIN/gistream --server $ADDR"
# Into files first: `grep -q` stops reading early, and with pipefail the
# client's SIGPIPE would fail the step.
$C status >"$TMP/status.txt" && grep -qi "renderer" "$TMP/status.txt" || { echo "FAIL: status"; exit 1; }
$C solvers >"$TMP/solvers.txt" || { echo "FAIL: solvers"; exit 1; }
# Every registered solver (gistreamd --list-solvers) is offered over the wire.
"$BIN/gistreamd" --list-solvers >"$TMP/registered.txt"
[ "$(wc -l <"$TMP/registered.txt")" -ge 6 ] || { echo "FAIL: --list-solvers lists fewer than 6"; exit 1; }
while read -r s; do
  grep -q "^$s - " "$TMP/solvers.txt" || { echo "FAIL: solvers lacks $s"; exit 1; }
done <"$TMP/registered.txt"
$C render --scene cornell_box --solver direct --param area_samples=8 --size 64x48 \
  --format png --out "$TMP/box.png" >/dev/null
[ "$(head -c 8 "$TMP/box.png" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] ||
  { echo "FAIL: render did not write a PNG"; exit 1; }
$C render --scene "$SCENES/furnace.gltf" --size 32x32 --format exr --out "$TMP/f.exr" >/dev/null
[ "$(head -c 4 "$TMP/f.exr" | od -An -tx1 | tr -d ' \n')" = "762f3101" ] ||
  { echo "FAIL: render of an uploaded file did not write an EXR"; exit 1; }
$C stream --frames 3 --size 48x32 --param area_samples=4 --out "$TMP/frames" >"$TMP/stream.log"
# A still direct view settles on its second frame and rests: the stream
# ends at the first keep-alive that says so (issue 27) instead of waiting
# a second per frame; it wrote every frame it got and said why it stopped.
written=$(ls "$TMP/frames" | wc -l)
if [ "$written" -lt 3 ]; then
  [ "$written" -ge 2 ] || { echo "FAIL: stream wrote $written frames"; exit 1; }
  grep -q "the view is at rest after $written of 3 frames" "$TMP/stream.log" ||
    { cat "$TMP/stream.log"; echo "FAIL: stream stopped after $written of 3 frames without saying why"; exit 1; }
fi
grep -q "shadow_maps" "$TMP/stream.log" || { echo "FAIL: stream printed no stage table"; exit 1; }
# H.264: one raw Annex-B stream (starts with a start code and an SPS).
$C stream --frames 2 --size 48x32 --param area_samples=4 --format h264 --out "$TMP/video" >/dev/null
[ "$(head -c 5 "$TMP/video/stream.h264" | od -An -tx1 | tr -d ' \n')" = "0000000167" ] ||
  { echo "FAIL: stream --format h264 did not write an Annex-B stream"; exit 1; }

# eval end to end on a tiny spec: outputs written, every row finite; a
# setting the server refuses (area_samples=0) is written down as not
# measured and the run goes on. The scene's animation (the bundled orbit
# script, 1 s) adds a table of the error during it, a row per setting.
cat >"$TMP/spec.json" <<JSON
{"size": [16, 16], "reference": {"spp": 16}, "timed_frames": 1, "pathtrace_budgets_ms": [10],
 "scenes": [{"name": "cornell_box",
   "geometry_change": [{"node_transform": {"node": 6, "translation": {"x": 0.01}}}, {"node_transform": {"node": 6}}],
   "light_change": [{"material": {"material": 3, "emissive_strength": 12}}, {"material": {"material": 3, "emissive_strength": 17}}],
   "animation": {"script": "$(cd "$SCENES" && pwd)/cornell_orbit.json", "duration_s": 1, "warmup_s": 0, "update_hz": 5}}],
 "solvers": [{"name": "direct", "grid": {"area_samples": ["4", "8", "0"]}}]}
JSON
$C eval "$TMP/spec.json" --out "$TMP/eval" --cache "$TMP/cache" >"$TMP/eval.log" 2>&1 ||
  { cat "$TMP/eval.log"; echo "FAIL: eval"; exit 1; }
for f in results.csv results.json results.md error_vs_time.png; do
  [ -s "$TMP/eval/$f" ] || { echo "FAIL: eval did not write $f"; exit 1; }
done
[ "$(grep -c '^cornell_box,' "$TMP/eval/results.csv")" -eq 4 ] || { echo "FAIL: eval rows"; exit 1; }
[ "$(grep -c 'INVALID_ARGUMENT.*area_samples' "$TMP/eval/results.csv")" -eq 1 ] &&
  grep -q 'area_samples=0 | not measured: INVALID_ARGUMENT' "$TMP/eval/results.md" ||
  { cat "$TMP/eval/results.csv"; echo "FAIL: eval did not record the refused setting"; exit 1; }
ls "$TMP/cache"/*.exr >/dev/null || { echo "FAIL: no cached reference"; exit 1; }
grep -q "During each scene's animation" "$TMP/eval/results.md" &&
  [ "$(grep -c '^| cornell_box | direct | area_samples=[48] | [0-9]' "$TMP/eval/results.md")" -eq 2 ] &&
  grep -q '^| cornell_box | direct | area_samples=0 | not measured: .*INVALID_ARGUMENT.*area_samples' "$TMP/eval/results.md" &&
  [ -s "$TMP/eval/animation/cornell_box_0/frames.csv" ] ||
  { cat "$TMP/eval/results.md" "$TMP/eval.log"; echo "FAIL: eval's animation table"; exit 1; }
if grep -v INVALID_ARGUMENT "$TMP/eval/results.csv" | grep -qiE 'nan|inf'; then echo "FAIL: non-finite metric"; exit 1; fi

# Errors: non-zero exit with the server's code and the field it names.
set +e
$C render --scene cornell_box --solver direct --param area_samples=0 --size 8x8 \
  --out "$TMP/x.jpg" 2>"$TMP/e1.log"
rc1=$?
$C render --scene no_such_scene --size 8x8 --out "$TMP/x.jpg" 2>"$TMP/e2.log"
rc2=$?
set -e
[ $rc1 -ne 0 ] && grep -q "INVALID_ARGUMENT" "$TMP/e1.log" && grep -q "area_samples" "$TMP/e1.log" ||
  { cat "$TMP/e1.log"; echo "FAIL: bad parameter"; exit 1; }
[ $rc2 -ne 0 ] && grep -q "NOT_FOUND" "$TMP/e2.log" || { cat "$TMP/e2.log"; echo "FAIL: unknown scene"; exit 1; }
$C status >/dev/null || { echo "FAIL: server stopped serving after bad input"; exit 1; }

# bench: one short step on the bundled Cornell box prints its table and
# writes the results and plots.
$C bench --sessions 1 --duration 1s --warmup 0s --size 32x32 --param area_samples=4 \
  --out "$TMP/bench" >"$TMP/bench.log" 2>&1 || { cat "$TMP/bench.log"; echo "FAIL: bench"; exit 1; }
grep -q "latency p50/p95/p99/max" "$TMP/bench.log" || { cat "$TMP/bench.log"; echo "FAIL: bench table"; exit 1; }
for f in results.csv results.json results.md latency_cdf.png fps_vs_sessions.png latency_vs_sessions.png; do
  [ -s "$TMP/bench/$f" ] || { echo "FAIL: bench did not write $f"; exit 1; }
done
# The error of every frame shown (issue 27): an object workload with a
# reference per update seq, on private copies of the named scene. frames.csv
# has a row per frame of the first session, motion frames and settle
# frames, each with a finite relMSE; the step reports its over-time summary.
$C bench --sessions 1 --duration 1s --warmup 0s --size 16x16 --format exr --workload object \
  --update-hz 5 --reference-spp 8 --param area_samples=4 --out "$TMP/bench_ref" \
  >"$TMP/bench_ref.log" 2>&1 || { cat "$TMP/bench_ref.log"; echo "FAIL: bench --reference-spp"; exit 1; }
grep -q "error over time: " "$TMP/bench_ref.log" ||
  { cat "$TMP/bench_ref.log"; echo "FAIL: bench --reference-spp printed no error over time"; exit 1; }
python3 - "$TMP/bench_ref/frames.csv" <<'PY' || { echo "FAIL: frames.csv"; exit 1; }
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
phases = {r["phase"] for r in rows}
assert {"motion", "settle"} <= phases, f"phases {phases} in {len(rows)} rows"
for r in rows:
    assert math.isfinite(float(r["relmse"])) and float(r["relmse"]) >= 0.0, r
assert len({r["frame"] for r in rows}) == len(rows), "a frame twice"
# The still picture refines after the stop: the settle frames end refined.
settle = [r for r in rows if r["phase"] == "settle"]
assert float(settle[-1]["refine_samples"]) == 16.0, settle[-1]
print(f"frames.csv: {len(rows)} rows")
PY

kill -TERM $PID
for _ in $(seq 1 100); do kill -0 $PID 2>/dev/null || break; sleep 0.1; done
if kill -0 $PID 2>/dev/null; then echo "FAIL: gistreamd ignored SIGTERM"; exit 1; fi
wait $PID && rc=0 || rc=$?
[ $rc -eq 0 ] || { cat "$TMP/main.err"; echo "FAIL: gistreamd exited $rc on SIGTERM"; exit 1; }

# SIGTERM under a long Render (4096 spp would trace for minutes): the server
# stops within its 1 s shutdown deadline plus one slice, and the client gets
# a status. 20 s bounds a hang; it is not a timing threshold.
start_server long --shutdown-deadline-s 1
"$BIN/gistream" --server "$ADDR" render --scene cornell_box --solver pathtrace --param spp=4096 \
  --size 64x64 --format exr --out "$TMP/long.exr" >"$TMP/long.log" 2>&1 &
RPID=$!
sleep 1
kill -TERM $PID
for _ in $(seq 1 200); do kill -0 $PID 2>/dev/null || break; sleep 0.1; done
if kill -0 $PID 2>/dev/null; then echo "FAIL: gistreamd still running 20 s after SIGTERM under a long Render"; exit 1; fi
wait $PID && rc=0 || rc=$?
[ $rc -eq 0 ] || { cat "$TMP/long.err"; echo "FAIL: gistreamd exited $rc on SIGTERM under a long Render"; exit 1; }
wait $RPID && rrc=0 || rrc=$?
[ $rrc -ne 0 ] && grep -Eq "UNAVAILABLE|CANCELLED" "$TMP/long.log" ||
  { cat "$TMP/long.log"; echo "FAIL: the long Render got no clean status at shutdown"; exit 1; }
# An upload the server's transport cannot hold (--max-transport-bytes 1 MB,
# an 8 MB glTF) is refused unread, and the client says why: the field, the
# cause and the server's flag (gRPC's own words are only "RST_STREAM with
# error code 11").
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); d["extras"]={"pad":"x"*8000000}; json.dump(d,open(sys.argv[2],"w"))' \
  "$SCENES/cornell_box_coarse.gltf" "$TMP/big.gltf"
start_server transport --max-transport-bytes 1000000
if "$BIN/gistream" --server "$ADDR" render --scene "$TMP/big.gltf" --solver direct --size 16x16 \
  --out "$TMP/big.png" >"$TMP/big.log" 2>&1; then
  echo "FAIL: an 8 MB upload passed a 1 MB transport limit"; exit 1
fi
grep -q "RESOURCE_EXHAUSTED: gltf: .*--max-transport-bytes" "$TMP/big.log" ||
  { cat "$TMP/big.log"; echo "FAIL: the transport refusal names neither the field nor the flag"; exit 1; }
kill -TERM $PID
wait $PID || true
echo "smoke test passed"
