#!/usr/bin/env bash
# Builds lhr and its tests with AddressSanitizer + UndefinedBehaviorSanitizer
# (CMake option LHR_SANITIZE) and runs the whole suite; any report fails it.
#   LHR_ASAN_BUILD_DIR  build directory (default build-asan)
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
build=${LHR_ASAN_BUILD_DIR:-build-asan}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DLHR_SANITIZE=ON >/dev/null
cmake --build "$build" -j "$(nproc)"
# The tests run the `lhr` executable too; it inherits these settings.
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:abort_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"
