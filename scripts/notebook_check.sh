#!/usr/bin/env bash
# Executes docs/notebooks/tour.ipynb with jupyter nbconvert (Debian's jupyter-nbconvert and
# python3-ipykernel) against a build: 10^5 particles a run, everything written to a temporary directory
# (removed after), and checks that the notebook ran through and drew its figure.
# Usage: scripts/notebook_check.sh BUILD_DIR
set -euo pipefail
build=$(realpath "$1")
src=$(realpath "$(dirname "$0")/..")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export PYTHONPATH=$build/python ROTLEAK_BINARY=$build/rotleak ROTLEAK_NOTEBOOK_OUT=$work/out
export ROTLEAK_NOTEBOOK_PARTICLES=${ROTLEAK_NOTEBOOK_PARTICLES:-100000} PYDEVD_DISABLE_FILE_VALIDATION=1
export JUPYTER_RUNTIME_DIR=$work/runtime
jupyter nbconvert --to notebook --execute "$src/docs/notebooks/tour.ipynb" --output-dir "$work/nb" 2>"$work/log" ||
  { cat "$work/log"; exit 1; }
test -s "$work/out/notebook_tour.png" || { echo "the notebook ran but drew no figure"; exit 1; }
/usr/bin/python3 - "$work/nb/tour.ipynb" <<'PY'
import json, sys
nb = json.load(open(sys.argv[1]))
errors = [o for c in nb["cells"] if c["cell_type"] == "code" for o in c.get("outputs", []) if o.get("output_type") == "error"]
ran = sum(1 for c in nb["cells"] if c["cell_type"] == "code" and c.get("execution_count"))
if errors or ran == 0:
    sys.exit("notebook: %d errors, %d cells run" % (len(errors), ran))
print("notebook: %d code cells executed, no errors, figure drawn" % ran)
PY
