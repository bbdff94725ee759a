#!/bin/bash
# First frames of one build, for A/B comparisons of a stage (RESULTS.md,
# "depth passes from one indirect draw list" and "sh_probes' probe cubes
# from the draw list"): starts GISTREAMD on SCENES_DIR, then renders each
# SCENE's first 64x64 frame twice (a new session each time) and prints
# the STAGE line (stage | CPU ms | GPU ms) of each. Run it for each build,
# one after the other, on a quiet machine.
#
#   docs/bench/ab_first_frames.sh GISTREAMD SOLVER STAGE SCENES_DIR SCENE...
#   e.g. docs/bench/ab_first_frames.sh build/gistreamd sh_probes rasterize_cubemaps \
#          /tmp/scale/scenes cornell_box cornell_box_x64 atrium_d3
# (tools/make_scale_scenes.py writes the scale scenes; copy
# scenes/cornell_box.gltf beside them.)
set -euo pipefail
[ $# -ge 5 ] || { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
bin=$1 solver=$2 stage=$3 scenes=$4
shift 4
cd "$(dirname "$0")/../.."
source docs/bench/start_server.sh
out=$(mktemp -d)
start_server "$bin" "$out" "$scenes"
for scene in "$@"; do
  for round in 1 2; do
    line=$(build/gistream --server "$ADDR" render --scene "$scene" --solver "$solver" \
             --size 64x64 --out "$out/${solver}_${scene}_${round}.png" 2>&1 |
           grep -E "^ *$stage " | tr -s ' ')
    echo "$bin $solver $scene round $round: $line"
  done
done
grep -i "geometry shader draws" "$out/gistreamd.log" | head -2 || true
echo "frames and server log: $out"
