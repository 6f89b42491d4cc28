#!/usr/bin/env bash
# The whole test suite: set up, build, run every GoogleTest binary through CTest (labels unit,
# numeric, slow). About a minute of tests on 2 cores after the build.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build
ctest -j"$(nproc)" --output-on-failure --timeout 600
