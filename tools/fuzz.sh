#!/usr/bin/env bash
# Builds the libFuzzer harnesses of tests/fuzz with clang 14 (ASan + UBSan)
# and runs each for a bounded time on its seed corpus; fails on any finding.
# Built at -O1, as libFuzzer's and AddressSanitizer's guides advise: it
# compiles much faster, and the harnesses still run thousands of inputs a
# second (docs/robustness.md, "What runs where").
# A finding's input is saved as tests/fuzz/crashes/fuzz_NAME-KIND-HASH: fix
# the loader and move the file into tests/fuzz/corpus/NAME as a regression
# input (docs/robustness.md).
#   LHR_FUZZ_SECONDS    seconds per fuzzer (default 60; CI's .ci/run sets 25)
#   LHR_FUZZ_BUILD_DIR  build directory (default build-fuzz)
#   LHR_FUZZ_TARGETS    which fuzzers (default "obj ply off scene_json")
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
seconds=${LHR_FUZZ_SECONDS:-60}
build=${LHR_FUZZ_BUILD_DIR:-build-fuzz}
# Ninja for a new build tree, as in tools/build.sh.
export CMAKE_GENERATOR=${CMAKE_GENERATOR:-Ninja}
targets=${LHR_FUZZ_TARGETS:-obj ply off scene_json}

CC=clang-14 CXX=clang++-14 cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" -DLHR_FUZZ=ON \
  -DLHR_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target lhr_fuzzers

crashes=tests/fuzz/crashes
mkdir -p "$crashes"
# intercept_tls_get_addr=0: see tools/test-sanitized.sh.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:intercept_tls_get_addr=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# One fuzzer per core at a time: each still runs its full time, and the
# stage takes about a core's share of their sum (docs/robustness.md).
fuzz_one() {
  local name=$1
  # New inputs go to a scratch corpus in the build directory; the seed
  # corpus in the repository is only read.
  local work="$build/fuzz-corpus/$name"
  local log="$build/fuzz-$name.log"
  mkdir -p "$work"
  local status=0
  # -timeout catches hangs, -rss_limit_mb and -malloc_limit_mb huge allocations.
  "$build/tests/fuzz/fuzz_$name" "$work" "tests/fuzz/corpus/$name" \
    -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -dict="tests/fuzz/$name.dict" -artifact_prefix="$crashes/fuzz_$name-" -print_final_stats=1 \
    >"$log" 2>&1 || status=$?
  echo "$status" >"$build/fuzz-$name.status"
}
jobs_max=$(nproc)
for name in $targets; do
  rm -f "$build/fuzz-$name.status"
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  fuzz_one "$name" &
done
wait
failed=()
for name in $targets; do
  log="$build/fuzz-$name.log"
  status=$(cat "$build/fuzz-$name.status" 2>/dev/null || echo "no status")
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  echo "fuzz_$name: ${runs:-?} executions in ${seconds} s, exit $status"
  if [ "$status" != 0 ]; then
    failed+=("$name")
    grep -E "ERROR|FUZZ FINDING|SUMMARY|Test unit written" "$log" | head -n 8 >&2 || true
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzzing found problems in: ${failed[*]} (inputs in $crashes, logs in $build)" >&2
  exit 1
fi
