#!/usr/bin/env bash
# gistream-web as a service, without a browser (issue 31): a WebSocket
# upgrade from another site's page is refused (403) while one from the
# gateway's own origin, or from an origin given with --allow-origin, is
# accepted (101); a connection that sends no request is closed after the
# header timeout; bad flags are usage errors (exit 2), not crashes;
# --version prints the version; connections that never send a request
# and running out of descriptors do not keep /healthz out or spin the
# accept loop, and viewers are limited (issue 30); /healthz follows the
# backend and a viewer after a backend restart gets frames (issue 31);
# --solvers, --page-params and --max-messages bound what a page asks for.
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
for _ in $(seq 300); do grep -q "listening on" "$TMP/d.log" && break; sleep 0.1; done
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
# Log lines are timestamped (ISO-8601 UTC, milliseconds) and levelled.
grep -Eq "^[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9:.]{12}Z warn +refused a WebSocket" "$TMP/w2.err" ||
  fail "the gateway's log lines carry no timestamp and level"
kill $WEB 2>/dev/null; wait $WEB 2>/dev/null

# Bounded (issue 30): 40 connections that never send a request, past
# --max-connections 8, cost the gateway only its oldest ones, so /healthz
# still answers; a second viewer past --max-viewers 1 is told 503.
start_web w3 --max-connections 8 --max-viewers 1
python3 - "$HOSTPORT" <<'EOF' || fail "connection limit"
import socket, sys
host, port = sys.argv[1].rsplit(":", 1)
idle = [socket.create_connection((host, int(port)), timeout=10) for _ in range(40)]
s = socket.create_connection((host, int(port)), timeout=5)
s.sendall(f"GET /healthz HTTP/1.1\r\nHost: {host}\r\n\r\n".encode())
got = s.recv(4096).decode(errors="replace").split("\r\n")[0]
print("healthz beside 40 idle connections:", got)
if " 200 " not in got:
    sys.exit("healthz did not answer 200 beside 40 idle connections")
# The oldest idle ones were closed to make room (recv sees EOF).
closed = 0
for c in idle[:8]:
    c.settimeout(5)
    try:
        closed += c.recv(1) == b""
    except (socket.timeout, ConnectionResetError):
        pass
print(f"oldest idle connections closed: {closed} of 8")
if closed < 8:
    sys.exit("the oldest idle connections were not closed")

def upgrade():
    c = socket.create_connection((host, int(port)), timeout=10)
    c.sendall((f"GET /ws HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
               "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
               "Sec-WebSocket-Version: 13\r\n\r\n").encode())
    return c, c.recv(4096).decode(errors="replace").split("\r\n")[0]

first, line1 = upgrade()
second, line2 = upgrade()
print("viewers:", line1, "/", line2)
if "101" not in line1 or "503" not in line2:
    sys.exit(f"--max-viewers 1: expected 101 then 503, got {line1!r}, {line2!r}")
EOF
kill $WEB 2>/dev/null; wait $WEB 2>/dev/null

# Out of descriptors: with 64 of them and 120 connections waiting, accept
# fails with EMFILE; the gateway closes its oldest pending connection and
# backs off instead of spinning, and /healthz answers.
(ulimit -n 64 && exec "$BIN/gistream-web" --server "$ADDR" --listen 127.0.0.1:0 --size 32x24 \
  --max-connections 1000 >"$TMP/w4.log" 2>"$TMP/w4.err") &
WEB=$!
for _ in $(seq 600); do grep -q "serving" "$TMP/w4.log" && break; sleep 0.1; done
HOSTPORT=$(sed -n 's/^serving http:\/\/\([^/ ]*\)\/.*/\1/p' "$TMP/w4.log")
[ -n "$HOSTPORT" ] || fail "gistream-web (64 descriptors) did not start"
python3 - "$HOSTPORT" "$WEB" <<'EOF' || fail "descriptor exhaustion"
import os, socket, sys, time
host, port = sys.argv[1].rsplit(":", 1)
pid = sys.argv[2]
idle = [socket.create_connection((host, int(port)), timeout=10) for _ in range(120)]

