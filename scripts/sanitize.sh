#!/usr/bin/env bash
# The unit and numeric tests under AddressSanitizer + UndefinedBehaviorSanitizer (LeakSanitizer with
# ASan): builds build-asan/ (-DROTLEAK_SANITIZE=ON, GCC, no Python module, no MPI, no benchmarks) and
# runs every test labelled unit or numeric there but the ones that check the tree rather than run code
# (format, layers, docs) and the install tree. A report fails the test that made it.
# Usage: scripts/sanitize.sh [extra ctest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/ninja_tree.sh build-asan
cmake -G Ninja -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DROTLEAK_SANITIZE=ON -DROTLEAK_TESTS=ON \
  -DROTLEAK_BENCH=OFF -DROTLEAK_PYTHON_MODULE=OFF -DROTLEAK_MPI=OFF -DROTLEAK_GPU=OFF -DROTLEAK_WARNINGS=OFF >/dev/null
cmake --build build-asan -j"$(nproc)"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd build-asan
ctest -j"$(nproc)" --output-on-failure --timeout 900 -L 'unit|numeric' \
  -E '^(Format\.|Layers\.|Docs\.|Install\.|Package\.|MutationAudit\.)' "$@"
