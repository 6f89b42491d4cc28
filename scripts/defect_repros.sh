#!/usr/bin/env bash
# Re-runs the reproductions of the "nothing lost, nothing silently wrong" defects, each in an empty
# directory, and prints one outcome line per case: the exit status, the first line on stderr, and what
# was left behind. Part one: the 18 first found (run directories, bounds, messages). Part two: the
# newcomer's cases (a crash, a scan race, splitting without mupo, ...), then bad inputs of our own across
# every command and the Python API, concurrency (two scans, scan + fit, simulate --force + fit, simulate +
# plot) and interruption of every command. A human reads it; the tests (test_cli, test_scene, test_exact,
# test_fits, test_scan, test_reference, tests/python, kill_trials.sh) hold each outcome.
# Usage: scripts/defect_repros.sh ROTLEAK_BINARY
set -uo pipefail
python=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
bin=$(realpath "$1")
S=$(realpath "$(dirname "$0")/../data/scenes/quickstart.toml")
Z=$(realpath "$(dirname "$0")/../data/scenes/stationary_sL_0.toml")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
n=0
fresh() { n=$((n + 1)); rm -rf "$work/$n"; mkdir -p "$work/$n"; cd "$work/$n"; }
show() {  # label, rc, stderr file
  local first
  first=$(tr '\r' '\n' <"$3" | grep -v '^\s*$' | head -1 | cut -c1-150)
  printf '%2d %-34s exit %-3s %s\n' "$n" "$1" "$2" "$first"
}
left() { printf '   left here: %s\n' "$(find . -mindepth 1 -maxdepth 1 ! -name err.txt ! -name out.txt | sort | tr '\n' ' ')"; }
run() { "$bin" "$@" >out.txt 2>err.txt; echo $?; }