def cpu_seconds():
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

time.sleep(0.5)
before = cpu_seconds()
time.sleep(2.0)
busy = cpu_seconds() - before
# A spinning accept loop takes a whole core: 2 s. Backing off: almost none.
print(f"gateway CPU over 2 s with descriptors exhausted: {busy:.2f} s")
if busy > 1.0:
    sys.exit("the accept loop spins while descriptors are exhausted")
for attempt in range(20):
    try:
        s = socket.create_connection((host, int(port)), timeout=5)
        s.sendall(f"GET /healthz HTTP/1.1\r\nHost: {host}\r\n\r\n".encode())
        got = s.recv(4096).decode(errors="replace").split("\r\n")[0]
        if " 200 " in got:
            print("healthz with descriptors exhausted:", got)
            break
    except OSError:
        pass
    time.sleep(0.2)
else:
    sys.exit("healthz did not answer while descriptors were exhausted")
EOF
grep -q "backing off" "$TMP/w4.err" || fail "the descriptor shortage was not logged"
kill $WEB 2>/dev/null; wait $WEB 2>/dev/null

# The backend (issue 31): /healthz is 503 while gistreamd is gone and names
# why, 200 again once it serves; a viewer after the restart gets frames
# (the gateway loads its scene again by name: the old id is unknown).
start_web w5
PORT=${ADDR##*:}
python3 - "$HOSTPORT" <<'EOF' || fail "healthz with the backend up"
import socket, sys
host, port = sys.argv[1].rsplit(":", 1)
s = socket.create_connection((host, int(port)), timeout=10)
s.sendall(f"GET /healthz HTTP/1.1\r\nHost: {host}\r\n\r\n".encode())
got = s.recv(4096).decode(errors="replace")
print("healthz, backend up:", got.split("\r\n")[0])
sys.exit(0 if " 200 " in got else 1)
EOF
kill $PID; wait $PID 2>/dev/null
python3 - "$HOSTPORT" <<'EOF' || fail "healthz with the backend down"
import socket, sys, time
host, port = sys.argv[1].rsplit(":", 1)
for _ in range(100):  # polled every 2 s: a hang bound of 10 s
    s = socket.create_connection((host, int(port)), timeout=10)
    s.sendall(f"GET /healthz HTTP/1.1\r\nHost: {host}\r\n\r\n".encode())
    got = s.recv(4096).decode(errors="replace")
    if " 503 " in got:
        print("healthz, backend down:", got.split("\r\n")[0], "|", got.split("\r\n\r\n", 1)[1].strip())
        sys.exit(0 if "not serving" in got else 1)
    time.sleep(0.1)
sys.exit("healthz stayed 200 with gistreamd gone")
EOF
"$BIN/gistreamd" --listen "127.0.0.1:$PORT" --scenes "$SCENES" >"$TMP/d2.log" 2>"$TMP/d2.err" &
PID=$!
echo $PID >"$TMP/backend.pid"
for _ in $(seq 300); do grep -q "listening on" "$TMP/d2.log" && break; sleep 0.1; done
PYTHONPATH="$(dirname "$0")" python3 - "$HOSTPORT" <<'EOF' || fail "a viewer after the backend restarted"
import socket, struct, sys, time, json
host, port = sys.argv[1].rsplit(":", 1)
start = time.monotonic()
for _ in range(300):  # a hang bound of 30 s
    s = socket.create_connection((host, int(port)), timeout=10)
    s.sendall(f"GET /healthz HTTP/1.1\r\nHost: {host}\r\n\r\n".encode())
    if " 200 " in s.recv(4096).decode(errors="replace"):
        break
    time.sleep(0.1)
else:
    sys.exit("healthz did not return to 200 after the restart")
print(f"healthz, backend restarted: 200 after {time.monotonic() - start:.1f} s")
from ws_client import Viewer
viewer = Viewer(host, port)
texts = []
deadline = time.monotonic() + 60  # a hang bound
while time.monotonic() < deadline:
    opcode, message = viewer.message()
    if opcode == 1:
        m = json.loads(message)
        texts.append(m.get("message", m["type"]))
        if m["type"] == "scene" and m.get("solver") != "antiradiance":
            sys.exit(f"the page opens on {m.get('solver')!r}, not a GI solver (antiradiance)")
    elif opcode == 2:
        print("a frame after the restart; the page was told:", " | ".join(texts))
        sys.exit(0 if any("loading it again" in t for t in texts) else 1)
sys.exit(f"no frame within 60 s after the restart; messages: {texts}")
EOF
grep -q "backend 127.0.0.1:$PORT not serving" "$TMP/w5.err" || fail "the backend's loss was not logged"
grep -q "viewer 127.0.0.1:[0-9]* opened" "$TMP/w5.err" || fail "a viewer was not logged"
kill $WEB 2>/dev/null; wait $WEB 2>/dev/null

# A viewer open across a backend restart keeps what its page changed
# (issue 31, drain and resume): the gateway replays the page's changes on
# the new server's session (the lamp's strength, seq 41 here).
start_web w5b --solver direct
PYTHONPATH="$(dirname "$0")" python3 - "$HOSTPORT" "$BIN" "127.0.0.1:$PORT" "$SCENES" "$TMP" <<'EOF' || fail "the page's changes after a backend restart"
import json, subprocess, sys, time
from ws_client import Viewer
host, port = sys.argv[1].rsplit(":", 1)
bin_dir, backend, scenes, tmp = sys.argv[2:6]
viewer = Viewer(host, port)
def until_frame(texts, deadline):
    while time.monotonic() < deadline:
        opcode, message = viewer.message()
        if opcode == 2:
            return True
        texts.append(json.loads(message).get("message", ""))
    return False
texts = []
if not until_frame(texts, time.monotonic() + 60):
    sys.exit("no first frame")
viewer.send({"type": "material", "material": 3, "emissive_strength": 20.0, "seq": 41})
time.sleep(1.0)
old = int(open(f"{tmp}/backend.pid").read())
subprocess.run(["kill", str(old)])  # SIGTERM: the drain
time.sleep(1.0)
new = subprocess.Popen([f"{bin_dir}/gistreamd", "--listen", backend, "--scenes", scenes],
                       stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
open(f"{tmp}/backend.pid", "w").write(str(new.pid))
if not new.stdout.readline().startswith("listening on"):
    sys.exit("gistreamd did not restart")
texts = []
deadline = time.monotonic() + 60  # a hang bound
while time.monotonic() < deadline:
    if until_frame(texts, deadline) and any("loading it again" in t for t in texts):
        break
else:
    sys.exit(f"no frame after the restart; messages: {texts}")
status = subprocess.run([f"{bin_dir}/gistream", "--server", backend, "status"],
                        capture_output=True, text=True).stdout
rows = [l for l in status.splitlines() if "session-" in l]
print("after the restart:", rows)
sys.exit(0 if rows and rows[0].split()[-1] == "41" else f"the new session's last seq is not 41:\n{status}")
EOF
kill $WEB 2>/dev/null; wait $WEB 2>/dev/null
PID=$(cat "$TMP/backend.pid")

# What a page may ask for (issue 30): --solvers and --page-params limit the
# picker and are enforced on the WebSocket; --max-messages drops a flood.
start_web w6 --solver direct --solvers direct,antiradiance --page-params area_samples \
  --max-messages 5 --metrics-listen 127.0.0.1:0
PYTHONPATH="$(dirname "$0")" python3 - "$HOSTPORT" <<'EOF' || fail "page limits"
import sys, time
from ws_client import Viewer
host, port = sys.argv[1].rsplit(":", 1)
viewer = Viewer(host, port)
next_text, send = viewer.next_text, viewer.send
scene = next_text()
names = [x["name"] for x in scene["solvers"]]
params = {x["name"]: [p["name"] for p in x["params"]] for x in scene["solvers"]}
print("offered:", names, params)
if names != ["direct", "antiradiance"]:
    sys.exit(f"the picker offers {names}, not --solvers direct,antiradiance")
if any(p != ["area_samples"] for p in params.values()):
    sys.exit(f"the page is shown parameters beyond --page-params: {params}")

def expect_error(want):
    for _ in range(20):
        m = next_text()
        if m["type"] == "error":
            print("refused:", m["message"])
            if want not in m["message"]:
                sys.exit(f"expected {want!r} in {m['message']!r}")
            return
    sys.exit(f"no error for {want!r}")

time.sleep(0.5)  # the bucket refills (5 a second, burst 10)
send({"type": "config", "solver": "pathtrace", "params": {}})
expect_error("solver 'pathtrace' is not offered by this gateway")
send({"type": "config", "solver": "direct", "params": {"shadow_res": "4096"}})
expect_error("params.shadow_res: not settable from this page")
for i in range(40):
    send({"type": "key_frame"})
expect_error("too many messages")
EOF

# Metrics (issue 31): on --metrics-listen's port alone, counting what the
# gateway did above (a flood dropped) and below (an origin refused, a
# viewer's update timed to the frame that shows it).
for _ in $(seq 100); do grep -q "^metrics on" "$TMP/w6.log" && break; sleep 0.1; done
METRICS=$(sed -n 's/^metrics on http:\/\/\([^/ ]*\)\/metrics/\1/p' "$TMP/w6.log")
[ -n "$METRICS" ] || fail "gistream-web printed no metrics address"
PYTHONPATH="$(dirname "$0")" python3 - "$HOSTPORT" "$METRICS" <<'EOF' || fail "metrics"
import re, socket, struct, json, sys, urllib.error, urllib.request
from ws_client import Viewer
host, port = sys.argv[1].rsplit(":", 1)

def scrape():
    with urllib.request.urlopen(f"http://{sys.argv[2]}/metrics", timeout=10) as r:
        return r.read().decode()

def value(text, name, labels=""):
    m = re.search(rf"^{re.escape(name + labels)} (\S+)$", text, re.M)
    return float(m.group(1)) if m else None

try:
    urllib.request.urlopen(f"http://{sys.argv[1]}/metrics", timeout=10)
    sys.exit("the viewers' port serves /metrics")
except urllib.error.HTTPError as e:
    if e.code != 404:
        sys.exit(f"the viewers' port answered /metrics with {e.code}, not 404")
s = socket.create_connection((host, int(port)), timeout=10)
s.sendall((f"GET /ws HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
           "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
           "Sec-WebSocket-Version: 13\r\nOrigin: http://evil.example\r\n\r\n").encode())
s.recv(4096)
s.close()
viewer = Viewer(host, port)
viewer.next_text()  # the scene
viewer.send({"type": "material", "material": 3, "emissive_strength": 12.0, "seq": 7})
for _ in range(40):  # frames, or a keep-alive a second at rest
    opcode, payload = viewer.message()
    if opcode == 1:
        print("text:", payload[:200])
    if opcode == 2:
        n = struct.unpack("<I", payload[:4])[0]
        if json.loads(payload[4:4 + n])["seq"] >= 7:
            break
else:
    sys.exit("no frame showing seq 7")
text = scrape()
checks = {
    ("gistream_web_viewers_opened_total", '{format="jpeg"}'): lambda v: v >= 2,
    ("gistream_web_upgrades_refused_total", '{reason="origin"}'): lambda v: v >= 1,
    ("gistream_web_messages_dropped_total", ""): lambda v: v >= 1,
    ("gistream_web_frames_sent_total", ""): lambda v: v >= 1,
    ("gistream_web_frame_bytes_sent_total", ""): lambda v: v > 0,
    ("gistream_web_update_to_frame_seconds_count", ""): lambda v: v >= 1,
    ("gistream_web_viewers", ""): lambda v: v == 1,
    ("gistream_web_backend_serving", ""): lambda v: v == 1,
    ("gistream_web_http_requests_total", '{code="404",path="/metrics"}'): lambda v: v >= 1,
}
for (name, labels), ok in checks.items():
    v = value(text, name, labels)
    print(f"{name}{labels} = {v}")
    if v is None or not ok(v):
        sys.exit(f"{name}{labels} is {v}:\n{text}")
EOF
kill $WEB 2>/dev/null; wait $WEB 2>/dev/null

# Viewer tokens (issue 31): with --viewer-tokens a WebSocket needs a token
# of the file, as `Authorization: Bearer` or as the page's subprotocol
# (base64url); the page itself and /healthz stay open.
printf '# viewers\nviewer-token-0123456789 alice\n' > "$TMP/viewers"
start_web w7 --viewer-tokens "$TMP/viewers"
python3 - "$HOSTPORT" <<'EOF' || fail "viewer tokens"
import base64, socket, sys, urllib.request
host, port = sys.argv[1].rsplit(":", 1)

def upgrade(extra):
    s = socket.create_connection((host, int(port)), timeout=10)
    s.sendall((f"GET /ws HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
               "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
               f"Sec-WebSocket-Version: 13\r\nOrigin: http://{host}:{port}\r\n{extra}\r\n").encode())
    head = b""
    while b"\r\n\r\n" not in head:
        chunk = s.recv(4096)
        if not chunk:
            break
        head += chunk
    s.close()
    return head.decode(errors="replace")

b64 = lambda t: base64.urlsafe_b64encode(t.encode()).decode().rstrip("=")
cases = [("no token", "", "401"),
         ("a wrong bearer token", "Authorization: Bearer viewer-token-wrong-000000\r\n", "401"),
         ("a wrong subprotocol token",
          f"Sec-WebSocket-Protocol: gistream, gistream.token.{b64('viewer-token-wrong-000')}\r\n", "401"),
         ("a bearer token", "Authorization: Bearer viewer-token-0123456789\r\n", "101"),
         ("the page's subprotocol token",
          f"Sec-WebSocket-Protocol: gistream, gistream.token.{b64('viewer-token-0123456789')}\r\n", "101")]
for name, extra, want in cases:
    head = upgrade(extra)
    line = head.split("\r\n")[0]
    print(f"{name}: {line}")
    if f" {want} " not in line + " ":
        sys.exit(f"{name}: expected {want}, got {line!r}")
    if "subprotocol" in name and want == "101" and "Sec-WebSocket-Protocol: gistream\r\n" not in head:
        sys.exit(f"the gateway did not select the 'gistream' subprotocol:\n{head}")
with urllib.request.urlopen(f"http://{sys.argv[1]}/", timeout=10) as r:
    print("the page without a token:", r.status)
with urllib.request.urlopen(f"http://{sys.argv[1]}/healthz", timeout=10) as r:
    print("healthz without a token:", r.status)
EOF
grep -q "refused a WebSocket without a viewer token from 127.0.0.1" "$TMP/w7.err" ||
  fail "the refusal was not logged"
grep -q "viewer-token-0123456789" "$TMP/w7.err" && fail "a token was logged"
grep -q "opened (jpeg, alice" "$TMP/w7.err" || fail "the viewer's name was not logged"
printf 'short alice\n' > "$TMP/bad_viewers"
"$BIN/gistream-web" --viewer-tokens "$TMP/bad_viewers" >"$TMP/bad.out" 2>&1
[ $? -eq 2 ] || fail "a bad --viewer-tokens file was not a usage error"
grep -q "viewer-tokens" "$TMP/bad.out" || fail "a bad --viewer-tokens file: $(cat "$TMP/bad.out")"
kill $WEB 2>/dev/null; wait $WEB 2>/dev/null
echo "PASS"
