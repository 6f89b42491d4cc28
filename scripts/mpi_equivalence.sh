#!/usr/bin/env bash
# The same run as 1 process, as `mpirun -np 2` and as `mpirun -np 3 --oversubscribe` (one thread per
# rank, and 2 threads in the single process): survival.csv, fc.csv and escapes.csv must be
# byte-identical, and summary.json's fitted numbers equal. The scene has every tally: a rotating
# leak, importance-sampling weights (exact sums), f_c, escape records. Then a split run, the GPU engine under 2
# ranks (emulated where no device is), and a run on the Sinai table with two leaks (leaks.csv too). Then a scan of three omegas
# as 1 process and as `mpirun -np 2`: table.csv and every point's survival.csv byte-identical. Then
# an audit as 1 process and as `mpirun -np 3`: audit.json identical but for its timing fields.
# Usage: scripts/mpi_equivalence.sh ROTLEAK_BINARY [MPIRUN]      Exit 1 on the first difference.
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
bin=$(realpath "$1")
mpirun=${2:-mpirun}
scene=$(realpath "$(dirname "$0")/../data/scenes/stationary_sL_0.toml")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
# Open MPI refuses root unless told; a container has no network to speak of: shared memory and self
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader OMPI_MCA_rmaps_base_oversubscribe=1
args=("$scene" --particles 200000 --set leak.omega=2/3 --set ensemble.sampling=mupo --set run.t_max=4000
  --set 'observe.collision_density={bins=100}' --set observe.escapes=true --no-progress)
"$bin" simulate "${args[@]}" --threads 2 --out one >/dev/null
"$mpirun" -np 2 "$bin" simulate "${args[@]}" --threads 1 --out two >two.txt
# the header says the ranks and each one's threads (it once said "1 threads" and never the ranks)
grep -q " 2 ranks x 1 threads, " two.txt || { echo "2 ranks: the header does not say so: $(head -1 two.txt)"; exit 1; }
"$mpirun" -np 3 --oversubscribe "$bin" simulate "${args[@]}" --threads 1 --out three >/dev/null
for run in two three; do
  for f in survival.csv fc.csv escapes.csv; do
    cmp -s "one/$f" "$run/$f" || { echo "$run ranks: $f differs from the single process's"; exit 1; }
  done
  "$py" - "$run" <<'PY'
import json, sys
run = sys.argv[1]
a, b = json.load(open("one/summary.json")), json.load(open(run + "/summary.json"))
for k in ("kappa", "alpha", "tail_exponent", "tail", "particles", "collisions", "escaped", "sampling"):
    if a[k] != b[k]:
        sys.exit("%s: summary.json %s differs: %s vs %s" % (run, k, a[k], b[k]))
if b["execution"]["ranks"] != {"two": 2, "three": 3}[run]:
    sys.exit("%s: summary.json says ranks = %s" % (run, b["execution"]["ranks"]))
PY
  echo "$run ranks: survival.csv, fc.csv, escapes.csv and the fits identical to one process"
done

# a split run (lines of a block, members to each split time): the same files under 3 ranks
split=("$scene" --particles 60000 --set leak.omega=2/3 --set ensemble.sampling=mupo --set run.splitting=true
  --set run.t_max=4000 --set 'observe.collision_density={bins=100}' --no-progress)
"$bin" simulate "${split[@]}" --threads 2 --out split1 >/dev/null
"$mpirun" -np 3 --oversubscribe "$bin" simulate "${split[@]}" --threads 1 --out split3 >/dev/null
for f in survival.csv fc.csv; do
  cmp -s "split1/$f" "split3/$f" || { echo "split run under 3 ranks: $f differs from the single process's"; exit 1; }
done
"$py" - <<'PY'
import json, sys
a, b = json.load(open("split1/summary.json")), json.load(open("split3/summary.json"))
if a["splitting"] != b["splitting"] or a["alpha"] != b["alpha"]:
    sys.exit("split run under 3 ranks: summary.json splitting or alpha differs")
PY
echo "split run under 3 ranks: survival.csv, fc.csv and summary.json's splitting identical to one process"

# the GPU engine under 2 ranks, each rank taking its own device (emulated on the cores where none is:
# ROTLEAK_GPU_EMULATE, 1 unless set), against the single process's CPU engine: the same files
gpu=("$scene" --particles 30000 --set leak.omega=2/3 --set ensemble.sampling=mupo --set run.t_max=2000
  --set 'observe.collision_density={bins=100}' --set observe.escapes=true --no-progress)
"$bin" simulate "${gpu[@]}" --threads 2 --out gpu1 >/dev/null
ROTLEAK_GPU_EMULATE=${ROTLEAK_GPU_EMULATE-1} "$mpirun" -np 2 "$bin" simulate "${gpu[@]}" --threads 1 --engine gpu \
  --out gpu2 >/dev/null
for f in survival.csv fc.csv escapes.csv; do
  cmp -s "gpu1/$f" "gpu2/$f" || { echo "the GPU engine under 2 ranks: $f differs from the single process's"; exit 1; }
done
"$py" -c 'import json, sys; e = json.load(open("gpu2/summary.json"))["execution"]; sys.exit(e["engine"] != "gpu" or e["ranks"] != 2)' || { echo "the GPU engine under 2 ranks: summary.json does not say gpu, 2 ranks"; exit 1; }
echo "the GPU engine under 2 ranks: survival.csv, fc.csv and escapes.csv identical to one process on the CPU"

