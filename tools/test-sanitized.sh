#!/usr/bin/env bash
# Builds lhr and its tests with AddressSanitizer + UndefinedBehaviorSanitizer
# (CMake option LHR_SANITIZE) and runs the suite; any report fails it.
# Tests labelled `slow` in tests/CMakeLists.txt are left out: sanitized they
# take many minutes, and each has a fast sibling that runs the same code here
# (docs/robustness.md, "What runs where"); the release build runs them all.
# The benchmarks are not built: no test runs them. The libraries are built
# at -O2, CGAL's translation unit at -O1 and the test files at -O0: compiling
# is most of this stage, and the tests' time is spent in the libraries.
# Built with clang 14, which compiles this instrumented code in about half
# the CPU time GCC 12 takes; the release build stays with GCC, so both
# compilers' warnings are seen (docs/robustness.md, "What runs where").
#   LHR_ASAN_BUILD_DIR  build directory (default build-asan)
#   LHR_ASAN_ALL=1      run the slow tests too
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
build=${LHR_ASAN_BUILD_DIR:-build-asan}
# Ninja for a new build tree, as in tools/build.sh.
export CMAKE_GENERATOR=${CMAKE_GENERATOR:-Ninja}
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" -DLHR_SANITIZE=ON -DLHR_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)"
# The tests run the `lhr` executable too; it inherits these settings.
# intercept_tls_get_addr=0: the sanitizer runtimes of GCC <= 13 and LLVM <= 16
# take a dynamic TLS block that happens to start 16 bytes into a page for a
# pre-2.25 glibc block with a header, read a bogus range from before it, and
# LeakSanitizer's tracer then dies at exit ("Tracer caught signal 11") with no
# leak found. The image module is dlopen'ed and its libraries use dynamic TLS,
# so any run that writes an image could hit it by chance of a malloc address
# (docs/robustness.md, "What runs where").
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:abort_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:strict_string_checks=1:intercept_tls_get_addr=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
skip=(-LE slow)
[ "${LHR_ASAN_ALL:-0}" = 1 ] && skip=()
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" "${skip[@]}"
