#!/usr/bin/env bash
# MPI scaling on this machine: the same run as one process (all threads), as mpirun -np 1, -np 2
# (one thread per rank) and -np 4 --oversubscribe (one thread per rank), and -np 1 --bind-to none
# (Open MPI's default binding puts a lone rank's threads on one core); wall seconds of each and
# whether survival.csv is the same bytes. Then `rotleak audit` as one process, -np 2 and -np 4
# (audit.json the same but for its timing fields). Reports, never fails.
# Usage: bench/bench_mpi.sh [ROTLEAK (build/rotleak)] [PARTICLES (2000000)] [OMEGA (2/3)] [AUDIT_STATS (1000000)]
set -euo pipefail
bin=$(realpath "${1:-build/rotleak}")
particles=${2:-2000000}
omega=${3:-2/3}
audit_stats=${4:-1000000}
scene=$(realpath "$(dirname "$0")/../data/scenes/stationary_sL_0.toml")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader
args=("$scene" --particles "$particles" --set leak.omega="$omega" --no-progress)
run() {  # name, command...
  local name=$1
  shift
  local t0 t1
  t0=$(date +%s.%N)
  "$@" >/dev/null
  t1=$(date +%s.%N)
  awk -v n="$name" -v a="$t0" -v b="$t1" 'BEGIN { printf "| %s | %.2f |", n, b - a }'
  if cmp -s one/survival.csv "$name/survival.csv"; then echo " same |"; else echo " DIFFERENT |"; fi
}
echo "bench_mpi: $particles particles, omega = $omega, $(nproc) cores"
echo
echo "| run | wall s | survival.csv vs one process |"
echo "|---|---|---|"
run one "$bin" simulate "${args[@]}" --out one
run np1 mpirun -np 1 "$bin" simulate "${args[@]}" --out np1
# Open MPI binds a rank to one core by default (np <= 2): its threads then share that core
run np1-unbound mpirun -np 1 --bind-to none "$bin" simulate "${args[@]}" --out np1-unbound
run np2 mpirun -np 2 "$bin" simulate "${args[@]}" --threads 1 --out np2
run np4 mpirun -np 4 --oversubscribe "$bin" simulate "${args[@]}" --threads 1 --out np4

# the audit: its ensembles split by blocks, its shadows by particle (rank 0 reports)
audit=("$scene" --set leak.omega="$omega" --stats-particles "$audit_stats")
run_audit() {  # name, command...
  local name=$1
  shift
  local t0 t1
  t0=$(date +%s.%N)
  "$@" --out "$name" >/dev/null
  t1=$(date +%s.%N)
  awk -v n="$name" -v a="$t0" -v b="$t1" 'BEGIN { printf "| %s | %.2f |", n, b - a }'
  python3 - "$name" <<'PY'
import json, sys
a, b = json.load(open("audit-one/audit.json")), json.load(open(sys.argv[1] + "/audit.json"))
for d in (a, b):
    d.pop("execution")
print(" same |" if a == b else " DIFFERENT |")
PY
}
echo
echo "audit (default sample and tiers, $audit_stats particles a statistics ensemble):"
echo
echo "| run | wall s | audit.json vs one process (timings aside) |"
echo "|---|---|---|"
run_audit audit-one "$bin" audit "${audit[@]}"
run_audit audit-np2 mpirun -np 2 --bind-to none "$bin" audit "${audit[@]}" --threads 1
run_audit audit-np4 mpirun -np 4 --oversubscribe --bind-to none "$bin" audit "${audit[@]}" --threads 1
