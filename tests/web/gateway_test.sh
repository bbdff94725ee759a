#!/usr/bin/env bash
# gistream-web as a service, without a browser (issue 31): a WebSocket
# upgrade from another site's page is refused (403) while one from the
# gateway's own origin, or from an origin given with --allow-origin, is
# accepted (101); a connection that sends no request is closed after the
# header timeout; bad flags are usage errors (exit 2), not crashes;
# --version prints the version.
# usage: gateway_test.sh BUILD_DIR SCENES_DIR
set -u
BIN=$1
SCENES=$2
[ -x "$BIN/gistream-web" ] || { echo "SKIP: gistream-web not built (libboost-dev missing)"; exit 77; }
TMP=$(mktemp -d)
cleanup() { kill $WEB $PID 2>/dev/null; wait 2>/dev/null; rm -rf "$TMP"; }
WEB=""
trap cleanup EXIT
fail() { echo "FAIL: $*"; cat "$TMP"/*.err 2>/dev/null; exit 1; }

# Flags first: no server needed.
"$BIN/gistream-web" --version | grep -q '^gistream-web [0-9]' || fail "--version"
for args in "--fps abc" "--fps -1" "--fps 1e9" "--size 0x10" "--size 10x" "--size 64x64junk"; do
  # shellcheck disable=SC2086
  "$BIN/gistream-web" $args >"$TMP/flag.out" 2>&1
  rc=$?
  [ $rc -eq 2 ] || fail "gistream-web $args exited $rc, not 2 (usage)"
  grep -q "usage:" "$TMP/flag.out" || fail "gistream-web $args printed no usage"
done

"$BIN/gistreamd" --listen 127.0.0.1:0 --scenes "$SCENES" >"$TMP/d.log" 2>"$TMP/d.err" &
PID=$!
for _ in $(seq 100); do grep -q "listening on" "$TMP/d.log" && break; sleep 0.1; done
ADDR=$(sed -n 's/^listening on //p' "$TMP/d.log")
[ -n "$ADDR" ] || fail "gistreamd did not start"
# start_web NAME [flags...]: a gateway on a free port; sets WEB, HOSTPORT.
start_web() {
  local name=$1
  shift
  "$BIN/gistream-web" --server "$ADDR" --listen 127.0.0.1:0 --size 32x24 "$@" \
    >"$TMP/$name.log" 2>"$TMP/$name.err" &
  WEB=$!
  for _ in $(seq 600); do grep -q "serving" "$TMP/$name.log" && break; sleep 0.1; done
  HOSTPORT=$(sed -n 's/^serving http:\/\/\([^/ ]*\)\/.*/\1/p' "$TMP/$name.log")
  [ -n "$HOSTPORT" ] || fail "gistream-web ($name) did not start"
}
start_web w --allow-origin http://viewer.example --allow-origin "http://127.0.0.1:1"

python3 - "$HOSTPORT" <<'EOF' || fail "origin checks"
import socket, sys, time
host, port = sys.argv[1].rsplit(":", 1)

def upgrade(origin):
    s = socket.create_connection((host, int(port)), timeout=10)
    req = (f"GET /ws?format=jpeg HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
           "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
           "Sec-WebSocket-Version: 13\r\n")
    if origin is not None:
        req += f"Origin: {origin}\r\n"
    s.sendall((req + "\r\n").encode())
    line = s.recv(4096).decode(errors="replace").split("\r\n")[0]
    s.close()
    return line

# With --allow-origin the list replaces the default: the gateway's own
# origin is refused unless listed (http://127.0.0.1:1 is another port). No
# Origin header: not a browser, let through.
cases = [("http://evil.example", "403"), ("null", "403"), (f"http://{host}:{port}", "403"),
         ("http://viewer.example", "101"), (None, "101")]
for origin, want in cases:
    got = upgrade(origin)
    print(f"Origin {origin!r}: {got}")
    if want not in got:
        sys.exit(f"Origin {origin!r}: expected {want}, got {got!r}")

# A connection that sends nothing is closed by the gateway (header timeout
# 10 s); wait at most 20 s for the close.
s = socket.create_connection((host, int(port)), timeout=20)
start = time.monotonic()
try:
    data = s.recv(1)
except socket.timeout:
    sys.exit("an idle connection was not closed within 20 s")
print(f"idle connection closed after {time.monotonic() - start:.1f} s")
s.close()
EOF
kill $WEB 2>/dev/null; wait $WEB 2>/dev/null
# Default allow-list: the gateway's own origin only.
start_web w2
python3 - "$HOSTPORT" <<'EOF' || fail "default origin checks"
import socket, sys
host, port = sys.argv[1].rsplit(":", 1)
for origin, want in [(f"http://{host}:{port}", "101"), ("http://evil.example", "403"),
                     (f"http://{host}:{int(port) + 1}", "403")]:
    s = socket.create_connection((host, int(port)), timeout=10)
    s.sendall((f"GET /ws HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
               "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
               f"Sec-WebSocket-Version: 13\r\nOrigin: {origin}\r\n\r\n").encode())
    got = s.recv(4096).decode(errors="replace").split("\r\n")[0]
    s.close()
    print(f"default list, Origin {origin!r}: {got}")
    if want not in got:
        sys.exit(f"Origin {origin!r}: expected {want}, got {got!r}")
EOF
grep -q "refused a WebSocket from origin 'http://evil.example'" "$TMP/w2.err" ||
  fail "the refusal was not logged"
echo "PASS"
