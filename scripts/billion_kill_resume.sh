#!/usr/bin/env bash
# The large-run check of checkpoints: an omega = 2/3 run of PARTICLES (default 10^9) made once without
# interruption, and once killed with SIGKILL twice at random moments and resumed (--resume) until it
# completes; survival.csv and the fitted numbers must be byte-identical. Prints the wall times: the
# uninterrupted run (checkpoints at the default 300 s), each piece of the killed one (checkpoints every
# CHECKPOINT_SECONDS, default 30) and their sum, which includes the work lost at each kill.
# Usage: scripts/billion_kill_resume.sh ROTLEAK_BINARY [PARTICLES] [CHECKPOINT_SECONDS] [WORKDIR]
# Exit 1 when the outputs differ.
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
bin=$(realpath "$1")
particles=${2:-1000000000}
every=${3:-30}
scene=$(realpath "$(dirname "$0")/../data/scenes/stationary_sL_0.toml")
work=${4:-$(mktemp -d)}
mkdir -p "$work"
cd "$work"
rm -rf whole cut cut.checkpoint
args=("$scene" --particles "$particles" --set leak.omega=2/3 --no-progress)
now() { date +%s.%N; }
# the blocks the checkpoint holds (its JSON header), or nothing when there is none
checkpointed() {
  [ -f cut.checkpoint ] || return 0
  "$py" - cut.checkpoint <<'PY2'
import json, sys
raw = open(sys.argv[1], 'rb').read(1 << 20).decode('latin-1')
h, _ = json.JSONDecoder().raw_decode(raw[raw.index('{'):])
blocks = sum(b - a for a, b in h['done'])
print(f"; checkpoint holds {blocks} blocks of {h['block_size']} ({min(blocks * h['block_size'], h['particles']) / h['particles']:.1%})")
PY2
}
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

t0=$(now)
"$bin" simulate "${args[@]}" --out whole >/dev/null
t1=$(now)
whole=$(secs "$t0" "$t1")
echo "uninterrupted: $whole s wall ($particles particles, checkpoints every 300 s)"

pieces=() kills=0 total=0
while [ ! -f cut/summary.json ]; do
  if [ -f cut.checkpoint ]; then how=(--resume cut); else how=(--out cut); fi
  a=$(now)
  if [ "$kills" -lt 2 ]; then
    "$bin" simulate "${args[@]}" --set run.checkpoint_seconds="$every" "${how[@]}" >/dev/null 2>&1 &
    pid=$!
    # somewhere in the first 20-50% of an uninterrupted run's time
    sleep "$(awk -v s="$whole" -v r="$RANDOM" 'BEGIN { printf "%.1f", s * (0.2 + 0.3 * r / 32768) }')"
    kill -9 "$pid" 2>/dev/null && kills=$((kills + 1))
    wait "$pid" 2>/dev/null || true
    what="killed (SIGKILL)"
  else
    "$bin" simulate "${args[@]}" --set run.checkpoint_seconds="$every" "${how[@]}" >/dev/null
    what="completed"
  fi
  b=$(now)
  echo "  ${how[0]} piece: $(secs "$a" "$b") s, $what$(checkpointed)"
  total=$(awk -v x="$total" -v y="$(secs "$a" "$b")" 'BEGIN { printf "%.1f", x + y }')
  [ "${#pieces[@]}" -gt 10 ] && { echo "no end after 10 pieces"; exit 1; }
  pieces+=("$a")
done
echo "killed twice and resumed: $total s wall in ${#pieces[@]} pieces (checkpoints every $every s)"
cmp whole/survival.csv cut/survival.csv
# summary.json without "execution" (wall time, rate, threads, ranks, kernel width, host, build) and the
# checkpoint interval
numbers() {
  "$py" -c 'import json, sys
s = json.load(open(sys.argv[1]))
s.pop("execution")
s["scene"]["run"].pop("checkpoint_seconds")  # not an input of the numbers
print(json.dumps(s, sort_keys=True))' "$1"
}
[ "$(numbers whole/summary.json)" = "$(numbers cut/summary.json)" ] || { echo "summary.json numbers differ"; exit 1; }
echo "survival.csv identical (sha256 $(sha256sum whole/survival.csv | cut -c1-16)...); summary.json identical but for timing fields"