fresh  # 1
run simulate "$S" --out o --particles 2000 --no-progress >/dev/null
rc=$(run simulate "$S" --out o/ --particles 2000 --force --no-progress)
show "trailing slash + --force" "$rc" err.txt; ls o >/dev/null 2>&1 && echo "   o/ holds: $(ls o | tr '\n' ' ')"
fresh  # 2
"$bin" simulate "$S" --out same --threads 1 --no-progress >out1.txt 2>err1.txt & p1=$!
sleep .3
rc=$(run simulate "$S" --out same --threads 1 --set ensemble.seed=2 --no-progress)
wait $p1; rc1=$?
show "two runs, one directory (second)" "$rc" err.txt
echo "   first run exit $rc1; seed in same/summary.json: $("$python" -c "import json;print(json.load(open('same/summary.json'))['seed'])")"
fresh  # 3
rc=$(run omega "$("$python" -c "print('('*20000+'1'+')'*20000)")")
show "20000 nested parentheses" "$rc" err.txt
"$python" - <<'PY'  # too long for one command-line argument: a scene file
open("minus.toml", "w").write('[leak]\nomega = "' + "-" * 200000 + '1"\n')
PY
rc=$(run simulate minus.toml --out o)
show "2e5 unary minus (in a scene file)" "$rc" err.txt
rc=$(run omega "$("$python" -c "print('sqrt('*20000+'2'+')'*20000)")")
show "2e4 nested sqrt" "$rc" err.txt
fresh  # 4
"$bin" simulate "$S" --out o --particles 2000 --json --plot --no-progress >out.txt 2>err.txt
rc=$?
show "--json --plot" "$rc" err.txt
"$python" -c "import json;json.load(open('out.txt'))" && echo "   stdout is one JSON document"
fresh  # 5
mkdir -p .o.partial-999999 && touch .o.partial-999999/survival.csv.tmp-1
rc=$(run simulate "$S" --out o --particles 2000 --no-progress)
show "stale staging, then a run" "$rc" err.txt; left
fresh  # 6
rc=$(run simulate /tmp --out o)
show "a directory as the scene" "$rc" err.txt; left
fresh  # 7
rc=$(run simulate "$S" --out o --particles -5)
show "--particles -5" "$rc" err.txt; left
fresh  # 8
escaped() { "$python" -c "import json;d=json.load(open('out.txt'));print(d['escaped'], 'of', d['scene']['ensemble']['particles'])"; }
rc=$(run simulate "$S" --out o --particles 20000 --set 'leak.start=1e30+1/2' --json --no-progress)
show "leak.start=1e30+1/2" "$rc" err.txt
echo "   escaped: $(escaped)"
rc=$(run simulate "$S" --out o2 --particles 20000 --set 'leak.start=1/2' --json --no-progress)
echo "   start 1/2, escaped: $(escaped)"
rc=$(run simulate "$S" --out o3 --particles 2000 --set 'leak.omega=1e100000' --no-progress)
show "leak.omega=1e100000" "$rc" err.txt
fresh  # 9
rc=$( (ulimit -v 6000000; "$bin" simulate "$S" --out o --particles 100 --threads 10 --set run.t_max=10000 --set observe.survival_dt=0.0001 --set 'observe.collision_density={bins=1000, windows=[[0, 10000]]}' --no-progress >out.txt 2>err.txt; echo $?) )
show "out of memory (ulimit -v 6e6)" "$rc" err.txt; left
rc=$(run simulate "$S" --out o --particles 100 --threads 10000)
show "--threads 10000" "$rc" err.txt
fresh  # 10
rc=$(run simulate "$S" --out o --set 'stadium.d=pi-pi')
show "stadium.d=pi-pi" "$rc" err.txt
rc=$(run omega 'pi-pi')
show "omega pi-pi" "$rc" err.txt
fresh  # 11
rc=$(run omega 'ln(19)' --terms 20000)
show "omega ln(19) --terms 20000" "$rc" err.txt
echo "   $(grep -m1 -i 'certified\|terms' out.txt | cut -c1-120)"
fresh  # 12
"$bin" simulate "$S" --out o --particles 2000 --no-progress >/dev/null 2>&1
head -c 100 o/summary.json >o/cut && mv o/cut o/summary.json
rc=$(run plot o)
show "plot with an unreadable summary" "$rc" err.txt
echo "   stderr lines: $(wc -l <err.txt); tmp.png left: $(find o -name '*.tmp.png' | wc -l)"
fresh  # 13
rc=$(run simulate "$S" --out o --particles 1 --no-progress)
show "one particle" "$rc" err.txt
echo "   $(grep -i kappa out.txt | head -1)"
fresh  # 14
rc=$(run simulate "$S" --out o --set 'observe.collision_density={bins=10, windows=[[0, 30000]]}')
show "window beyond t_max" "$rc" err.txt
rc=$(run simulate "$S" --out o --set ensemble.creation_window=1e300)
show "creation_window 1e300" "$rc" err.txt
rc=$(run simulate "$S" --out o --set stadium.r=1e-300)
show "stadium.r=1e-300" "$rc" err.txt
fresh  # 15
rc=$(run simulate "$S" --out o --set leak.width=1e-9 --set leak.start=2 --set 'observe.survival_dt=-1e-9')
show "survival_dt=-1e-9 (value as written)" "$rc" err.txt
rc=$(run simulate "$S" --out o --set run.t_max=-1000.0)
show "t_max=-1000.0 (value as written)" "$rc" err.txt
rc=$(run omega 2/3 --terms 1e20)
show "--terms 1e20" "$rc" err.txt
rc=$(run simulate "$S" --out o --set 'leak.width=½')
show "a lone non-ASCII character" "$rc" err.txt
rc=$(run simulate "$S" --out o --set "leak.omega=$("$python" -c "print('1e100000+ln(2)'+'+1'*50000)")")
show "a 100 KB value" "$rc" err.txt
echo "   longest stderr line: $(awk '{ if (length > m) m = length } END { print m }' err.txt) characters"
fresh  # 16
rc=$(run simulate "$S" --out o --particles 10000000000000 --set observe.escapes=true)
show "1e13 particles with escape records" "$rc" err.txt
fresh  # 17
rc=$(run simulate "$S" --out np/a/b/c --set leak.width=2)
show "input error after --out np/a/b/c" "$rc" err.txt; left
fresh  # 18
"$bin" simulate "$S" --out o --particles 2000 --no-progress >/dev/null 2>&1
"$bin" certify "$S" --particle 3 >/dev/null 2>&1
rc=$?
show "Core_Diagnostics after certify" "$rc" /dev/null; left

