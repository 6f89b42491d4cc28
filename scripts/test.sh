#!/usr/bin/env bash
# The whole test suite: set up, build, then
#  1. the unit and numeric tests again under AddressSanitizer + UndefinedBehaviorSanitizer
#     (scripts/sanitize.sh, build-asan/);
#  2. a short run (10 s each) of the libFuzzer targets of every reader, after their kept regression
#     inputs (scripts/fuzz.sh, build-fuzz/, clang);
#  3. every GoogleTest binary through CTest (labels unit, numeric, slow) in build/: its summary is the
#     last thing printed.
# ROTLEAK_QUICK_TESTS=1 skips 1 and 2 (a developer's loop; CI runs all three).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
if [ -z "${ROTLEAK_QUICK_TESTS:-}" ]; then
  bash scripts/sanitize.sh
  bash scripts/fuzz.sh 10
fi
cd build
ctest -j"$(nproc)" --output-on-failure --timeout 600
