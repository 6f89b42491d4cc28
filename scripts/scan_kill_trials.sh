#!/usr/bin/env bash
# kill -9 a `rotleak scan` at random moments, N times (default 3), then re-run the same command: the
# re-run must redo at most the point that was running (skipped + ran, and ran <= points not complete
# before it), and its table.csv must be byte-identical to an uninterrupted scan's (run first, with a
# different thread count).
# Usage: scripts/scan_kill_trials.sh ROTLEAK_BINARY [N]     Exit 1 on the first violation.
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
bin=$(realpath "$1")
trials=${2:-3}
scene=$(realpath "$(dirname "$0")/../data/scenes/stationary_sL_0.toml")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
args=(--over 'leak.omega=0,1e-4,2/3,1' --particles 1000000 --set run.t_max=6000 --no-progress)
"$bin" scan "$scene" "${args[@]}" --out timing >/dev/null  # how long an uninterrupted scan takes here
t0=$(date +%s.%N)
"$bin" scan "$scene" "${args[@]}" --out timing --force >/dev/null
span=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
"$bin" scan "$scene" "${args[@]}" --threads 1 --out whole >/dev/null
for t in $(seq 1 "$trials"); do
  rm -rf cut
  "$bin" scan "$scene" "${args[@]}" --out cut >/dev/null 2>&1 &
  pid=$!
  sleep "$(awk -v s="$span" -v r="$RANDOM" 'BEGIN { printf "%.2f", s * (0.05 + 0.9 * r / 32768) }')"
  kill -9 "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  done_before=$(find cut/points -maxdepth 2 -name summary.json 2>/dev/null | wc -l)
  "$bin" scan "$scene" "${args[@]}" --out cut --json >resumed.json
  "$py" - "$t" "$done_before" <<'PY'
import json, sys
t, before = sys.argv[1], int(sys.argv[2])
d = json.load(open("resumed.json"))
if d["ran"] + d["skipped"] != 4 or d["ran"] > 4 - before + 1:
    sys.exit("trial %s: %d complete before, then ran %d, skipped %d" % (t, before, d["ran"], d["skipped"]))
PY
  cmp -s whole/table.csv cut/table.csv || { echo "trial $t: table.csv differs from the uninterrupted scan"; exit 1; }
  echo "trial $t: $done_before point(s) complete at the kill; table identical"
done