# any table with two leaks (one on the Sinai table's disc): the same files, leaks.csv too, under 3 ranks
table=("$(dirname "$scene")/tables/sinai.toml" --particles 60000 --set run.t_max=2000
  --set 'observe.collision_density={bins=50}' --no-progress)
"$bin" simulate "${table[@]}" --threads 2 --out table1 >/dev/null
"$mpirun" -np 3 --oversubscribe "$bin" simulate "${table[@]}" --threads 1 --out table3 >/dev/null
for f in survival.csv fc.csv leaks.csv; do
  cmp -s "table1/$f" "table3/$f" || { echo "a table under 3 ranks: $f differs from the single process's"; exit 1; }
done
echo "the Sinai table with two leaks under 3 ranks: survival.csv, fc.csv and leaks.csv identical to one process"

scan=("$scene" --over "leak.omega=2/3,1/7,ln(19)" --particles 60000 --set run.t_max=3000 --no-progress)
"$bin" scan "${scan[@]}" --threads 2 --out scan1 >/dev/null
"$mpirun" -np 2 "$bin" scan "${scan[@]}" --threads 1 --out scan2 >/dev/null
cmp -s scan1/table.csv scan2/table.csv || { echo "scan under 2 ranks: table.csv differs"; exit 1; }
for p in scan1/points/*/; do
  q=scan2/points/$(basename "$p")
  cmp -s "$p/survival.csv" "$q/survival.csv" || { echo "scan under 2 ranks: $(basename "$p") survival.csv differs"; exit 1; }
  "$py" -c 'import json, sys; sys.exit(json.load(open(sys.argv[1]))["execution"]["ranks"] != 2)' "$q/summary.json" || { echo "scan under 2 ranks: $(basename "$p") summary.json lacks ranks = 2"; exit 1; }
done
echo "scan under 2 ranks: table.csv and the points' survival.csv identical to one process"
# calibrate: a scan over seeds, then files from the points: the same bytes under 2 ranks
cal=("$scene" --seeds 3 --particles 3000 --set run.t_max=2000 --no-progress)
"$bin" calibrate "${cal[@]}" --threads 2 --out cal1 >/dev/null
"$mpirun" -np 2 "$bin" calibrate "${cal[@]}" --threads 1 --out cal2 >/dev/null
cmp -s cal1/calibration.csv cal2/calibration.csv || { echo "calibrate under 2 ranks: calibration.csv differs"; exit 1; }
cmp -s cal1/calibration.json cal2/calibration.json || { echo "calibrate under 2 ranks: calibration.json differs"; exit 1; }
echo "calibrate under 2 ranks: calibration.csv and calibration.json identical to one process"
# the audit: its ensembles split by blocks, its shadows by particle; audit.json the same but for
# the timing and layout fields (seconds, timing, threads, ranks)
audit=("$scene" --set leak.omega=2/3 --sample 48 --stats-particles 30000 --stratify-particles 30000
  --tiers float,double,dd,mpfr:256)
"$bin" audit "${audit[@]}" --threads 2 --out audit1 >/dev/null
"$mpirun" -np 3 --oversubscribe "$bin" audit "${audit[@]}" --threads 1 --out audit3 >/dev/null
"$py" - <<'PY'
import json, sys
a, b = json.load(open("audit1/audit.json")), json.load(open("audit3/audit.json"))
if b["execution"]["ranks"] != 3 or a["execution"]["ranks"] != 1:
    sys.exit("audit: audit.json says ranks = %s (one process: %s)" % (b["execution"]["ranks"], a["execution"]["ranks"]))
a.pop("execution"); b.pop("execution")
if a != b:
    diff = [k for k in a if a[k] != b.get(k)]
    sys.exit("audit under 3 ranks: audit.json differs from one process's in " + ", ".join(diff))
if len(a["verdicts"]) < 4 or a["sample"] != 48:
    sys.exit("audit: too little to compare (%d verdicts, sample %d)" % (len(a["verdicts"]), a["sample"]))
PY
echo "audit under 3 ranks: audit.json identical to one process (timings aside)"
# a certified sample: ranks share the particles in turn; its files identical to one process's
"$bin" certify "$scene" --sample 90 --t-cap 400 --threads 2 --out certify1 --no-progress >/dev/null
"$mpirun" -np 3 --oversubscribe "$bin" certify "$scene" --sample 90 --t-cap 400 --threads 1 --out certify3 \
  --no-progress >/dev/null
for f in escapes.csv bracket.csv; do
  cmp "certify1/$f" "certify3/$f" || { echo "certify under 3 ranks: $f differs from one process's"; exit 1; }
done
echo "certify --sample under 3 ranks: escapes.csv and bracket.csv identical to one process"
# any other command is refused under mpirun with one line (it would run K times over its files)
set +e
msg=$("$mpirun" -np 2 "$bin" omega 2/3 2>&1 >/dev/null)
set -e
grep -q "only \`rotleak simulate\`, \`scan\`, \`calibrate\`, \`audit\` and \`certify --sample\` run under MPI" <<<"$msg" || { echo "omega under 2 ranks not refused: $msg"; exit 1; }
echo "other commands under mpirun: refused with one line"
