#!/usr/bin/env bash
# The omega atlas: every p/q with q <= 30, eps families near 1/3, 2/5, 3/8 and 2/3, and 20 irrationals
# (data/atlas/sets.tsv: one rotleak scan each on data/study/study.toml, mupo sampling, the fast-forward and
# population splitting), then the report (scripts/atlas_report.py): the table and the figures of the tail
# amplitude C, the tail ends and alpha against omega. Resumable: a re-run skips every complete point
# (rotleak scan), and each scan prints its progress line. Usage:
#   scripts/atlas.sh                 # 10^5 lines a point, runs/atlas (about 20 minutes on 2 cores)
#   scripts/atlas.sh --docs          # ... and rewrite docs/study/atlas (README.md and its pictures)
#   options: --particles N (lines a point), --out DIR (output directory), --only NAME (one set)
# ROTLEAK (default build/rotleak) names the binary.
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
cd "$(dirname "$0")/.."
rotleak=${ROTLEAK:-build/rotleak}
particles=100000 out=runs/atlas to_docs=0 only=""
while [ $# -gt 0 ]; do
  case "$1" in
    --docs) to_docs=1 ;;
    --particles) particles=$2; shift ;;
    --out) out=$2; shift ;;
    --only) only=$2; shift ;;
    *) echo "atlas: unknown argument $1 (allowed: --docs, --particles N, --out DIR, --only NAME)" >&2; exit 2 ;;
  esac
  shift
done
docs=$out/report
[ "$to_docs" = 1 ] && docs=docs/study/atlas
mkdir -p "$out"
start=$(date +%s)
while IFS=$'\t' read -r name title args; do
  [ -z "$name" ] || [ "${name:0:1}" = "#" ] && continue
  [ -n "$only" ] && [ "$name" != "$only" ] && continue
  echo "atlas: $name: $title" >&2
  # shellcheck disable=SC2086  # the set's arguments are words
  "$rotleak" scan data/study/study.toml $args --particles "$particles" --set ensemble.sampling=mupo \
    --set run.fast_forward=true --set run.splitting=true --out "$out/$name" >/dev/null
done <data/atlas/sets.tsv
seconds=$(($(date +%s) - start))
"$py" scripts/atlas_report.py "$out" "$docs" "$particles" "$seconds"
echo "atlas: report in $docs/README.md ($seconds s)" >&2
