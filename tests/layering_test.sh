#!/usr/bin/env bash
# The ARCHITECTURE module table, checked: each folder may include only the
# project folders listed for it (its own layer and those below). The CMake
# layer libraries enforce the same direction at link time; this catches a
# header-only reach upwards too.
set -euo pipefail
ROOT=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$ROOT"

# folder: allowed include prefixes (first path component of "x/...")
declare -A ALLOWED=(
  [common/util]="util"
  [common/encode]="util encode"
  [server/gl]="util gl"
  [server/scene]="util encode gl scene"
  [server/render]="util encode gl scene render"
  [server/solvers]="util encode gl scene render solvers"
  [server/engine]="util encode gl scene render solvers engine"
  [server/service]="util engine service gistream grpc"
  [server/metrics]="util engine metrics"
  [client]="util encode gistream grpc client"
)

# Third-party headers some files include with quotes.
EXTERNAL="absl"

# The table row of a file: the longest folder in ALLOWED that holds it
# (common/encode/video belongs to common/encode).
row_of() {
  local f=$1 best=""
  for dir in "${!ALLOWED[@]}"; do
    if [[ $f == "$dir"/* && ${#dir} -gt ${#best} ]]; then best=$dir; fi
  done
  echo "$best"
}

failed=0
checked=0
while IFS= read -r file; do
  row=$(row_of "$file")
  [[ -n $row ]] || continue
  checked=$((checked + 1))
  while IFS= read -r inc; do
    [[ $inc == */* ]] || continue  # a header next to the file
    prefix=${inc%%/*}
    # A solver's own binding table (shaders/<solver>/bindings.glsl, read by
    # its GLSL and its C++): only that solver's folder may include it.
    if [[ $inc == */bindings.glsl && $file == server/solvers/"$prefix"/* ]]; then continue; fi
    ok=0
    for a in ${ALLOWED[$row]} $EXTERNAL; do [[ $prefix == "$a" ]] && ok=1; done
    if (( !ok )); then
      echo "FAIL: $file includes \"$inc\" ($row may include: ${ALLOWED[$row]})"
      failed=1
    fi
  done < <(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$file")
done < <(find common server client \( -name '*.cpp' -o -name '*.h' \) | sort)
(( checked > 100 )) || { echo "FAIL: only $checked files checked"; exit 1; }
if (( failed )); then exit 1; fi
echo "layering: $checked files, every include follows the module table"
