#!/usr/bin/env bash
# The suite's second command, run by CI after scripts/test.sh:
#  1. the unit and numeric tests under AddressSanitizer + UndefinedBehaviorSanitizer (LeakSanitizer with
#     ASan) in build-asan/ (scripts/sanitize.sh, GCC);
#  2. every libFuzzer target of the readers (build-fuzz/, clang): its kept regression inputs, then
#     SECONDS of fuzzing each (scripts/fuzz.sh; 10 s by default, the suite's short run).
# Each stage's wall time is printed at the end.
# Usage: scripts/test_sanitizers.sh [SECONDS_EACH]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/stage.sh
trap stage_summary EXIT
stage "sanitizers (ASan + UBSan)" bash scripts/sanitize.sh
stage "fuzz (${1:-10} s a target)" bash scripts/fuzz.sh "${1:-10}"
