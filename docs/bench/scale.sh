#!/usr/bin/env bash
# Issue 19: cost against triangle count, proxies against full detail.
#   docs/bench/scale.sh BUILD_DIR OUT_DIR [SOLVER...]
# Generates the Cornell box at 1x/4x/16x/64x the triangles and the atrium at
# detail 3 and 6 (tools/make_scale_scenes.py) into OUT_DIR/scenes, serves
# them, and renders one 64x64 first frame per scene, solver and setting
# (proxies, full_detail=true) with `gistream render`, printing its
# per-stage timings into OUT_DIR/SCENE_SOLVER_SETTING.txt and the EXR
# beside it. docs/bench/scale_summary.py tabulates them (with the RMS difference of the
# proxy image against the full-detail one).
set -euo pipefail
build=$1 out=$2; shift 2
solvers=("${@:-direct}")
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out/scenes"
/usr/bin/python3 "$here/../../tools/make_scale_scenes.py" "$out/scenes" 3 6 >"$out/scenes.txt"
cp "$here/../../scenes/cornell_box.gltf" "$out/scenes/"
source "$here/start_server.sh"
start_server "$build/gistreamd" "$out" "$out/scenes"
addr=$ADDR
for scene in cornell_box cornell_box_x4 cornell_box_x16 cornell_box_x64 atrium_d3 atrium_d6; do
  for solver in "${solvers[@]}"; do
    for setting in proxies full; do
      extra=()
      [ "$setting" = full ] && extra=(--param full_detail=true)
      "$build/gistream" --server "$addr" render --scene "$scene" --solver "$solver" \
        --size 64x64 --out "$out/${scene}_${solver}_${setting}.exr" "${extra[@]}" \
        >"$out/${scene}_${solver}_${setting}.txt" 2>&1 || echo "failed: $scene $solver $setting"
    done
  done
done
