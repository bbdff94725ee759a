#!/usr/bin/env bash
# Container smoke test (issue 15): builds the image (`make image`), runs it
# as shipped (TLS, bearer tokens, read-only root, no capabilities), waits for
# health on the plaintext health port, renders one frame over TLS with a
# token (and sees UNAUTHENTICATED without one), then stops it and checks it
# exited 0 within the grace period, and that gistreamd and gistream-web
# print a version with the commit. Prints build time, image size, startup
# and first-frame time.
#
#   deploy/smoke_test.sh [--no-build]
#
# Environment: ENGINE (podman, else docker), IMAGE (gistream/gistreamd:latest),
# CONTEXT (the source tree to build, default this checkout),
# ENGINE_OPTS / BUILD_OPTS / RUN_OPTS (extra engine, build and run options;
# deploy/README.md lists what podman needs in a sandbox), GRACE_S (stop's
# grace period, default 20, longer than the image's 10 s shutdown deadline),
# CLIENT (the gistream binary, default build/gistream; else the image's own,
# run with exec).
set -euo pipefail
cd "$(dirname "$0")/.."

ENGINE=${ENGINE:-$(command -v podman >/dev/null 2>&1 && echo podman || echo docker)}
IMAGE=${IMAGE:-gistream/gistreamd:latest}
ENGINE_OPTS=${ENGINE_OPTS:-}
BUILD_OPTS=${BUILD_OPTS:-}
RUN_OPTS=${RUN_OPTS:-}
GRACE_S=${GRACE_S:-20}
CLIENT=${CLIENT:-build/gistream}
PORT=${PORT:-50151}
HEALTH_PORT=${HEALTH_PORT:-50152}
engine() { $ENGINE $ENGINE_OPTS "$@"; }
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }
fail() { echo "smoke: FAIL: $*" >&2; [ -n "${cid:-}" ] && engine logs "$cid" 2>&1 | tail -20 >&2; exit 1; }

work=$(mktemp -d)
cid=""
cleanup() {
  [ -n "$cid" ] && engine rm -f "$cid" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT

if [ "${1:-}" != "--no-build" ]; then
  start=$(now)
  make image ENGINE="$ENGINE" ENGINE_OPTS="$ENGINE_OPTS" BUILD_OPTS="$BUILD_OPTS" IMAGE="$IMAGE" \
    CONTEXT="${CONTEXT:-.}"
  echo "smoke: build: $(since "$start") s"
fi
size=$(engine image inspect --format '{{.Size}}' "$IMAGE")
echo "smoke: image $IMAGE: $(awk -v b="$size" 'BEGIN { printf "%.0f MiB", b / 1048576 }')"

# Secrets as a Kubernetes TLS secret lays them out (tls.crt, tls.key, ca.crt)
# and a token file; readable by the image's user (65534).
scripts/dev_certs.sh "$work/tls" >/dev/null
mv "$work/tls/server.crt" "$work/tls/tls.crt"
mv "$work/tls/server.key" "$work/tls/tls.key"
token=$(openssl rand -hex 24)
printf '%s smoke scenes=4 sessions=4\n' "$token" > "$work/tokens"
chmod 755 "$work" "$work/tls"
chmod 644 "$work/tls/"* "$work/tokens"

start=$(now)
# shellcheck disable=SC2086
cid=$(engine run -d $RUN_OPTS --read-only --cap-drop ALL --security-opt no-new-privileges \
  -p "127.0.0.1:$PORT:50051" -p "127.0.0.1:$HEALTH_PORT:50052" \
  -v "$work/tls:/etc/gistream/tls:ro" -v "$work/tokens:/etc/gistream/tokens/tokens:ro" \
  "$IMAGE")

if [ -x "$CLIENT" ]; then
  client() { "$CLIENT" "$@"; }
  ca="$work/tls/ca.crt" server="localhost:$PORT" health="127.0.0.1:$HEALTH_PORT" out="$work"
else
  client() { engine exec -e GISTREAM_TOKEN="${GISTREAM_TOKEN:-}" "$cid" gistream "$@"; }
  ca=/etc/gistream/tls/ca.crt server="localhost:50051" health="127.0.0.1:50052" out=/tmp
fi

for _ in $(seq 240); do
  client --server "$health" --timeout 2 health >/dev/null 2>&1 && break
  [ "$(engine inspect --format '{{.State.Running}}' "$cid")" = true ] || fail "the container exited"
  sleep 0.5
done
client --server "$health" --timeout 2 health >/dev/null || fail "health never SERVING"
echo "smoke: healthy after $(since "$start") s"

if GISTREAM_TOKEN="" client --server "$server" --ca "$ca" solvers >"$work/noauth" 2>&1; then
  fail "a call without a token succeeded"
fi
grep -q UNAUTHENTICATED "$work/noauth" || fail "no token: $(cat "$work/noauth")"
echo "smoke: no token -> UNAUTHENTICATED"

start=$(now)
GISTREAM_TOKEN=$token client --server "$server" --ca "$ca" render --scene cornell_box \
  --size 128x96 --out "$out/frame.png" >"$work/render" 2>&1 || fail "render: $(cat "$work/render")"
echo "smoke: first frame over TLS with a token (LoadScene + Render, 128x96, direct): $(since "$start") s"
head -1 "$work/render"

start=$(now)
engine stop -t "$GRACE_S" "$cid" >/dev/null
stopped=$(since "$start")
code=$(engine inspect --format '{{.State.ExitCode}}' "$cid")
[ "$code" = 0 ] || fail "exit code $code after stop"
awk -v s="$stopped" -v g="$GRACE_S" 'BEGIN { exit !(s < g) }' || fail "stop took $stopped s (grace $GRACE_S s)"
engine logs "$cid" 2>&1 | grep -q "shut down" || fail "no 'shut down' in the log"
echo "smoke: stopped in $stopped s (grace $GRACE_S s), exit 0"

# Both servers start from the image and name the commit they were built
# from (`make image` passes it; the context has no .git).
for bin in gistreamd gistream-web; do
  # shellcheck disable=SC2086
  version=$(engine run --rm $RUN_OPTS --entrypoint "/usr/local/bin/$bin" "$IMAGE" --version) ||
    fail "$bin --version"
  echo "smoke: $version"
  if [ "${1:-}" != "--no-build" ] && ! [[ $version =~ \+[0-9a-f]{7,}$ ]]; then
    fail "$bin's version names no commit: $version"
  fi
done
echo "smoke: PASS"
