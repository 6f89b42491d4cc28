#!/bin/bash
# The bit-identity baseline of the engines, for before and after a change to the shared physics:
# every scene below on the 8-lane kernel (where the
# CPU has AVX-512), the 4-lane kernel and the scalar core; prints the sha256 of each survival.csv and
# fc.csv. Run it with the binary before a change and after it, and diff the two lists: they must be
# identical, and within one list the three engines of a scene must share their hashes.
# usage: scripts/bit_identity.sh BINARY OUTDIR   (OUTDIR is replaced; about 5 s on 2 cores)
set -euo pipefail
bin=$(realpath "$1")
out=$2
rm -rf "$out"
mkdir -p "$out"
cd "$(dirname "$0")/.."
engines="4 scalar"
if "$bin" --version | grep -q "8 lanes"; then engines="8 $engines"; fi
run() {
  local name=$1
  shift
  for e in $engines; do
    if [ "$e" = scalar ]; then
      "$bin" simulate "$@" --engine scalar --out "$out/$name.$e" --force --no-progress >/dev/null
    else
      ROTLEAK_SIMD_LANES=$e "$bin" simulate "$@" --out "$out/$name.$e" --force --no-progress >/dev/null
    fi
  done
}
S=data/scenes/stationary_sL_0.toml
FC='observe.collision_density={bins=200, windows=[[0,20000],[2000,20000]]}'
run qs data/scenes/quickstart.toml --particles 200000
run w23 $S --particles 100000 --set leak.omega=2/3
run w1e4 $S --particles 100000 --set leak.omega=1e-4
run mupoff $S --particles 100000 --set ensemble.sampling=mupo --set run.fast_forward=true --set "$FC"
run w23fc $S --particles 100000 --set leak.omega=2/3 \
  --set 'observe.collision_density={bins=100, windows=[[0,500],[100,3000]]}'
for s in 0 0.1 0.1022 0.1024 0.11 0.25; do run "st$s" "data/scenes/stationary_sL_$s.toml" --particles 100000; done
for z in "1 1" "2 2" "3 0.7"; do  # the other stadiums of tests/test_stadiums.cpp, moving leak with f_c
  set -- $z
  run "d$1r$2" $S --particles 50000 --set stadium.d=$1 --set stadium.r=$2 --set leak.omega=2/3 --set "$FC"
done
run split $S --particles 20000 --set ensemble.sampling=mupo --set run.splitting=true --set leak.omega=70/71
cd "$out" && sha256sum ./*/survival.csv ./*/fc.csv
