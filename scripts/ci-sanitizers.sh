#!/usr/bin/env bash
# CI's second half (called by .ci/run after `make test`). Two extra build
# trees, both clang at -O1, each building only what it runs:
#   build-sanitize/  AddressSanitizer + UndefinedBehaviorSanitizer, libFuzzer
#                    coverage on the libraries the fuzz targets reach
#                    (GISTREAM_SANITIZE=ON GISTREAM_FUZZ=ON)
#   build-tsan/      ThreadSanitizer (GISTREAM_TSAN=ON), `thread_tests` and
#                    `thread_engine_tests` only, the solvers `direct` and
#                    `implicit_visibility` only (GISTREAM_SOLVERS)
# Steps, each timed:
#   1. unit, client, service and reliability tests under ASan + UBSan, and
#      the GL suites that drive the engine and every solver through a frame
#      ($GL_SUITES, compiled from their own files into gl_engine_tests;
#      the long numeric and reference suites run in `make test` only), the
#      five binaries JOBS at a time. Any report fails the run; LeakSanitizer ignores Mesa's and
#      the driver's own allocations (tests/fuzz/lsan.supp).
#   2. ThreadSanitizer: thread_tests (the session reactor's frame slot, the
#      service's worker pool, the CPU pool), then thread_engine_tests (the
#      real engine on EGL with client threads, background jobs, loads and
#      unloads at once; $TSAN_ENGINE_SUITES) beside step 3, in one of its
#      JOBS lanes (run_lanes counts it among the shell's jobs): on 2 cores
#      the four 30-s fuzzers then run one at a time beside it, and both end
#      after about 130 s (tests/CMakeLists.txt says why the gRPC-driven
#      tests are not there).
#   3. each fuzz target (JOBS at a time) for FUZZ_SECONDS (default 30) from its seed corpus
#      (tests/fuzz/corpus/<target>/, read-only; new inputs go to
#      build-sanitize/fuzz/corpus/<target>/, crashes to
#      build-sanitize/fuzz/artifacts/).
# Environment: BUILD_DIR (build-sanitize), TSAN_BUILD_DIR (build-tsan),
# FUZZ_SECONDS, JOBS (nproc).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build-sanitize}
TSAN_BUILD_DIR=${TSAN_BUILD_DIR:-build-tsan}
FUZZ_SECONDS=${FUZZ_SECONDS:-30}
JOBS=${JOBS:-$(nproc)}
GENERATOR=$(command -v ninja >/dev/null 2>&1 && echo "-G Ninja" || true)

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}

step_start=$(date +%s)
total_start=$step_start
step() {  # prints how long the step that just ended took
  local now
  now=$(date +%s)
  echo "ci-sanitizers: $1 took $((now - step_start)) s"
  step_start=$now
}

configure() {  # DIR, extra cmake options...
  local dir=$1
  shift
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    # shellcheck disable=SC2086
    cmake -S . -B "$dir" $GENERATOR -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_FLAGS_RELEASE=-O1 -DCMAKE_CXX_FLAGS_RELEASE=-O1 "$@"
  fi
}

# ---------------------------------------------------------------- ASan + UBSan
configure "$BUILD_DIR" -DGISTREAM_SANITIZE=ON -DGISTREAM_FUZZ=ON
# Test discovery runs the binaries at build time: no leak check there.
ASAN_OPTIONS=detect_leaks=0 cmake --build "$BUILD_DIR" -j "$JOBS" \
  --target unit_tests client_tests service_tests reliability_tests gl_engine_tests fuzzers
step "ASan build"

