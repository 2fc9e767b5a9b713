#!/usr/bin/env bash
# Builds lhr and runs the whole test suite, `slow` tests included (CI's
# release stage; docs/robustness.md, "What runs where"). Tests labelled `slow`
# carry a high ctest COST, so they start first and overlap the short ones.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
