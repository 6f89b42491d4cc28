#!/usr/bin/env bash
# Every kind of file rotleak writes, made once and read back against docs/output.md's schemas with
# Python's csv and json and with pandas (scripts/check_output_schema.py): a run with escapes and f_c, a
# split run, a 3-point scan, a run and a scan on other tables (two leaks), a shadow, a covering of two omegas with segments, an audit, proven orbits and a certified sample. Then four
# damaged copies (a row one field short, an undocumented summary.json key, a renamed column, a flipped bit in a
# split run's tally.bin) must be
# refused, so the check is seen to fail where it should.
# Usage: scripts/check_outputs.sh ROTLEAK_BINARY      Exit 1 on any violation.
set -euo pipefail
bin=$(realpath "$1")
here=$(dirname "$(realpath "$0")")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scene="$here/../data/scenes/quickstart.toml"
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
q=(--no-progress)
"$bin" simulate "$scene" --particles 20000 --set observe.escapes=true --out "$work/out/run" "${q[@]}" >/dev/null
"$bin" simulate "$scene" --particles 500 --set run.tier=float --out "$work/out/scalar" "${q[@]}" >/dev/null
"$bin" simulate "$here/../data/scenes/stationary_sL_0.toml" --particles 4000 --set ensemble.sampling=mupo \
  --set run.splitting=true --set run.t_max=3000 --out "$work/out/split" "${q[@]}" >/dev/null
"$bin" scan "$scene" --over leak.omega=0,1,2/3 --set ensemble.particles=5000 --out "$work/out/scan" "${q[@]}" >/dev/null
# any table with two leaks (summary.json's table and leaks, leaks.csv, fc by the boundary's share), and a scan of one
"$bin" simulate "$here/../data/scenes/tables/sinai.toml" --particles 5000 --set run.t_max=2000 --set observe.escapes=true \
  --set "observe.collision_density={ bins = 50 }" --out "$work/out/table" "${q[@]}" >/dev/null
"$bin" scan "$here/../data/scenes/tables/mushroom.toml" --over leak.width=0.01,0.02 --set ensemble.particles=2000 \
  --set run.t_max=1000 --out "$work/out/table_scan" "${q[@]}" >/dev/null
"$bin" shadow "$scene" --particle 3 --tiers float,double,dd --collisions 300 --out "$work/out/shadow" >/dev/null
"$bin" covering --omega 2/3 --omega 1e-4 --resolution 200 --segments --out "$work/out/covering" >/dev/null
"$bin" audit "$scene" --sample 20 --stats-particles 20000 --stratify-particles 5000 --max-collisions 200 \
  --tiers float,double --threads 2 --out "$work/out/audit" >/dev/null
"$bin" orbits --period-max 5 --out "$work/out/orbits" --no-progress
"$bin" certify "$scene" --sample 40 --t-cap 500 --out "$work/out/certify" --no-progress >/dev/null
"$py" "$here/check_output_schema.py" "$work/out"

# the check must fail on damaged files
refused() {  # DIR WHAT
  if "$py" "$here/check_output_schema.py" "$1" >"$work/log" 2>&1; then
    echo "check_output_schema.py accepted $2"
    exit 1
  fi
  grep "^schema:" "$work/log" | head -1
}
mkdir -p "$work/bad1" "$work/bad2" "$work/bad3"
awk -F, -v OFS=, 'NR == 3 { NF = NF - 1 } { print }' "$work/out/scan/table.csv" >"$work/bad1/table.csv"
refused "$work/bad1" "a table.csv row one field short"
"$py" -c 'import json, sys; d = json.load(open(sys.argv[1])); d["host"] = "x"; json.dump(d, open(sys.argv[2], "w"))' \
  "$work/out/run/summary.json" "$work/bad2/summary.json"
refused "$work/bad2" "an undocumented key in summary.json"
sed '1s/P_err/P_error/' "$work/out/run/survival.csv" >"$work/bad3/survival.csv"
refused "$work/bad3" "a renamed survival.csv column"
mkdir -p "$work/bad4"
"$py" -c 'import sys; d = bytearray(open(sys.argv[1], "rb").read()); d[-20] ^= 1; open(sys.argv[2], "wb").write(d)' \
  "$work/out/split/tally.bin" "$work/bad4/tally.bin"
refused "$work/bad4" "a tally.bin with one bit flipped"
echo "every file matches docs/output.md; damaged copies refused"
