#!/usr/bin/env bash
# Extra CI configurations, each in its own build folder:
#  - AddressSanitizer + UndefinedBehaviorSanitizer over the whole test suite;
#  - ThreadSanitizer over the tests that race plain std::threads on epsray's lock-free
#    structures (linetrees, the unique-ray hash, the node pool, the light cache). TBB-driven code is left out: Debian's
#    oneTBB is not instrumented, so TSan cannot see its synchronisation (tools/tsan.supp);
#  - the libFuzzer targets for a fixed number of runs (tools/run-fuzz.sh, docs/fuzzing.md).
# Run after tools/setup.sh (which installs the packages).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEPSRAY_SANITIZE=address,undefined \
  -DEPSRAY_BENCH=OFF >/dev/null
cmake --build build-asan -j"$jobs" >/dev/null
# A failing test runs once more (--repeat until-pass:2): LeakSanitizer's
# stop-the-world tracer itself crashed ("Tracer caught signal 11") at the exit of a test that
# had passed. A test that fails twice fails CI; tools/run-tests.sh never retries.
UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=detect_leaks=1 \
  LSAN_OPTIONS="suppressions=$PWD/tools/lsan.supp" \
  ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 900 --repeat until-pass:2

cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEPSRAY_SANITIZE=thread \
  -DEPSRAY_BENCH=OFF >/dev/null
cmake --build build-tsan -j"$jobs" --target test_ray_hash test_node_pool test_interp test_light_cache >/dev/null
export TSAN_OPTIONS="halt_on_error=1 suppressions=$PWD/tools/tsan.supp"
build-tsan/tests/test_ray_hash
build-tsan/tests/test_node_pool
build-tsan/tests/test_interp --gtest_filter='InterpConcurrency.*:Linetree.*'
build-tsan/tests/test_light_cache --gtest_filter='LightCache.ConcurrentQueriesAgreeWithTheBvh'

bash tools/run-fuzz.sh
