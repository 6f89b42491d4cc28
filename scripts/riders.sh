#!/usr/bin/env bash
# Where the long-lived bouncing-ball lines of a moving leak start (docs/model.md, "Riding orbits"): unsplit runs
# whose mupo draws (99% of them: ensemble.sampling_eps = 0.01) hold one narrow band of |p| each, log-spaced over
# [LO, HI]; for each band the share of its lines alive at T1 and T2. The riding |p| of the scene
# (riding_bands, printed by simulate with ensemble.sampling_ride > 0) is where the shares peak.
# Usage: scripts/riders.sh ROTLEAK OMEGA [LO HI BANDS PARTICLES T1 T2]   (defaults 5e-4 2e-3 12 3000000 3000 4000)
set -euo pipefail
rotleak=$1 omega=$2 lo=${3:-5e-4} hi=${4:-2e-3} bands=${5:-12} n=${6:-3000000} t1=${7:-3000} t2=${8:-4000}
py=$(bash "$(dirname "$0")/setup.sh" --python)
scene="$(dirname "$0")/../data/scenes/stationary_sL_0.toml"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
edges=$("$py" -c "import math,sys; lo,hi,k=float(sys.argv[1]),float(sys.argv[2]),int(sys.argv[3]); print(' '.join('%.6g'%(lo*(hi/lo)**(i/k)) for i in range(k+1)))" "$lo" "$hi" "$bands")
read -r -a e <<<"$edges"
printf '%-10s %-10s %10s %10s %12s\n' p_lo p_hi "alive($t1)" "alive($t2)" "share($t1)"
for ((i = 0; i < bands; i++)); do
  "$rotleak" simulate "$scene" --set "leak.omega=$omega" --set ensemble.sampling=mupo --set ensemble.sampling_eps=0.01 \
    --set "ensemble.sampling_p=[${e[i]}, ${e[i + 1]}]" --set "run.t_max=$t2" --particles "$n" --out "$tmp/b$i" >/dev/null
  "$py" - "$tmp/b$i/survival.csv" "${e[i]}" "${e[i + 1]}" "$t1" "$t2" "$n" <<'PY'
import csv, sys
path, lo, hi, t1, t2, n = sys.argv[1:]
alive = {int(float(r["t"])): int(r["survivors"]) for r in csv.DictReader(open(path))}
a1, a2 = alive[int(float(t1))], alive[int(float(t2))]
print("%-10s %-10s %10d %10d %12.3g" % (lo, hi, a1, a2, a1 / (0.99 * int(n))))
PY
done
