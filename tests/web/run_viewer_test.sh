#!/usr/bin/env bash
# The browser viewer end to end: gistreamd + gistream-web on free ports,
# then tests/web/viewer_test.mjs in Debian's headless Chromium for JPEG and
# H.264 (WebCodecs). Screenshots go to BUILD/test-artifacts/. Skips (exit
# 77) when gistream-web was not built, or chromium, node or puppeteer-core
# (installed here from npm on first use) are missing.
# usage: run_viewer_test.sh BUILD_DIR SCENES_DIR
set -u
BIN=$1
SCENES=$2
HERE=$(cd "$(dirname "$0")" && pwd)
[ -x "$BIN/gistream-web" ] || { echo "SKIP: gistream-web not built (libboost-dev missing)"; exit 77; }
command -v node >/dev/null || { echo "SKIP: node not installed"; exit 77; }
[ -x "${CHROMIUM:-/usr/bin/chromium}" ] || { echo "SKIP: chromium not installed"; exit 77; }
if [ ! -d "$HERE/node_modules/puppeteer-core" ]; then
  (cd "$HERE" && npm install --no-audit --no-fund >/dev/null 2>&1) ||
    { echo "SKIP: npm install puppeteer-core failed (no registry?)"; exit 77; }
fi
TMP=$(mktemp -d)
cleanup() { kill $WEB $PID 2>/dev/null; wait 2>/dev/null; rm -rf "$TMP"; }
trap cleanup EXIT
"$BIN/gistreamd" --listen 127.0.0.1:0 --scenes "$SCENES" >"$TMP/d.log" 2>"$TMP/d.err" &
PID=$!
for _ in $(seq 100); do grep -q "listening on" "$TMP/d.log" && break; sleep 0.1; done
ADDR=$(sed -n 's/^listening on //p' "$TMP/d.log")
[ -n "$ADDR" ] || { cat "$TMP/d.err"; echo "FAIL: gistreamd did not start"; exit 1; }
# The page authenticates as a viewer (--viewer-tokens; opened as /#token=).
export VIEWER_TOKEN=viewer-test-token-0123
printf '%s tester\n' "$VIEWER_TOKEN" > "$TMP/viewers"
"$BIN/gistream-web" --server "$ADDR" --listen 127.0.0.1:0 --size 320x240 --solver direct \
  --param area_samples=16 --viewer-tokens "$TMP/viewers" \
  >"$TMP/w.log" 2>"$TMP/w.err" &
WEB=$!
for _ in $(seq 600); do grep -q "serving" "$TMP/w.log" && break; sleep 0.1; done
URL=$(sed -n 's/^serving \(http:[^ ]*\).*/\1/p' "$TMP/w.log")
[ -n "$URL" ] || { cat "$TMP/w.err"; echo "FAIL: gistream-web did not start"; exit 1; }
OUT="$BIN/test-artifacts"
rc=0
for format in jpeg h264; do
  node "$HERE/viewer_test.mjs" "$URL" "$OUT" $format >"$TMP/$format.log" 2>&1 || rc=1
  grep -v "willReadFrequently\|status of 404" "$TMP/$format.log"
done
exit $rc
