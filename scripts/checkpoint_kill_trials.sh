#!/usr/bin/env bash
# kill -9 a `rotleak simulate` twice at random moments, resume it (--resume) until it completes, N times
# (default 3): survival.csv and fc.csv must be byte-identical to an uninterrupted run's (made with
# another thread count). The scene exercises every tally: importance-sampling weights (exact sums),
# f_c, a rotating leak; checkpoints every 0.2 s so that kills land between and during them.
# Further arguments are extra scene keys (run.splitting=true: a split run).
# Usage: scripts/checkpoint_kill_trials.sh ROTLEAK_BINARY [N] [PARTICLES] [KEY=VALUE ...]
# Exit 1 on the first violation.
set -euo pipefail
bin=$(realpath "$1")
trials=${2:-3}
particles=${3:-400000}
extra=()
for kv in "${@:4}"; do extra+=(--set "$kv"); done
scene=$(realpath "$(dirname "$0")/../data/scenes/stationary_sL_0.toml")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
args=("$scene" --particles "$particles" --set leak.omega=2/3 --set ensemble.sampling=mupo --set run.t_max=5000
  --set 'observe.collision_density={bins=100}' --set run.checkpoint_seconds=0.2 ${extra[@]+"${extra[@]}"} --no-progress)
t0=$(date +%s.%N)
"$bin" simulate "${args[@]}" --threads 1 --out whole >/dev/null
span=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print (b - a) / 2 }')  # two threads below
for t in $(seq 1 "$trials"); do
  rm -rf cut cut.checkpoint
  kills=0 runs=0 resumed=0
  while [ ! -f cut/summary.json ]; do
    if [ -f cut.checkpoint ]; then
      how=(--resume cut)
      resumed=$((resumed + 1))
    else
      how=(--out cut)
    fi
    runs=$((runs + 1))
    [ "$runs" -gt 20 ] && { echo "trial $t: no end after 20 runs"; exit 1; }
    if [ "$kills" -lt 2 ]; then
      "$bin" simulate "${args[@]}" --threads 2 "${how[@]}" >/dev/null 2>&1 &
      pid=$!
      sleep "$(awk -v s="$span" -v r="$RANDOM" 'BEGIN { printf "%.2f", s * (0.1 + 0.5 * r / 32768) }')"
      if kill -9 "$pid" 2>/dev/null; then kills=$((kills + 1)); fi
      wait "$pid" 2>/dev/null || true
    else
      "$bin" simulate "${args[@]}" --threads 2 "${how[@]}" >/dev/null 2>&1
    fi
  done
  [ -f cut.checkpoint ] && { echo "trial $t: checkpoint left beside a complete run"; exit 1; }
  for f in survival.csv fc.csv; do
    cmp -s "whole/$f" "cut/$f" || { echo "trial $t: $f differs from the uninterrupted run"; exit 1; }
  done
  echo "trial $t: killed $kills times, $runs runs ($resumed from a checkpoint); survival.csv and fc.csv identical"
done