echo
echo "== part two: the newcomer's cases"
py() { PYTHONPATH="$(dirname "$bin")/python" "$python" "$@"; }
fresh  # 19
rc=$(run simulate "$Z" --particles 1000 --set run.splitting=true --set run.t_max=100 --set 'fit.kappa_window=[0,50]' --out X)
show "split, t_max 100 (was rc 139)" "$rc" err.txt; left
rc=$(run simulate "$Z" --particles 1000 --set run.splitting=true --set ensemble.sampling=mupo --set run.t_max=1e8 --out X)
show "split mupo, t_max 1e8 (was rc 139)" "$rc" err.txt
rc=$(run simulate "$Z" --particles 1000 --set run.splitting=true --set ensemble.sampling=mupo --set leak.width=1e-6 --set run.t_max=1e6 --out X)
show "split mupo, width 1e-6 (was rc 139)" "$rc" err.txt
rc=$(run simulate "$S" --set run.t_max=1 --out Y)
show "quickstart t_max=1 (was rc 139)" "$rc" err.txt; left
rc=$(run simulate "$Z" --particles 10000 --set run.splitting=true --out Z)
show "split on uniform draws (was 2e-38)" "$rc" err.txt; left
fresh  # 20
"$bin" scan "$S" --over leak.omega=0,1 --particles 3000000 --out D --no-progress >/dev/null 2>first.txt & p1=$!
sleep 1
rc=$(run scan "$S" --over leak.omega=2/3 --particles 1000 --out D --no-progress)
show "a second scan into D" "$rc" err.txt
rc=$(run fit D)
show "fit D while the scan runs" "$rc" err.txt
wait $p1; echo "   first scan exit $?; table rows: $(($(wc -l <D/table.csv) - 1))"
rc=$(run scan "$S" --over leak.omega=0,1 --particles 1000 --out D --no-progress)
show "scan D again, other particles" "$rc" err.txt
"$bin" simulate "$S" --particles 2000000 --out R --no-progress >/dev/null 2>&1
"$bin" simulate "$S" --particles 3000000 --out R --force --no-progress >/dev/null 2>&1 & p1=$!
sleep 1
rc=$(run fit R --set fit.alpha_factor=5)
show "fit during simulate --force" "$rc" err.txt
rc=$(run plot R)
show "plot during simulate --force" "$rc" err.txt
wait $p1
"$bin" simulate "$S" --particles 3000000 --out P --no-progress >/dev/null 2>&1 & p1=$!
sleep 0.5
rc=$(run plot P)
show "plot a run still running" "$rc" err.txt
wait $p1
fresh  # 21
rc=$(run simulate "$S" --particles 300000 --set run.splitting=true --set ensemble.sampling=mupo --set run.t_max=5000 --set run.split_cap=1e6 --set 'observe.collision_density={bins=10}' --out o --no-progress)
show "split_cap=1e6 through --set" "$rc" err.txt
rc=$(run simulate "$Z" --set run.splitting=true --set ensemble.sampling=mupo --set run.split_every=1e400 --out o2)
show "split_every=1e400" "$rc" err.txt
rc=$(run simulate "$Z" --set run.splitting=true --set ensemble.sampling=mupo --set run.split_delta=1e-400 --out o2)
show "split_delta=1e-400 (was silently 0)" "$rc" err.txt
rc=$(run simulate --set leak.omega=2/3 "$S" --particles 1000 --out o3 --no-progress)
show "--set before the scene" "$rc" err.txt
echo "keep" >notes.md
rc=$(run simulate "$S" --out notes.md)
show "--out a file" "$rc" err.txt
rc=$(run simulate "$S" --out notes.md --force)
show "--out a file --force" "$rc" err.txt
rc=$(run audit "$Z" --set run.splitting=true --set ensemble.sampling=mupo)
show "audit a split scene" "$rc" err.txt
rc=$(run simulate "$S" --set run.t_max=1e12 --out o4)
show "t_max=1e12" "$rc" err.txt
rc=$(run verify --tier mpfr:1024)
show "verify --tier mpfr:1024" "$rc" err.txt; echo "   $(grep -m1 '^mpfr' out.txt)"
rc=$(run shadow "$S" --particle 3 --tiers mpfr:65536 --collisions 5)
show "shadow --tiers mpfr:65536" "$rc" err.txt

echo
echo "== part two: bad inputs of our own"
fresh  # 22
for args in "--set ensemble.seed=-1" "--set ensemble.seed=1e30" "--set fit.tail_floor=0" \
  "--set fit.kappa_window=[0,1e300]" "--set observe.collision_density={bins=1e7}" "--set observe.survival_dt=1e-300" \
  "--set ensemble.sampling=mupo --set ensemble.sampling_p=[0,1]" "--set ensemble.particles=1e19" \
  "--set leak.omega=\"2/3\"" "--set leak.start=nan" "--set run.tier=mpfr:256" "--ids 5:3" "--resume nowhere" \
  "--engine gpu" "--threads 1.5" "--set observe.escapes=yes" "--set leak.omega=1/0" "--set stadium.d=1e-400"; do
  # shellcheck disable=SC2086  # the case's words
  rc=$(run simulate "$S" --out o $args)
  show "simulate $args" "$rc" err.txt
