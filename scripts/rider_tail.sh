#!/usr/bin/env bash
# How much of P(t) the riding lines of one band of |p| carry (docs/model.md, "Riding orbits"), against what a split
# run of the whole scene draws. Two runs of the default stadium at OMEGA:
#   band:  unsplit, 99% of the draws on |p| in [LO, HI] (ensemble.sampling_eps = 0.01), BAND_N lines. Its P(t) is
#          the band's share of the true P(t): the 1% uniform share's lines weigh 100 / BAND_N each and none is alive
#          where that share is below P (the script prints where it stops mattering).
#   split: mupo with population splitting, SPLIT_N lines, the README's deep-tail run.
# Both are unbiased for their own part, so band + split is what P is at least; where the band's share is larger than
# the split run's P, the split run (which draws a line of the band alive there about once in thousands of runs)
# reads P low by that much.
# Usage: scripts/rider_tail.sh ROTLEAK OMEGA LO HI [BAND_N SPLIT_N T_MAX STEP]
#        (defaults 100000000 100000 10000 500; 10^8 band lines take 91 s on the 2-core development machine)
set -euo pipefail
rotleak=$1 omega=$2 lo=$3 hi=$4 band_n=${5:-100000000} split_n=${6:-100000} t_max=${7:-10000} step=${8:-500}
py=$(bash "$(dirname "$0")/setup.sh" --python)
scene="$(dirname "$0")/../data/scenes/stationary_sL_0.toml"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$rotleak" simulate "$scene" --set "leak.omega=$omega" --set ensemble.sampling=mupo --set ensemble.sampling_eps=0.01 \
  --set "ensemble.sampling_p=[$lo, $hi]" --set "run.t_max=$t_max" --particles "$band_n" --out "$tmp/band" --no-progress >/dev/null
"$rotleak" simulate "$scene" --set "leak.omega=$omega" --set ensemble.sampling=mupo --set run.splitting=true \
  --set "run.t_max=$t_max" --particles "$split_n" --out "$tmp/split" --no-progress >/dev/null
"$py" - "$tmp/band/survival.csv" "$tmp/split/survival.csv" "$band_n" "$step" <<'PY'
import csv, sys
band_path, split_path, band_n, step = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
band = {float(r["t"]): r for r in csv.DictReader(open(band_path))}
split = {float(r["t"]): r for r in csv.DictReader(open(split_path))}
heavy = 100.0 / band_n  # one line of the uniform share
print("%8s %9s %11s %11s %11s %11s %9s" % ("t", "band_alive", "band_P", "band_err", "split_P", "split_err", "band/split"))
for t in sorted(band):
    if t % step or t == 0:
        continue
    b, s = band[t], split[t]
    bp, sp = float(b["P"]), float(s["P"])
    note = "" if bp < heavy else "  (the uniform share may be in band_P)"
    print("%8g %9s %11.3g %11.2g %11.3g %11.2g %9.3g%s" % (t, b["survivors"], bp, float(b["P_err"]), sp,
                                                         float(s["P_err"]), bp / sp if sp > 0 else float("nan"), note))
PY
