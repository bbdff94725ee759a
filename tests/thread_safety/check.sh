#!/usr/bin/env bash
# Proves clang's -Wthread-safety checks what the engine states with
# ABSL_GUARDED_BY / ABSL_EXCLUSIVE_LOCKS_REQUIRED (and ThreadRole): a
# correct file compiles, the same file with two violations does not, each
# violation named. Usage: check.sh SOURCE_DIR
set -euo pipefail
ROOT=$1
CXX=${CLANGXX:-clang++}
command -v "$CXX" >/dev/null || { echo "FAIL: $CXX not found (scripts/install-deps.sh installs clang)"; exit 1; }
SRC=$ROOT/tests/thread_safety/role_and_mutex.cpp
FLAGS=(-std=c++20 -fsyntax-only -Wthread-safety -Werror=thread-safety -I"$ROOT/common")
"$CXX" "${FLAGS[@]}" "$SRC" || { echo "FAIL: the correct file does not compile"; exit 1; }
if out=$("$CXX" "${FLAGS[@]}" -DVIOLATE "$SRC" 2>&1); then
  echo "FAIL: the violations compiled: -Wthread-safety checks nothing"
  exit 1
fi
for want in "calling function 'DrawOnRenderThread' requires holding mutex 'render_role_'" \
            "reading variable 'sessions_' requires holding mutex 'mutex_'"; do
  grep -qF "$want" <<<"$out" || { echo "FAIL: no error \"$want\" in:"; echo "$out"; exit 1; }
done
echo "thread_safety_analysis: correct code compiles, both violations are errors"
