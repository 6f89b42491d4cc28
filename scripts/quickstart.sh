#!/usr/bin/env bash
# The main job: set up, build the tool and the Python module (their targets only: the tests and benchmarks
# are built by scripts/test.sh), run the quick-start scene (s_L = 0, 10^6 particles), print kappa and
# alpha, write runs/quickstart/ with survival.png and fc.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh rotleak rotleak_python
./build/rotleak simulate data/scenes/quickstart.toml --out runs/quickstart --force --plot
