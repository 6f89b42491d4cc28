#!/usr/bin/env bash
# reproduce_study.sh end to end at a small size (--particles 2000, every panel, every covering, the
# report) into a temporary directory: it must write its report there and change no tracked file (the
# committed docs/study/README.md and its pictures keep their bytes).   Usage: scripts/study_check.sh BINARY
set -euo pipefail
bin=$(realpath "$1")
src=$(realpath "$(dirname "$0")/..")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
before=$(cd "$src" && find docs/study -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum)
ROTLEAK=$bin bash "$src/scripts/reproduce_study.sh" --quick --particles 2000 --out "$work/study" 2>"$work/log" ||
  { tail -5 "$work/log"; exit 1; }
after=$(cd "$src" && find docs/study -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum)
[ "$before" = "$after" ] || { echo "reproduce_study.sh changed docs/study without --docs"; exit 1; }
test -s "$work/study/report/README.md" || { echo "no report in OUT/report"; exit 1; }
n=$(grep -c '^!\[' "$work/study/report/README.md")
echo "reproduce_study.sh --particles 2000: report with $n pictures in its output directory; docs/study untouched"
