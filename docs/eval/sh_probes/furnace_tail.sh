#!/usr/bin/env bash
# What sh_probes' geometric tail estimate does on the white furnace, where
# the exact answer is L = E / (1 - rho): one EXR frame per setting through
# `gistream script` (which can set the albedo), mean over the image by
# OpenImageIO's iinfo. Usage: furnace_tail.sh BUILD_DIR SERVER_ADDR
set -euo pipefail
BIN=${1:?build dir}
ADDR=${2:?server address}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
echo "| rho | exact | bounces | tail_estimate | mean | error |"
echo "| --- | --- | --- | --- | --- | --- |"
for rho in 0.5 0.9; do
  exact=$(python3 -c "print(1 / (1 - $rho))")
  for bounces in 1 2 4; do
    for tail in false true; do
      cat >"$TMP/s.json" <<JSON
{"scene": "furnace", "solver": "sh_probes",
 "params": {"grid": "8", "bounces": "$bounces", "tolerance": "0", "tail_estimate": "$tail"},
 "size": [64, 64], "format": "exr", "frames": 1,
 "tracks": [{"type": "material", "material": "furnace", "keys": [{"frame": 0, "base_color": [$rho, $rho, $rho]}]}]}
JSON
      "$BIN/gistream" --server "$ADDR" script "$TMP/s.json" --out "$TMP/out" >/dev/null
      mean=$(iinfo --stats "$TMP/out/frame_00000.exr" | sed -n 's/.*Stats Avg: \([0-9.e+-]*\).*/\1/p')
      err=$(python3 -c "print(f'{($mean - $exact) / $exact * 100:+.1f} %')")
      echo "| $rho | $exact | $bounces | $tail | $mean | $err |"
    done
  done
done
