#!/usr/bin/env bash
# Redraws the guides' and the README's pictures (docs/img) from a build, each by the command its page names, so
# that every figure shown is this build's: the quick-start run (survival, f_c), the coverings of five omegas, particle
# 1's shadow, a 100/101 split run to t = 10^4, the notebook's figure, bench_sampling's and bench_tiers' trades and
# bench_splitting's work-normalised precision. The study's panels (docs/study/img) come from
# scripts/reproduce_study.sh --quick --docs. Work goes to a temporary directory, removed after.
# Usage: scripts/doc_figures.sh [BUILD_DIR]   (default build; a few minutes on the 2-core machine)
set -euo pipefail
src=$(realpath "$(dirname "$0")/..")
build=$(realpath "${1:-$src/build}")
B=$build/rotleak
img=$src/docs/img
[ -x "$B" ] && [ -d "$build/python/rotleak" ] ||
  { echo "doc_figures: $build has no rotleak binary and Python package: run bash scripts/build.sh first" >&2; exit 2; }
w=$(mktemp -d)
trap 'rm -rf "$w"' EXIT
cd "$src"
export PYTHONPATH=$build/python${PYTHONPATH:+:$PYTHONPATH}
keep() { cp "$1" "$img/$2"; echo "docs/img/$2: $3"; }
caption() { grep -F "drew $1" "$2" | sed 's/^[^:]*: //'; }

"$B" simulate data/scenes/quickstart.toml --out "$w/quickstart" --plot --no-progress >"$w/q.log"
keep "$w/quickstart/survival.png" quickstart_survival.png "$(caption "$w/quickstart/survival.png" "$w/q.log")"
keep "$w/quickstart/fc.png" quickstart_fc.png "$(caption "$w/quickstart/fc.png" "$w/q.log")"

"$B" covering --omega 1 2/3 22/23 70/71 100/101 --delta 1e-7 --lambda 0.01 --out "$w/covering" >"$w/c.log"
keep "$w/covering/f_L.png" covering_fL.png "$(caption "$w/covering/f_L.png" "$w/c.log")"

"$B" shadow data/scenes/quickstart.toml --particle 1 --collisions 400 --out "$w/shadow1" >"$w/s.log"
keep "$w/shadow1/shadow.png" shadow_particle1.png "$(caption "$w/shadow1/shadow.png" "$w/s.log")"

"$B" simulate data/scenes/stationary_sL_0.toml --particles 1000000 --set ensemble.sampling=mupo \
  --set run.splitting=true --set leak.omega=100/101 --set run.t_max=10000 --out "$w/split" --plot --no-progress \
  >"$w/p.log"
keep "$w/split/survival.png" split_100_101.png "$(caption "$w/split/survival.png" "$w/p.log")"

bash scripts/notebook.sh "$build" "$w/notebook" >/dev/null
keep "$w/notebook/notebook_tour.png" notebook_tour.png "the notebook's scan: kappa, alpha and regime against omega"

"$build/bench/bench_sampling" "$w/sampling.csv" >/dev/null
/usr/bin/python3 -m rotleak.plot.sampling "$w/sampling.csv" "$w/sampling.png" >/dev/null
keep "$w/sampling.png" sampling.png "bench_sampling: P(t) uniform and mupo, s_L = 0"

"$build/bench/bench_tiers" "$w/tiers.csv" >/dev/null
/usr/bin/python3 -m rotleak.plot.tiers "$w/tiers.csv" "$w/tiers.png" >/dev/null
keep "$w/tiers.png" tiers.png "bench_tiers: cost per collision against the trust horizon"

/usr/bin/python3 bench/bench_splitting.py "$B" 10000000 1000000 100/101 "$w/fom" >/dev/null
keep "$w/fom/splitting_fom.png" splitting_fom.png "bench_splitting: work-normalised precision, 100/101"
