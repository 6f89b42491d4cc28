#!/usr/bin/env bash
# Reproduces the study panel by panel (data/study/panels.tsv: one rotleak scan each, on
# data/study/study.toml, with importance sampling, the fast-forward and population splitting), the
# MUPO coverings of the rotating panels, then writes the report (scripts/study_report.py): every
# figure and the published-vs-ours table. Resumable: a re-run skips every complete point (rotleak scan).
# It writes under its output directory only, the report in OUT/report, unless --docs asks it to
# replace the tracked report (docs/study, or docs/study/full for the full run). Usage:
#   scripts/reproduce_study.sh --quick         # 10^5 lines a point, runs/study-quick, a few minutes on 2 cores
#   scripts/reproduce_study.sh                 # 10^6 lines a point, runs/study (expected time printed first)
#   scripts/reproduce_study.sh --quick --docs  # ... and rewrite docs/study/README.md and its pictures
#   options: --particles N (lines a point), --out DIR (output directory)
# (a line: a starting particle and its descendants, run.splitting; docs/model.md "Deep tails")
# ROTLEAK (default build/rotleak) names the binary.
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
cd "$(dirname "$0")/.."
rotleak=${ROTLEAK:-build/rotleak}
quick=0 to_docs=0 particles="" out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --docs) to_docs=1 ;;
    --particles) particles=$2; shift ;;
    --out) out=$2; shift ;;
    *) echo "reproduce_study: unknown argument $1 (allowed: --quick, --docs, --particles N, --out DIR)" >&2; exit 2 ;;
  esac
  shift
done
if [ "$quick" = 1 ]; then
  particles=${particles:-100000}
  out=${out:-runs/study-quick}
  docs=docs/study
else
  particles=${particles:-1000000}
  out=${out:-runs/study}
  docs=docs/study/full
  # measured on the 2-core development machine (AMD EPYC): 1407 s in all at 683968a, the stationary
  # panel's f_c points about 2 minutes each (117 s for s_L = 0); since f_c counts a fast-forwarded
  # stretch whole, 69 s for s_L = 0 (same fc.csv); the rotating points seconds to a minute
  [ "$particles" = 1000000 ] &&
    echo "reproduce_study: full run, 10^6 lines a point: expect about an hour on 2 cores (resumable)" >&2
fi
[ "$to_docs" = 1 ] || docs=$out/report
mkdir -p "$out"
start=$(date +%s)
while IFS=$'\t' read -r name title args; do
  [ -z "$name" ] || [ "${name:0:1}" = "#" ] && continue
  echo "reproduce_study: panel $name: $title" >&2
  # shellcheck disable=SC2086  # the panel's arguments are words
  "$rotleak" scan data/study/study.toml $args --particles "$particles" --set ensemble.sampling=mupo \
    --set run.fast_forward=true --set run.splitting=true --out "$out/$name" --no-progress >/dev/null
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
"$py" scripts/study_report.py "$out" "$docs" "$particles" "$seconds"
echo "reproduce_study: report in $docs/README.md" >&2
