#!/usr/bin/env bash
# docs/RESULTS.md's scale table (issue 14): the bundled furnace (albedo 0.5,
# emission 1, so L = 2; `direct`: 1.5) with its mesh node scaled by s from
# 1e-4 to 1e5, every solver at the all-solver suite's furnace settings
# (tests/gl/all_solvers_test.cpp), 16 x 16 EXR through `gistream render`,
# the image mean over the mean at s = 1 (needs s = 1 among the scales;
# last column: that mean). Usage:
# scale_table.sh BUILD_DIR SERVER_ADDR [SCALE...]
set -euo pipefail
BIN=${1:?build dir}
ADDR=${2:?server address}
shift 2
SCALES=${*:-1e-4 1e-3 1 1e3 1e5}
SCENES=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../scenes" && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# solver|--param flags (the suite's furnace_params)
CASES=(
  "direct|"
  "pathtrace|spp=64"
  "sh_probes|grid=4 bounces=12 tolerance=0"
  "avg|"
  "implicit_visibility|bounces=12 bins_per_face=8"
  "antiradiance|iterations=8"
)
header="| solver |"
rule="| --- |"
for s in $SCALES; do header+=" $s |"; rule+=" --- |"; done
header+=" L at 1 |"
rule+=" --- |"
echo "$header"
echo "$rule"
for s in $SCALES; do
  python3 - "$SCENES/furnace.gltf" "$TMP/furnace_$s.gltf" "$s" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
s = float(sys.argv[3])
for n in d["nodes"]:
    if n.get("mesh") == 0:
        n["scale"] = [s, s, s]
json.dump(d, open(sys.argv[2], "w"))
PY
done
for c in "${CASES[@]}"; do
  IFS='|' read -r solver params <<<"$c"
  args=()
  for p in $params; do args+=(--param "$p"); done
  row="| \`$solver\` |"
  ref=""
  means=()
  for s in $SCALES; do
    "$BIN/gistream" --server "$ADDR" render --scene "$TMP/furnace_$s.gltf" --solver "$solver" \
      "${args[@]}" --size 16x16 --format exr --out "$TMP/o.exr" >/dev/null 2>&1
    m=$(iinfo --stats "$TMP/o.exr" | sed -n 's/.*Stats Avg: \([0-9.e+-]*\).*/\1/p' | head -1)
    means+=("$m")
    [ "$s" = "1" ] && ref=$m
  done
  for m in "${means[@]}"; do
    row+=" $(python3 -c "print(f'{float(\"$m\") / float(\"$ref\"):.4f}')") |"
  done
  echo "$row $(python3 -c "print(f'{float(\"$ref\"):.4f}')") |"
done
