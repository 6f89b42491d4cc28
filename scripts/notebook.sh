#!/usr/bin/env bash
# Executes the example notebook docs/notebooks/tour.ipynb (a small study: a Scene built in Python, a 4-point scan, a refit, figures) against a build (Debian's jupyter-nbconvert and
# python3-ipykernel) and keeps the executed notebook and its figure: OUT_DIR/tour.ipynb and
# OUT_DIR/notebook_tour.png. The package and the binary come from BUILD_DIR by absolute paths, so it
# runs from any directory. ROTLEAK_NOTEBOOK_PARTICLES sets the particles a run (default 10^5).
# Usage: scripts/notebook.sh [BUILD_DIR] [OUT_DIR]   (defaults: build, runs/notebook)
set -euo pipefail
src=$(realpath "$(dirname "$0")/..")
build=$(realpath "${1:-$src/build}")
out=$(realpath -m "${2:-runs/notebook}")
[ -x "$build/rotleak" ] && [ -d "$build/python/rotleak" ] ||
  { echo "notebook: $build has no rotleak binary and Python package: run bash scripts/build.sh first" >&2; exit 2; }
mkdir -p "$out"
runtime=$(mktemp -d)
trap 'rm -rf "$runtime"' EXIT
export PYTHONPATH=$build/python${PYTHONPATH:+:$PYTHONPATH} ROTLEAK_BINARY=$build/rotleak ROTLEAK_NOTEBOOK_OUT=$out
export ROTLEAK_NOTEBOOK_PARTICLES=${ROTLEAK_NOTEBOOK_PARTICLES:-100000} PYDEVD_DISABLE_FILE_VALIDATION=1
export JUPYTER_RUNTIME_DIR=$runtime
jupyter nbconvert --to notebook --execute "$src/docs/notebooks/tour.ipynb" --output-dir "$out" 2>"$runtime/log" ||
  { cat "$runtime/log" >&2; exit 1; }
echo "wrote $out/tour.ipynb (executed) and $out/notebook_tour.png"
