#!/usr/bin/env bash
# Files nobody here wrote: every glTF 2.0 file of a public corpus (by
# default Debian's assimp-testmodels, /usr/share/assimp/models/glTF2:
# Khronos sample models, the glTF Asset Generator's cases and files that
# are broken on purpose) rendered by each solver at 32x32 through the CLI,
# one `render` per file and solver (the file uploaded each time). Per
# render: the exit status, the error (code and message), the wall time,
# the picture's mean and its NaN/Inf count (oiiotool --stats), and whether
# the server still answers its health check (a crash or a hang shows
# there). ENVIRONMENT (an equirectangular HDR/EXR) lights every file
# besides its own lights: most sample models have none (the solvers that
# read an environment then have something to show; `direct` and `avg` do
# not read one). Writes OUT_DIR/sweep.tsv and prints a summary per solver.
#
#   docs/bench/corpus_sweep.sh [BUILD_DIR] [OUT_DIR] [CORPUS_DIR] [SOLVERS] [ENVIRONMENT]
set -uo pipefail
BUILD=${1:-build}
OUT=${2:-out/corpus-sweep}
CORPUS=${3:-/usr/share/assimp/models/glTF2}
SOLVERS=${4:-"direct sh_probes avg implicit_visibility antiradiance pathtrace"}
ENVIRONMENT=${5:-}
[ -d "$CORPUS" ] || { echo "no corpus at $CORPUS (apt-get install assimp-testmodels)" >&2; exit 1; }
source "$(dirname "$0")/start_server.sh"
start_server "$BUILD/gistreamd" "$OUT" || exit 1
TSV="$OUT/sweep.tsv"
printf 'file\tsolver\trc\tseconds\tmean\tnon_finite\tserver_up\terror\n' >"$TSV"
mapfile -t FILES < <(find "$CORPUS" \( -name '*.gltf' -o -name '*.glb' \) | sort)
for f in "${FILES[@]}"; do
  rel=${f#"$CORPUS"/}
  for solver in $SOLVERS; do
    params=()
    [ "$solver" = pathtrace ] && params=(--param spp=16)
    [ -n "$ENVIRONMENT" ] && params+=(--environment "$ENVIRONMENT")
    start=$(date +%s.%N)
    timeout 300 "$BUILD/gistream" --server "$ADDR" render --scene "$f" --solver "$solver" \
      --size 32x32 --format exr --out "$OUT/frame.exr" "${params[@]}" >"$OUT/render.log" 2>&1
    rc=$?
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    mean=- nonfinite=-
    if [ $rc -eq 0 ]; then
      stats=$(oiiotool --stats "$OUT/frame.exr" 2>/dev/null)
      mean=$(echo "$stats" | sed -n 's/.*Stats Avg: *\([^ ]*\) \([^ ]*\) \([^ ]*\).*/\1 \2 \3/p' | head -1)
      nonfinite=$(echo "$stats" | sed -n 's/.*NanCount: *\([0-9 ]*\).*/\1/p; s/.*InfCount: *\([0-9 ]*\).*/\1/p' |
        tr ' ' '\n' | awk '{s += $1} END {print s + 0}')
    fi
    up=yes
    "$BUILD/gistream" --server "$ADDR" --timeout 10 health >/dev/null 2>&1 || up=no
    error=$(grep -m1 '^error:' "$OUT/render.log" | cut -c1-160 | tr '\t' ' ')
    printf '%s\t%s\t%s\t%.2f\t%s\t%s\t%s\t%s\n' "$rel" "$solver" "$rc" "$seconds" "$mean" "$nonfinite" \
      "$up" "$error" >>"$TSV"
    if [ "$up" = no ]; then
      echo "server down after $rel with $solver" >&2
      tail -20 "$OUT/gistreamd.log" >&2
      exit 1
    fi
  done
done
echo "files: ${#FILES[@]}"
awk -F'\t' 'NR > 1 {
  n[$2]++; if ($3 == 0) ok[$2]++; else err[$2]++
  if ($6 != "-" && $6 > 0) bad[$2]++
  if ($3 == 0 && $5 ~ /^0(\.0+)? 0(\.0+)? 0(\.0+)?$/) black[$2]++
  if ($4 > slow[$2]) { slow[$2] = $4; slowest[$2] = $1 }
} END {
  printf "%-20s %6s %6s %6s %10s %6s  %s\n", "solver", "renders", "ok", "errors", "non-finite", "black", "slowest"
  for (s in n) printf "%-20s %6d %6d %6d %10d %6d  %.1f s (%s)\n", s, n[s], ok[s], err[s], bad[s], black[s], slow[s], slowest[s]
}' "$TSV"
