#!/usr/bin/env bash
# Executes docs/notebooks/tour.ipynb with scripts/notebook.sh (the README's command) against a build: 10^5 particles a run, everything written to a temporary directory
# (removed after), and checks that the notebook ran through and drew its figure.
# Usage: scripts/notebook_check.sh BUILD_DIR
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
build=$(realpath "$1")
src=$(realpath "$(dirname "$0")/..")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bash "$src/scripts/notebook.sh" "$build" "$work/out" >/dev/null  # the command the README gives
mkdir -p "$work/nb" && cp "$work/out/tour.ipynb" "$work/nb/tour.ipynb"
test -s "$work/out/notebook_tour.png" || { echo "the notebook ran but drew no figure"; exit 1; }
"$py" - "$work/nb/tour.ipynb" <<'PY'
import json, sys
nb = json.load(open(sys.argv[1]))
errors = [o for c in nb["cells"] if c["cell_type"] == "code" for o in c.get("outputs", []) if o.get("output_type") == "error"]
ran = sum(1 for c in nb["cells"] if c["cell_type"] == "code" and c.get("execution_count"))
if errors or ran == 0:
    sys.exit("notebook: %d errors, %d cells run" % (len(errors), ran))
print("notebook: %d code cells executed, no errors, figure drawn" % ran)
PY
