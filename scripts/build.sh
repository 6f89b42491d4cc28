#!/usr/bin/env bash
# Installs the Debian packages (if missing), configures and builds rotleak in build/ (Release), with
# the project's warnings on; under CI (CI set in the environment) a warning fails the build.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
werror=OFF
[ -n "${CI:-}" ] && werror=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DROTLEAK_TESTS=ON -DROTLEAK_BENCH=ON -DROTLEAK_WARNINGS=ON -DROTLEAK_PYTHON_MODULE=ON \
  -DROTLEAK_WERROR="$werror" >/dev/null
cmake --build build -j"$(nproc)"