done
left
fresh  # 23
for args in "--over leak.omega=" "--over leak.omega=logspace(0,1,3)" "--over leak.omega=1/0" "--over omega=1" \
  "--over leak.omega=linspace(0,1,100001)" "--over leak.omega=1 --over leak.omega=2"; do
  # shellcheck disable=SC2086
  rc=$(run scan "$S" --out D $args)
  show "scan $args" "$rc" err.txt
done
left
fresh  # 24
touch afile
for args in "fit nowhere" "fit afile" "fit . --set leak.omega=1" "plot ." "plot nowhere" "merge out nowhere" \
  "omega ''" "omega 1/0" "omega 2/3 --digits 0" "covering --omega 2/3 --resolution 0" "shadow $S --particle -1" \
  "shadow $S --particle 1e30" "shadow $S --particle 1 --tiers quad" "lyapunov $S --particles 0" \
  "certify $S --particle 3 --bits 1" "regimes $S --out r --steps 100" "verify --tier mpfr:10" \
  "audit $S --sample 2"; do
  # shellcheck disable=SC2086
  rc=$(eval run $args)
  show "$args" "$rc" err.txt
done
left
fresh  # 25
cat >bad.py <<PY
import sys, rotleak
cases = [dict(overrides={"leak.omega": 2 / 3}), dict(particles=True), dict(threads=2.7), dict(threads="two"),
         dict(progress=5), dict(overrides=["run.t_max=5"]),
         dict(overrides={"run.splitting": True, "ensemble.sampling": "mupo", "run.t_max": 100}),
         dict(overrides={"run.splitting": True}), dict(overrides={"stadium.r": 1.0}), dict(overrides={"nonsense": 1})]
for kw in cases:
    try:
        rotleak.simulate("$S", **kw)
        print("python %-70s accepted" % kw)
    except ValueError as e:
        print("python %-70s ValueError: %s" % (kw, str(e)[:90]))
for name, text in (("cut survival.csv", None),):
    pass
PY
py bad.py
"$bin" simulate "$S" --particles 2000 --out o --no-progress >/dev/null 2>&1
head -c 20000 o/survival.csv >o/cut && mv o/cut o/survival.csv
py -c "import rotleak
try: rotleak.read_run('o').survival
except rotleak.RotleakError as e: print('python read_run of a cut survival.csv: RotleakError:', e)"
rc=$(run fit o)
show "fit of the same" "$rc" err.txt

echo
echo "== part two: interruption of every command: SIGINT, SIGTERM and SIGKILL 0.5 s in, then the same command again"
fresh  # 26
set -m  # background commands in their own process groups: a non-interactive shell would start them ignoring SIGINT
interrupt() {  # label, then the command's words with OUT where its output directory goes
  local label=$1 sig rc p words
  shift
  for sig in INT TERM KILL; do
    words=("${@//OUT/$label-$sig}")
    "$bin" "${words[@]}" >out.txt 2>err.txt &
    p=$!
    sleep 0.5
    kill -$sig $p 2>/dev/null
    wait $p 2>/dev/null
    rc=$?
    show "$label: SIG$sig" "$rc" err.txt
    rc=$(run "${words[@]}")
    printf '   again: exit %s %s; left: %s\n' "$rc" "$(tr '\r' '\n' <err.txt | grep -v '^\s*$' | head -1 | cut -c1-90)" \
      "$(find . -mindepth 1 -maxdepth 1 -name "*$label-$sig*" | sort | tr '\n' ' ')"
  done
}
interrupt simulate simulate "$S" --particles 20000000 --out OUT --no-progress
interrupt scan scan "$S" --over leak.omega=0,1 --particles 10000000 --out OUT --no-progress
interrupt regimes regimes "$S" --out OUT --particles 3000000 --coarse 1e-4,1e-3,1e-2 --steps 1
interrupt audit audit "$S" --out OUT --stats-particles 3e6
interrupt shadow shadow "$S" --particle 3 --tiers mpfr:4096 --collisions 3000 --out OUT
interrupt lyapunov lyapunov "$S" --particles 4000
interrupt certify certify "$S" --particle 3
interrupt verify verify --tier all --engine all
interrupt covering covering --omega 'ln(19)' --delta 1e-14 --out OUT
interrupt omega omega 'ln(19)' --terms 20000
"$bin" simulate "$S" --particles 2000 --out fitme --no-progress >/dev/null 2>&1
interrupt fit fit fitme
interrupt plot plot fitme
set +m
