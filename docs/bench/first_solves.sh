#!/usr/bin/env bash
# First solves beside a stream (RESULTS.md, "First solves off the render
# thread"): one `direct` stream on cornell_box_x4 (26K triangles, 128x128,
# 10 fps cap, camera orbit) for 100 s while, from 25 s on, one Render each
# of avg, antiradiance, implicit_visibility and sh_probes opens its first
# solve on the same scene. The stream's longest frame interval is the stall.
#   docs/bench/first_solves.sh BUILD_DIR OUT_DIR
set -euo pipefail
build=$1 out=$2
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out/scenes"
[ -f "$out/scenes/cornell_box_x4.gltf" ] ||
  /usr/bin/python3 "$here/../../tools/make_scale_scenes.py" "$out/scenes" 1 >"$out/scenes.txt"
source "$here/start_server.sh"
start_server "$build/gistreamd" "$out" "$out/scenes"
addr=$ADDR
"$build/gistream" --server "$addr" bench --scene cornell_box_x4 --solver direct --size 128x128 \
  --fps 10 --sessions 1 --duration 100s --warmup 2s --out "$out/bench" >"$out/bench.txt" 2>&1 &
bench=$!
sleep 25
for solver in avg antiradiance implicit_visibility sh_probes; do
  "$build/gistream" --server "$addr" render --scene cornell_box_x4 --solver "$solver" \
    --size 64x64 --out "$out/$solver.png" >>"$out/renders.txt" 2>&1
done
wait $bench
grep -A2 "^sessions" "$out/bench.txt"
