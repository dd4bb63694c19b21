#!/usr/bin/env bash
# The test suite: set up, build, run every test with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 600
