#!/usr/bin/env bash
# kill -9 a `rotleak simulate --force` into a directory that holds an earlier complete run, at random
# moments, N times (default 20). After each kill the target must be a complete run (every file that
# summary.json lists is there, survival.csv has all its rows), either the earlier one or the new
# one, never anything else; the next run must clean what the killed one left.
# Usage: scripts/kill_trials.sh ROTLEAK_BINARY [N]     Exit 1 on the first violation.
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
bin=$(realpath "$1")
trials=${2:-20}
scene=$(realpath "$(dirname "$0")/../data/scenes/quickstart.toml")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
common=(--particles 100000 --no-progress --set run.t_max=2000 --set observe.survival_dt=0.005
        --set 'observe.collision_density={bins=1000, windows=[[0, 2000]]}')
"$bin" simulate "$scene" --out target "${common[@]}" --set ensemble.seed=1 >/dev/null
check() {  # the target is a complete run with seed 1 or 2
  [ -f target/summary.json ] || { echo "trial $1: target has no summary.json"; return 1; }
  "$py" - "$1" <<'PY'
import json, os, sys
s = json.load(open("target/summary.json"))
for f in s["files"]:
    if not os.path.exists(os.path.join("target", f)):
        sys.exit(f"trial {sys.argv[1]}: summary.json lists {f}, which is missing")
rows = sum(1 for _ in open("target/survival.csv")) - 1
want = int(s["scene"]["run"]["t_max"] / s["scene"]["observe"]["survival_dt"]) + 1
if rows != want:
    sys.exit(f"trial {sys.argv[1]}: survival.csv has {rows} rows, not {want}")
if s["seed"] not in (1, 2):
    sys.exit(f"trial {sys.argv[1]}: seed {s['seed']}")
PY
}
kept_old=0 new=0
for ((i = 1; i <= trials; i++)); do
  "$bin" simulate "$scene" --out target --force "${common[@]}" --set ensemble.seed=2 >/dev/null 2>&1 &
  pid=$!
  sleep "$(printf "0.%03d" $((RANDOM % 400)))"  # uniform in [0, 0.4) s: the run takes about 0.35 s
  kill -9 "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  check "$i"
  if grep -q '"seed": 2' target/summary.json; then new=$((new + 1)); else kept_old=$((kept_old + 1)); fi
  # back to the earlier run for the next trial; this run also cleans what the killed one left
  "$bin" simulate "$scene" --out target --force "${common[@]}" --set ensemble.seed=1 >/dev/null
  left=$(find . -maxdepth 1 -name '.target.*' | wc -l)
  [ "$left" -eq 0 ] || { echo "trial $i: $left staging entries left after the next run"; exit 1; }
done
echo "$trials kill -9 trials: target always complete ($kept_old times the earlier run, $new times the new one); nothing left behind"
