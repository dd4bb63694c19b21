#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, clang-14) into build-fuzz/ and runs each over a copy
# of its seed corpus (docs/fuzzing.md).
#   tools/run-fuzz.sh            CI: a fixed number of runs per target, fixed seed
#   tools/run-fuzz.sh N          N runs per target, fixed seed
#   tools/run-fuzz.sh --time S   S seconds per target, random seed, corpus kept between runs
# Exits non-zero when a target crashes; the input is left in build-fuzz/crashes/.
set -euo pipefail
cd "$(dirname "$0")/.."

runs=50000  # under a minute for both targets on two cores, build excluded
seconds=""
case "${1:-}" in
  "") ;;
  --time) seconds=${2:?"usage: tools/run-fuzz.sh [RUNS | --time SECONDS]"} ;;
  *[!0-9]*) echo "usage: tools/run-fuzz.sh [RUNS | --time SECONDS]" >&2; exit 2 ;;
  *) runs=$1 ;;
esac

CC=${FUZZ_CC:-clang-14} CXX=${FUZZ_CXX:-clang++-14} cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DEPSRAY_FUZZ=ON -DEPSRAY_TESTS=OFF -DEPSRAY_BENCH=OFF >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_scene fuzz_path >/dev/null

mkdir -p build-fuzz/crashes
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
status=0
for kind in scene path; do
  corpus=build-fuzz/corpus/$kind
  if [ -z "$seconds" ]; then
    rm -rf "$corpus"  # the same inputs every run, so CI results repeat
    limit=(-runs="$runs" -seed=1) what="$runs runs"
  else
    limit=(-max_total_time="$seconds") what="$seconds s"
  fi
  mkdir -p "$corpus"
  cp -n fuzz/corpus/$kind/* "$corpus"/
  dict=()
  [ "$kind" = scene ] && dict=(-dict=fuzz/nff.dict)
  # -timeout: one input running 10 s is a hang; -max_len: the largest seed (artroom.nff).
  echo "fuzz_$kind: $what"
  if ! build-fuzz/fuzz/fuzz_$kind "${limit[@]}" "${dict[@]}" -timeout=10 -max_len=10000 -rss_limit_mb=4096 \
      -print_final_stats=1 -artifact_prefix=build-fuzz/crashes/$kind- "$corpus" 2>build-fuzz/fuzz_$kind.log; then
    tail -n 60 build-fuzz/fuzz_$kind.log >&2
    echo "fuzz_$kind: FAILED; input in build-fuzz/crashes/, log in build-fuzz/fuzz_$kind.log" >&2
    status=1
  else
    grep -E '^stat::number_of_executed_units|^Done' build-fuzz/fuzz_$kind.log || true
  fi
done
exit $status
