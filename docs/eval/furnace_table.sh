#!/usr/bin/env bash
# docs/RESULTS.md's white-furnace table (issue 14): the bundled furnace
# (closed 2 m cube, emission 1) with every wall's albedo set to rho, so the
# exact answer is L = 1 / (1 - rho) (`direct`: 1 + rho); every solver run to
# convergence, 16 x 16 EXR through `gistream render` (the albedo is set in
# an uploaded copy of the scene), mean over the image by OpenImageIO's
# iinfo, iterations and cap_reached from the frame stats, ms = the server's
# frame time. Usage: [SOLVERS="antiradiance sh_probes"] furnace_table.sh
# BUILD_DIR SERVER_ADDR [RHO...] (SOLVERS: only those rows).
set -euo pipefail
BIN=${1:?build dir}
ADDR=${2:?server address}
shift 2
RHOS=${*:-0.5 0.9 0.99 0.999}
SCENES=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../scenes" && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# solver|settings shown|--param flags
CASES=(
  "pathtrace|64 spp|spp=64"
  "sh_probes|grid 4, tolerance 1e-4, bounces <= 32, tail_estimate|grid=4 tolerance=1e-4 bounces=32 tail_estimate=true"
  "implicit_visibility|tolerance 1e-4, bounces <= 4096|tolerance=1e-4 bounces=4096"
  "antiradiance|tolerance 1e-4, iterations <= 4096|tolerance=1e-4 iterations=4096"
  "avg|vpls 2048, bounces <= 1024|vpls=2048 bounces=1024"
  "direct|defaults|"
)
echo "| solver | settings | ρ | mean L | exact | error | iterations | cap reached | ms |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for rho in $RHOS; do
  python3 - "$SCENES/furnace.gltf" "$TMP/furnace_$rho.gltf" "$rho" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
r = float(sys.argv[3])
d["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = [r, r, r, 1.0]
json.dump(d, open(sys.argv[2], "w"))
PY
  for c in "${CASES[@]}"; do
    IFS='|' read -r solver shown params <<<"$c"
    if [ -n "${SOLVERS:-}" ] && [[ " $SOLVERS " != *" $solver "* ]]; then continue; fi
    args=()
    for p in $params; do args+=(--param "$p"); done
    out=$("$BIN/gistream" --server "$ADDR" render --scene "$TMP/furnace_$rho.gltf" --solver "$solver" \
      "${args[@]}" --size 16x16 --format exr --out "$TMP/o.exr" 2>&1)
    mean=$(iinfo --stats "$TMP/o.exr" | sed -n 's/.*Stats Avg: \([0-9.e+-]*\).*/\1/p' | head -1)
    stat() { echo "$out" | grep -oE "[ ]$1=[0-9.e+-]+" | head -1 | cut -d= -f2 || true; }
    iters=$(stat bounces_run)
    [ -n "$iters" ] || iters=$(stat iterations)
    cap=$(stat cap_reached)
    ms=$(echo "$out" | sed -n 's/^wrote .*, \([0-9.]*\) ms$/\1/p')
    python3 - "$solver" "$shown" "$rho" "$mean" "${iters:--}" "${cap:--}" "$ms" <<'PY'
import sys
solver, shown, rho, mean, iters, cap, ms = sys.argv[1:]
r, m = float(rho), float(mean)
exact = 1 + round(r * 255) / 255 if solver == "direct" else 1 / (1 - r)
print(f"| `{solver}` | {shown} | {rho} | {m:.4g} | {exact:.4g} | {100 * (m - exact) / exact:+.1f} % "
      f"| {iters.split('.')[0]} | {cap.split('.')[0]} | {float(ms):.0f} |")
PY
  done
done
