#!/usr/bin/env bash
# Installs the Debian packages (if missing), configures and builds rotleak in build/ (Release).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DROTLEAK_TESTS=ON -DROTLEAK_BENCH=ON >/dev/null
cmake --build build -j"$(nproc)"