# The numeric convergence tests (furnaces run to hundreds of thousands of
# paths, BRDF integrals, proxy error bounds over large meshes) take minutes
# at -O1 with ASan and coverage and exercise the same code as the smaller
# tests of their suites: run in `make test` only. (unit_tests took 402 s
# under ASan with only the first five excluded; each of the others takes
# 1.5-8 s in `make test`, 5-10x that here.)
SLOW_NUMERIC='Ggx.WhiteFurnace*:Albedos/PathtraceFurnace.*:PathtraceGlossyFurnace.*:AvgStiffFurnace.*:AntiradianceEnergy.StiffFurnace*'
SLOW_NUMERIC+=':Ggx.SamplingPdfIntegratesToOne:Ggx.SampleWeightsAverageToTheAlbedo:Ggx.VisibleNormalsProjectToTheView'
SLOW_NUMERIC+=':Ggx.MetallicZeroRoughnessOneIsLambert:AntiradianceGlossy.IteratedFurnace*'
SLOW_NUMERIC+=':ProxyLevels.BumpyPlane*:ProxyClusters.BumpyPlane*:ProxyLoadControl.DeadlineDuringTheTrees*'
SLOW_NUMERIC+=':AvgGridFlux.*:AvgIncremental.RevoxelizedGrid*:AntiradianceStability.DeepSlab*'
# 30 hierarchical solves of one scene (51 s here, 2026-12-05).
SLOW_NUMERIC+=':HierarchyLinks.ASilhouetteSharesItsBinsWithWhatIsBehind'
# reliability_tests: antiradiance's memory estimate against what it builds
# at every size of a sweep (47 s here); the other solvers' estimates stay.
SLOW_RELIABILITY='MemoryBudget.AntiradianceEstimateCoversWhatItBuilds'
# The GL suites under ASan: the engine's frame pipeline (slices, stages,
# first solves in the background, rest, video frames, the solver cache) and
# each solver's own suite at its small sizes, cancellation (jobs asked to
# stop while the engine drops their solvers). The path-traced references
# and furnace sweeps stay in `make test`.
# (222 s with EngineSlicing, VideoFramesTest and EngineRest's
# implicit_visibility case too, 2026-12-03: those stay in `make test`.)
GL_SUITES=${GL_SUITES:-'EngineStagesTest.*:EngineSolverCache.*:EngineRestShared.*:Solvers/EngineRest.*/direct:FirstSolves.*:AllSolvers/StagePlan.*:DirectIncremental.*:DrawListTest.*:GlProgram.*:GlDebug.*:GlDriverQuirks.*:AvgBackgroundTrace.*:BackgroundRelink.*:GpuDeformTest.*:ShProbesFirstSolve.*:Refinement.*:Cancellation.*:EverySolver/CancelledRender.*/antiradiance:EverySolver/CancelledRender.*/implicit_visibility'}
# The five binaries run JOBS at a time, in the order below; the two longest
# (GL, unit) as two gtest shards each (GTEST_TOTAL_SHARDS), so that the
# lanes end together (each is mostly one thread; llvmpipe's rasterizer
# threads are idle while the GL suites wait on the engine's clock). Their
# times in CI (2026-12-05, before the shards and with coverage everywhere):
# GL 340 s, unit 258 s, reliability 195 s, service 132 s, client 9 s, in two
# lanes 484 s; after (f46bc04): GL 157 + 119 s, unit 36 + 88 s, reliability
# 122 s, service 97 s, client 9 s, in two lanes 357 s. The order hands the
# shorter GL shard the service lane and the longer unit shard next, which
# packs the two lanes closer: with 1716773's times (GL 202 + 171 s,
# reliability 146, service 117, unit 50 + 102, client 9) the lanes end at
# about 399 s instead of the longest-first order's 421 (436 measured).
# Each run writes its output to a log, printed whole when it ends, with
# its own time; any failure fails the step.
mkdir -p "$BUILD_DIR/test-results"
run_sanitized() {  # binary name[@shard/shards]
  local t=${1%@*} shard='' filter='*' start
  [ "$t" != "$1" ] && shard=${1#*@}
  local log=$BUILD_DIR/test-results/$t${shard:+.${shard%/*}}
  start=$(date +%s)
  [ "$t" = unit_tests ] && filter="*:-$SLOW_NUMERIC"
  [ "$t" = reliability_tests ] && filter="*:-$SLOW_RELIABILITY"
  [ "$t" = gl_engine_tests ] && filter="$GL_SUITES"
  local -a env_shard=()
  [ -n "$shard" ] && env_shard=(GTEST_SHARD_INDEX="${shard%/*}" GTEST_TOTAL_SHARDS="${shard#*/}")
  local rc=0
  env "${env_shard[@]}" "$BUILD_DIR/tests/$t" --gtest_brief=1 --gtest_filter="$filter" \
    --gtest_output="xml:$log.xml" >"$log.log" 2>&1 || rc=$?
  # LeakSanitizer's own tracer can crash at exit (signal 11 in StopTheWorld,
  # seen once on reliability_tests after all 52 tests passed): not a finding,
  # so such a run is repeated once, leak checks on.
  if [ $rc -ne 0 ] && grep -q "LeakSanitizer has encountered a fatal error" "$log.log" &&
    ! grep -q "^\[  FAILED  \]" "$log.log"; then
    echo "ci-sanitizers: $1: LeakSanitizer failed at exit after every test passed; once more"
    rc=0
    env "${env_shard[@]}" "$BUILD_DIR/tests/$t" --gtest_brief=1 --gtest_filter="$filter" \
      --gtest_output="xml:$log.xml" >"$log.log" 2>&1 || rc=$?
  fi
  echo "ci-sanitizers: $1 under ASan + UBSan (exit $rc, $(($(date +%s) - start)) s):"
  cat "$log.log"
  return $rc
}
run_lanes() {  # command, then its arguments, JOBS at a time; fails if any failed
  local cmd=$1 failed=0
  shift
  local -a pids=()
  for arg in "$@"; do
    # Throttle only: each job's status is read by its pid below (bash keeps
    # it after wait -n reaped the job).
    while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || true; done
    "$cmd" "$arg" &
    pids+=($!)
  done
  for p in "${pids[@]}"; do wait "$p" || failed=1; done
  return $failed
}
# Every pattern of GL_SUITES must select a test of gl_engine_tests (a suite
# whose file is not in tests/CMakeLists.txt's GL_ENGINE_TEST_FILES would
# otherwise drop out of this run in silence).
for pattern in ${GL_SUITES//:/ }; do
  if ! ASAN_OPTIONS=detect_leaks=0 "$BUILD_DIR/tests/gl_engine_tests" --gtest_filter="$pattern" --gtest_list_tests | grep -q '^  '; then
    echo "ci-sanitizers: GL_SUITES pattern '$pattern' selects no test of gl_engine_tests" >&2
    echo "  (add its file to GL_ENGINE_TEST_FILES in tests/CMakeLists.txt)" >&2
    exit 1
  fi
done
echo "ci-sanitizers: unit, GL, service, reliability and client tests under ASan + UBSan, $JOBS at a time"
run_lanes run_sanitized gl_engine_tests@0/2 gl_engine_tests@1/2 service_tests reliability_tests \
  unit_tests@1/2 unit_tests@0/2 client_tests
step "tests under ASan + UBSan"
# Where the sanitizer runs' time went (the 10 slowest cases).
python3 scripts/test_times.py "$BUILD_DIR" 10 || true

# ---------------------------------------------------------------- TSan
configure "$TSAN_BUILD_DIR" -DGISTREAM_TSAN=ON "-DGISTREAM_SOLVERS=direct;implicit_visibility"
cmake --build "$TSAN_BUILD_DIR" -j "$JOBS" --target thread_tests thread_engine_tests
step "TSan build"
export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/tsan.supp}
echo "ci-sanitizers: thread_tests under ThreadSanitizer"
"$TSAN_BUILD_DIR/tests/thread_tests" --gtest_brief=1
step "thread_tests under TSan"
# The engine under TSan (about 70 s alone, 2026-12-06): the suites whose
# threads meet (clients, the render thread, the CPU pool's background
# relinks, loads racing unloads); EngineRest's per-solver cases wait out
# seconds of keep-alives and add nothing ConcurrentClients does not.
TSAN_ENGINE_SUITES=${TSAN_ENGINE_SUITES:-'ConcurrentClients.*:EngineStagesTest.*:EngineSolverCache.*:EngineRestShared.*:BackgroundRelink.LinksAre*:BackgroundRelink.ARender*:LoadUnloadRace.*'}
tsan_engine_log=$TSAN_BUILD_DIR/thread_engine_tests.log
tsan_engine_start=$(date +%s)
"$TSAN_BUILD_DIR/tests/thread_engine_tests" --gtest_brief=1 --gtest_filter="$TSAN_ENGINE_SUITES" \
  >"$tsan_engine_log" 2>&1 &
tsan_engine_pid=$!

# ---------------------------------------------------------------- fuzzing
mkdir -p "$BUILD_DIR/fuzz/artifacts"
run_fuzzer() {  # target name
  local f=$1 rc=0
  local corpus="$BUILD_DIR/fuzz/corpus/$f"
  mkdir -p "$corpus"
  # Leaks in a fuzz target are found by the tests' run above; here they
  # would stop the campaign on third-party caches.
  ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0" "$BUILD_DIR/tests/fuzz/${f}_fuzzer" \
    -max_total_time="$FUZZ_SECONDS" -timeout=20 -rss_limit_mb=3072 -max_len=262144 \
    -print_final_stats=1 -artifact_prefix="$BUILD_DIR/fuzz/artifacts/${f}-" \
    "$corpus" "tests/fuzz/corpus/$f" >"$BUILD_DIR/fuzz/$f.log" 2>&1 || rc=$?
  echo "ci-sanitizers: ${f}_fuzzer for ${FUZZ_SECONDS} s (exit $rc):"
  grep -v '^#[0-9]' "$BUILD_DIR/fuzz/$f.log" || true
  [ $rc -eq 0 ] || echo "ci-sanitizers: ${f}_fuzzer failed" >&2
  return $rc
}
# Each fuzzer is one thread: JOBS run at once, the TSan engine run one of them.
fuzz_rc=0
run_lanes run_fuzzer gltf_import image_decode update script || fuzz_rc=$?
step "fuzzing"
tsan_engine_rc=0
wait "$tsan_engine_pid" || tsan_engine_rc=$?
echo "ci-sanitizers: thread_engine_tests under ThreadSanitizer (exit $tsan_engine_rc," \
  "$(($(date +%s) - tsan_engine_start)) s from its start):"
cat "$tsan_engine_log"
step "thread_engine_tests under TSan (after fuzzing)"
echo "ci-sanitizers: total $(($(date +%s) - total_start)) s"
if [ $fuzz_rc -ne 0 ] || [ $tsan_engine_rc -ne 0 ]; then
  echo "ci-sanitizers: fuzzing exit $fuzz_rc, thread_engine_tests exit $tsan_engine_rc" >&2
  exit 1
fi
