#!/usr/bin/env bash
# The README's test command: set up, build everything in build/ (Release: the tool, the Python module, the
# tests, the benchmarks), then run the Release suite through CTest: every GoogleTest case and every
# script test (labels unit, numeric, slow: the numerics, the docs' blocks, the Python package, the
# output schemas, kill-and-resume, MPI, install and package). Its summary is the last thing printed,
# after each stage's wall time. The sanitizer and fuzz stages are scripts/test_sanitizers.sh, which CI
# runs after this one. Extra arguments go to ctest (-L unit, -R Pattern, ...).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/stage.sh
trap stage_summary EXIT
stage setup bash scripts/setup.sh
stage "build (Release, everything)" bash scripts/build.sh
cd build
stage "ctest (Release)" ctest -j"$(nproc)" --output-on-failure --timeout 600 "$@"
