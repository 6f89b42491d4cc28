#!/usr/bin/env bash
# Installs the Debian packages (if missing), configures and builds rotleak in build/ (Release), with
# the project's warnings on; under CI (CI set in the environment) a warning fails the build.
# ROTLEAK_PREBUILT=DIR uses the build in DIR instead (build/ must be it or a link to it): the docs runner
# (scripts/run_docs.py) runs the README's commands in a copy of the tree against the suite's own build.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
if [ -n "${ROTLEAK_PREBUILT:-}" ]; then
  if [ ! -x build/rotleak ] || [ "$(realpath build)" != "$(realpath "$ROTLEAK_PREBUILT")" ]; then
    echo "build.sh: ROTLEAK_PREBUILT=$ROTLEAK_PREBUILT, but build/ is not that build" >&2
    exit 2
  fi
  exit 0
fi
werror=OFF
[ -n "${CI:-}" ] && werror=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DROTLEAK_TESTS=ON -DROTLEAK_BENCH=ON -DROTLEAK_WARNINGS=ON -DROTLEAK_PYTHON_MODULE=ON \
  -DROTLEAK_WERROR="$werror" >/dev/null
cmake --build build -j"$(nproc)"
