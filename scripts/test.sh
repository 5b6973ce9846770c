#!/usr/bin/env bash
# The test suite: install what is missing, build (warnings as errors), run ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh -DVOLTS_WARNINGS_AS_ERRORS=ON
BUILD_DIR=${VOLTS_BUILD_DIR:-build}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$(nproc)" --timeout 600 "$@"
