#!/usr/bin/env bash
# Installs the Debian packages (if missing), configures and builds rotleak in build/ (Release), with
# the project's warnings on; under CI (CI set in the environment) a warning fails the build.
# Usage: scripts/build.sh [TARGET ...]: only those targets (the quick start builds `rotleak` and the Python
# module), else everything (the tool, the Python module, the tests, the benchmarks). Objects go through
# ccache when it is installed (CMakeLists.txt), so a second clone or a second tree compiles little.
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
# Ninja (Debian's ninja-build): it starts a library's dependants' objects before the library is linked,
# where make waits; a build/ made by another generator is configured afresh (ccache keeps its objects).
bash scripts/ninja_tree.sh build
werror=OFF
[ -n "${CI:-}" ] && werror=ON
cmake -G Ninja -S . -B build -DCMAKE_BUILD_TYPE=Release -DROTLEAK_TESTS=ON -DROTLEAK_BENCH=ON -DROTLEAK_WARNINGS=ON -DROTLEAK_PYTHON_MODULE=ON \
  -DROTLEAK_WERROR="$werror" >/dev/null
if (($#)); then
  cmake --build build -j"$(nproc)" --target "$@"
else
  cmake --build build -j"$(nproc)"
fi
