#!/usr/bin/env bash
# Checks (default) or applies (--fix) .clang-format to our C++ sources:
# common/, server/, client/, tests/, tools/, web/. The `format` ctest runs the check;
# `make format` the fix.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files -co --exclude-standard -- \
    'common/*.cpp' 'common/*.h' 'server/*.cpp' 'server/*.h' 'client/*.cpp' 'client/*.h' 'tests/*.cpp' 'tests/*.h' \
    'tools/*.cpp' 'tools/*.h' 'web/*.cpp' 'web/*.h')
else
  mapfile -t files < <(find common server client tests tools web -name '*.cpp' -o -name '*.h' | sort)
fi
command -v clang-format >/dev/null || { echo "clang-format is not installed (make deps)" >&2; exit 1; }
if [ "${1:-}" = --fix ]; then
  printf '%s\0' "${files[@]}" | xargs -0 clang-format -i
  echo "formatted ${#files[@]} files"
else
  if ! printf '%s\0' "${files[@]}" | xargs -0 clang-format --dry-run -Werror 2>/tmp/gistream-format.$$; then
    head -40 /tmp/gistream-format.$$ >&2
    echo "$(grep -c 'error:' /tmp/gistream-format.$$) lines differ from .clang-format; run 'make format'" >&2
    rm -f /tmp/gistream-format.$$; exit 1
  fi
  rm -f /tmp/gistream-format.$$
  echo "${#files[@]} files follow .clang-format"
fi
