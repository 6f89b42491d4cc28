#!/usr/bin/env bash
# Reproduces the study panel by panel (data/study/panels.tsv: one rotleak scan each, on
# data/study/study.toml, with importance sampling), the MUPO coverings of the rotating panels, then
# writes docs/study/README.md (scripts/study_report.py): every figure and the published-vs-ours table.
# Resumable: a re-run skips every complete point (rotleak scan). Usage:
#   scripts/reproduce_study.sh --quick   # 10^5 particles a point, runs/study-quick, a few minutes on 2 cores
#   scripts/reproduce_study.sh           # 10^7 particles a point, runs/study, docs/study/full (expected time printed first)
# ROTLEAK (default build/rotleak) names the binary.
set -euo pipefail
cd "$(dirname "$0")/.."
rotleak=${ROTLEAK:-build/rotleak}
quick=0
[ "${1:-}" = "--quick" ] && quick=1
if [ "$quick" = 1 ]; then
  particles=100000
  out=runs/study-quick
  docs=docs/study
else
  particles=10000000
  out=runs/study
  docs=docs/study/full
  # measured on the 2-core development machine (AMD EPYC): 104.5 min for all panels (6239 s of point
  # simulations), plus about 45 min for the stationary panel's f_c since the fast-forward shows each
  # skipped bounce to f_c (436 s for s_L = 0)
  echo "reproduce_study: full run, 10^7 particles a point: expect about 2.5 hours on 2 cores (resumable)" >&2
fi
mkdir -p "$out"
start=$(date +%s)
while IFS=$'\t' read -r name title args; do
  [ -z "$name" ] || [ "${name:0:1}" = "#" ] && continue
  echo "reproduce_study: panel $name: $title" >&2
  # shellcheck disable=SC2086  # the panel's arguments are words
  "$rotleak" scan data/study/study.toml $args --particles "$particles" --set ensemble.sampling=mupo \
    --set run.fast_forward=true --out "$out/$name" --no-progress >/dev/null
  "$rotleak" plot "$out/$name" >/dev/null
  if [ "$name" = stationary ]; then  # f_c of each leak
    for point in "$out/$name"/points/*/; do "$rotleak" plot "$point" >/dev/null; done
  fi
  # f_L at delta = 1e-7 for the panel's omegas (the rotating panels of the high regime)
  ws=$(echo "$args" | grep -o 'leak.omega=[^ ]*' | sed 's/leak.omega=//; s/,/ /g' || true)
  if [ -n "$ws" ] && [ "$name" != low_omega ]; then
    # shellcheck disable=SC2086
    "$rotleak" covering --omega $ws --delta 1e-7 --out "$out/covering_$name" --force >/dev/null
  fi
done <data/study/panels.tsv
# ln(19) at two deltas
"$rotleak" covering --omega "ln(19)" --delta 1e-7 1e-9 --out "$out/covering_ln19" --force >/dev/null
seconds=$(($(date +%s) - start))
/usr/bin/python3 scripts/study_report.py "$out" "$docs" "$particles" "$seconds"
