#!/usr/bin/env bash
# Executes docs/notebooks/tour.ipynb with scripts/notebook.sh (the README's command) against a build: 10^5 particles a run, everything written to a temporary directory
# (removed after), and checks that the notebook ran through, drew its figure, and made its study: a Scene saved, a
# 4-point scan refitted, its figures as PNG and PDF.
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
# the study it makes: a Scene saved, a 4-point scan refitted (each point's previous summary kept), figures as PNG and PDF
"$py" - "$work/out" <<'PY'
import json, os, sys
out = sys.argv[1]
scan = json.load(open(os.path.join(out, "study_scan", "scan.json")))
points = [os.path.join(out, "study_scan", "points", p["point"]) for p in scan["points"]]
checks = {"the scene saved": os.path.exists(os.path.join(out, "study.toml")),
          "4 points from a Python Scene": len(points) == 4 and scan["scene"] == "rotleak.Scene",
          "refitted": all(os.path.exists(os.path.join(p, "summary.prev.json")) for p in points),
          "PNG and PDF": all(open(os.path.join(out, "study_scan", "scan_%s.%s" % (n, f)), "rb").read(4) in (b"%PDF", b"\x89PNG")
                             for n in ("survival", "leak_omega") for f in ("png", "pdf"))}
failed = [k for k, ok in checks.items() if not ok]
if failed:
    sys.exit("notebook: its study lacks " + ", ".join(failed))
print("notebook: a Scene, a 4-point scan, a refit, figures as PNG and PDF")
PY
