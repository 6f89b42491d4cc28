#!/usr/bin/env bash
# atlas.sh end to end at a small size (the irrationals and one eps family, 2000 lines a point) into a
# temporary directory: it must write its report there and change no tracked file (docs/study/atlas keeps
# its bytes), and what it writes -- the scans and atlas.csv -- must read back with Python's csv and json
# and pandas as docs/output.md describes (scripts/check_output_schema.py).   Usage: scripts/atlas_check.sh BINARY
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
bin=$(realpath "$1")
src=$(realpath "$(dirname "$0")/..")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
before=$(cd "$src" && find docs/study/atlas -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum)
for set in irrationals near_2o5; do
  ROTLEAK=$bin bash "$src/scripts/atlas.sh" --only "$set" --particles 2000 --out "$work/atlas" 2>"$work/log" ||
    { tail -5 "$work/log"; exit 1; }
done
after=$(cd "$src" && find docs/study/atlas -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum)
[ "$before" = "$after" ] || { echo "atlas.sh changed docs/study/atlas without --docs"; exit 1; }
test -s "$work/atlas/report/README.md" || { echo "no report in OUT/report"; exit 1; }
mkdir "$work/schema" && cp "$work/atlas/report/atlas.csv" "$work/schema/"
"$py" "$src/scripts/check_output_schema.py" "$work/schema" "$work/atlas/irrationals" "$work/atlas/near_2o5" >"$work/log" ||
  { grep -E "FAIL|schema:" "$work/log" | head -5; exit 1; }
rows=$("$py" -c "import pandas, sys; print(len(pandas.read_csv(sys.argv[1])))" "$work/schema/atlas.csv")
[ "$rows" = 24 ] || { echo "atlas.csv has $rows rows, not 24 (20 irrationals, 4 near 2/5)"; exit 1; }
n=$(grep -c '^!\[' "$work/atlas/report/README.md")
echo "atlas.sh --particles 2000: report with $n pictures and 24 rows in its output directory; docs/study/atlas untouched"
