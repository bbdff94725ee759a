#!/usr/bin/env bash
# CI's second half (called by .ci/run after `make test`): one extra build
# tree, build-sanitize/, compiled by clang with AddressSanitizer,
# UndefinedBehaviorSanitizer and libFuzzer's coverage instrumentation
# (GISTREAM_SANITIZE=ON GISTREAM_FUZZ=ON). Only what is run is built: the
# unit, client and service test binaries and the four fuzz targets.
#   1. unit_tests, client_tests and service_tests under ASan + UBSan (any
#      report fails the run; LeakSanitizer ignores Mesa's and the driver's
#      own allocations: tests/fuzz/lsan.supp).
#   2. each fuzz target for FUZZ_SECONDS (default 45) from its seed corpus
#      (tests/fuzz/corpus/<target>/, read-only; new inputs go to
#      build-sanitize/fuzz/corpus/<target>/, crashes to
#      build-sanitize/fuzz/artifacts/).
# Environment: BUILD_DIR (build-sanitize), FUZZ_SECONDS, JOBS (nproc).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build-sanitize}
FUZZ_SECONDS=${FUZZ_SECONDS:-45}
JOBS=${JOBS:-$(nproc)}
GENERATOR=$(command -v ninja >/dev/null 2>&1 && echo "-G Ninja" || true)

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}

start=$(date +%s)
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  # shellcheck disable=SC2086
  cmake -S . -B "$BUILD_DIR" $GENERATOR -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_FLAGS_RELEASE=-O1 -DCMAKE_CXX_FLAGS_RELEASE=-O1 \
    -DGISTREAM_SANITIZE=ON -DGISTREAM_FUZZ=ON
fi
# Test discovery runs the binaries at build time: no leak check there.
ASAN_OPTIONS=detect_leaks=0 cmake --build "$BUILD_DIR" -j "$JOBS" \
  --target unit_tests client_tests service_tests fuzzers
built=$(date +%s)
echo "ci-sanitizers: build took $((built - start)) s"

# The numeric convergence tests (furnaces run to hundreds of thousands of
# paths, BRDF integrals) take minutes at -O1 with ASan and exercise the
# same code as the smaller tests of their suites: run in `make test` only.
SLOW_NUMERIC='Ggx.WhiteFurnace*:Albedos/PathtraceFurnace.*:PathtraceGlossyFurnace.*:AvgStiffFurnace.*:AntiradianceEnergy.StiffFurnace*'
for t in unit_tests client_tests service_tests; do
  echo "ci-sanitizers: $t under ASan + UBSan"
  filter='*'
  [ "$t" = unit_tests ] && filter="*:-$SLOW_NUMERIC"
  "$BUILD_DIR/tests/$t" --gtest_brief=1 --gtest_filter="$filter"
done
tested=$(date +%s)
echo "ci-sanitizers: tests took $((tested - built)) s"

mkdir -p "$BUILD_DIR/fuzz/artifacts"
for f in gltf_import image_decode update script; do
  corpus="$BUILD_DIR/fuzz/corpus/$f"
  mkdir -p "$corpus"
  echo "ci-sanitizers: ${f}_fuzzer for ${FUZZ_SECONDS} s"
  # Leaks in a fuzz target are found by the tests' run above; here they
  # would stop the campaign on third-party caches.
  ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0" "$BUILD_DIR/tests/fuzz/${f}_fuzzer" \
    -max_total_time="$FUZZ_SECONDS" -timeout=20 -rss_limit_mb=3072 -max_len=262144 \
    -print_final_stats=1 -artifact_prefix="$BUILD_DIR/fuzz/artifacts/${f}-" \
    "$corpus" "tests/fuzz/corpus/$f" 2>&1 | grep -v '^#[0-9]' || { echo "ci-sanitizers: ${f}_fuzzer failed" >&2; exit 1; }
done
echo "ci-sanitizers: fuzzing took $(( $(date +%s) - tested )) s; total $(( $(date +%s) - start )) s"
