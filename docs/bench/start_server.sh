# Sourced by the docs/bench scripts: starts GISTREAMD (a gistreamd binary)
# on a free loopback port with SCENES_DIR (default: the bundled scenes),
# logs into OUT_DIR, waits for "listening on", sets ADDR and stops the
# server when the script exits.
start_server() {  # GISTREAMD OUT_DIR [SCENES_DIR]
  local bin=$1 out=$2
  local scenes=${3:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../../scenes" && pwd)}
  mkdir -p "$out"
  "$bin" --listen 127.0.0.1:0 --scenes "$scenes" >"$out/listen.txt" 2>"$out/gistreamd.log" &
  SERVER_PID=$!
  trap 'kill $SERVER_PID 2>/dev/null || true' EXIT
  for _ in $(seq 1 300); do grep -q "^listening on" "$out/listen.txt" && break; sleep 0.1; done
  ADDR=$(sed -n 's/^listening on //p' "$out/listen.txt")
  [ -n "$ADDR" ] || { cat "$out/gistreamd.log" >&2; echo "gistreamd did not start" >&2; return 1; }
}
