#!/usr/bin/env bash
# Issue 19: a scene load's time bound, end to end.
#   docs/bench/load_budget.sh BUILD_DIR SCENES_DIR OUT_DIR [SCENE]
# SCENES_DIR: docs/bench/scale.sh's OUT_DIR/scenes. Serves them with
# --max-load-seconds 5 and renders one 64x64 `direct` frame of SCENE
# (default cornell_box_x64): the scene loads without the proxy trees not
# done in time (the server log says how many). Then, with the default
# budget, a client whose 3 s deadline passes during the load: the server
# log names the stage it stopped at.
set -uo pipefail
build=$1 scenes=$2 out=$3 scene=${4:-cornell_box_x64}
mkdir -p "$out"
serve() {  # serve LOG_SUFFIX [FLAGS...]: starts gistreamd, sets pid and addr
  local suffix=$1; shift
  "$build/gistreamd" --listen 127.0.0.1:0 --scenes "$scenes" "$@" >"$out/listen$suffix.txt" \
    2>"$out/gistreamd$suffix.log" &
  pid=$!
  for _ in $(seq 1 300); do grep -q "^listening on" "$out/listen$suffix.txt" && break; sleep 0.1; done
  addr=$(sed -n 's/^listening on //p' "$out/listen$suffix.txt")
}
serve _budget --max-load-seconds 5
"$build/gistream" --server "$addr" render --scene "$scene" --solver direct --size 64x64 \
  --out "$out/${scene}_budget5.exr" >"$out/${scene}_budget5.txt" 2>&1 || echo "failed: budget"
kill $pid; wait $pid
serve _deadline
"$build/gistream" --server "$addr" --timeout 3 render --scene "$scene" --solver direct \
  --size 64x64 --out "$out/${scene}_deadline.exr" >"$out/${scene}_deadline.txt" 2>&1
sleep 2  # the server stops at its next slice
kill $pid; wait $pid
grep -h "loaded by\|failed" "$out"/gistreamd_*.log
