#!/usr/bin/env bash
# Re-runs the 18 reproductions of the "nothing lost, nothing silently wrong" issue (run directories,
# bounds, messages), each in an empty directory, and prints one outcome line per defect: the exit
# status, the first line on stderr, and what was left behind. A human reads it; the tests
# (test_cli, test_scene, test_exact, test_fits, kill_trials.sh) hold each outcome.
# Usage: scripts/defect_repros.sh ROTLEAK_BINARY
set -uo pipefail
bin=$(realpath "$1")
S=$(realpath "$(dirname "$0")/../data/scenes/quickstart.toml")
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
echo "   first run exit $rc1; seed in same/summary.json: $(python3 -c "import json;print(json.load(open('same/summary.json'))['seed'])")"
fresh  # 3
rc=$(run omega "$(python3 -c "print('('*20000+'1'+')'*20000)")")
show "20000 nested parentheses" "$rc" err.txt
python3 - <<'PY'  # too long for one command-line argument: a scene file
open("minus.toml", "w").write('[leak]\nomega = "' + "-" * 200000 + '1"\n')
PY
rc=$(run simulate minus.toml --out o)
show "2e5 unary minus (in a scene file)" "$rc" err.txt
rc=$(run omega "$(python3 -c "print('sqrt('*20000+'2'+')'*20000)")")
show "2e4 nested sqrt" "$rc" err.txt
fresh  # 4
"$bin" simulate "$S" --out o --particles 2000 --json --plot --no-progress >out.txt 2>err.txt
rc=$?
show "--json --plot" "$rc" err.txt
python3 -c "import json;json.load(open('out.txt'))" && echo "   stdout is one JSON document"
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
escaped() { python3 -c "import json;d=json.load(open('out.txt'));print(d['escaped'], 'of', d['scene']['ensemble']['particles'])"; }
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
rc=$(run simulate "$S" --out o --set "leak.omega=$(python3 -c "print('1e100000+ln(2)'+'+1'*50000)")")
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
