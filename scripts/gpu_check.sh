#!/usr/bin/env bash
# The GPU engine's checks on a machine with a CUDA device, from a build made on a machine without one
# (docs/performance.md, "The GPU engine"). Two steps:
#   scripts/gpu_check.sh pack [BUILD]   here: the build's rotleak, test_gpu and bench_gpu, and every library they load
#                                       that is not the C library's or the CUDA driver's, into .gpu-carry/ (git
#                                       ignores it)
#   scripts/gpu_check.sh run [OUT]      there, in a copy of this tree with .gpu-carry/ beside it: the device, the GPU
#                                       tests, byte comparisons of run directories (--engine gpu against the CPU's
#                                       engine: every file, summary.json less its execution and command, a split
#                                       run's tally.bin less the engine its inputs name; 100/101 split to P ~ 1e-20), and
#                                       bench_gpu (BENCH_PARTICLES a scene, default 10^8); its log and bench_gpu's
#                                       output under OUT (default gpu-check-out)
# The run step took about 3 minutes on an H200 with 16 cores before the split runs were added (up to 2 more).
set -euo pipefail
cd "$(dirname "$0")/.."
carry=.gpu-carry
case "${1:-}" in
  pack)
    build=${2:-build}
    rm -rf "$carry"
    mkdir -p "$carry/bin" "$carry/lib"
    grep -qx "/$carry/" .git/info/exclude 2>/dev/null || echo "/$carry/" >>.git/info/exclude
    for b in "$build/rotleak" "$build/tests/test_gpu" "$build/bench/bench_gpu"; do
      cp "$b" "$carry/bin/"
      strip "$carry/bin/$(basename "$b")"
      ldd "$b" | awk '/=> \// {print $3}' | while read -r lib; do
        case "$(basename "$lib")" in
          libc.so* | libm.so* | libpthread.so* | libdl.so* | librt.so* | ld-linux* | libcuda.so*) ;;
          *) cp -L "$lib" "$carry/lib/" ;;
        esac
      done
    done
    # the tests and the command find the source tree's data where the build was configured
    grep -m1 '^CMAKE_HOME_DIRECTORY' "$build/CMakeCache.txt" | cut -d= -f2 >"$carry/source_dir"
    du -sh "$carry" | sed 's/^/packed: /'
    ;;
  run)
    out=${2:-gpu-check-out}
    mkdir -p "$out"
    exec > >(tee "$out/gpu_check.log") 2>&1
    [[ -d $carry/bin ]] || { echo "gpu_check: no $carry/ here: run 'scripts/gpu_check.sh pack' where the build is"; exit 2; }
    export LD_LIBRARY_PATH="$PWD/$carry/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
    src=$(cat "$carry/source_dir")
    if [[ $src != "$PWD" && ! -e $src ]]; then mkdir -p "$(dirname "$src")" && ln -s "$PWD" "$src"; fi
    rl=$PWD/$carry/bin/rotleak
    nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv,noheader || true
    echo "cores: $(nproc)"
    echo "== test_gpu"
    "$carry/bin/test_gpu" >"$out/test_gpu.log" 2>&1 || true
    tail -n 30 "$out/test_gpu.log"
    echo "== byte comparisons: --engine gpu against --engine simd (${CPU_THREADS:-all} cores)"
    same() {  # name scene particles overrides...: one run on each engine, then every file compared
      local name=$1 scene=$2 n=$3
      shift 3
      local sets=()
      for s in "$@"; do sets+=(--set "$s"); done
      local a=$out/$name.cpu b=$out/$name.gpu
      rm -rf "$a" "$b"
      local e
      for e in simd gpu; do
        local dir=$a
        [[ $e == gpu ]] && dir=$b
        if ! "$rl" simulate "$scene" --particles "$n" "${sets[@]}" --engine $e --out "$dir" --no-progress \
          >"$out/$name.$e.log" 2>&1; then
          echo "$name: the $e run failed: $(tail -n 2 "$out/$name.$e.log")"
          return 0
        fi
        rm -f "$out/$name.$e.log"
      done
      local verdict=identical
      for f in "$a"/*; do
        local g=$b/$(basename "$f")
        if [[ $(basename "$f") == summary.json ]]; then
          python3 - "$f" "$g" <<'PY' || verdict="DIFFER (summary.json)"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
for d in (a, b):
    d.pop("execution", None), d.pop("command", None)
sys.exit(0 if a == b else 1)
PY
        elif [[ $(basename "$f") == tally.bin ]]; then  # a split run's: its inputs name the engine that ran it
          python3 - "$f" "$g" <<'PY' || verdict="DIFFER (tally.bin)"
import json, re, sys
def parts(path):  # "rotleak-tallies 4\n", the header's length, the header (JSON), the tallies, an FNV-1a checksum
    b = open(path, "rb").read()
    first = b.index(b"\n") + 1
    second = b.index(b"\n", first) + 1
    n = int(b[first:second])
    head = json.loads(b[second:second + n])
    head["inputs"] = re.sub(r"# engine = \w+\n", "", head["inputs"])
    return b[:first], head, b[second + n:-8]  # the checksum covers the header too
sys.exit(0 if parts(sys.argv[1]) == parts(sys.argv[2]) else 1)
PY
        elif ! cmp -s "$f" "$g"; then
          verdict="DIFFER ($(basename "$f"))"
        fi
      done
      python3 - "$b/summary.json" "$a/summary.json" "$name" "$verdict" "$b/survival.csv" <<'PY'
import csv, json, sys
g, c = (json.load(open(p))["execution"] for p in sys.argv[1:3])
last = list(csv.DictReader(open(sys.argv[5])))[-1]
print(f"{sys.argv[3]:<28} {sys.argv[4]:<12} gpu {g['collisions_per_second']:.3g} coll/s ({g['wall_seconds']:.2f} s), "
      f"cpu {c['collisions_per_second']:.3g} coll/s ({c['wall_seconds']:.2f} s, {c['threads']} threads); "
      f"P({last['t']}) = {float(last['P']):.3g}")
PY
      rm -rf "$a" "$b"
    }
    same quickstart_fc data/scenes/quickstart.toml 1000000
    same omega_2_3_mupo data/scenes/rotating.toml 1000000 leak.omega=2/3 ensemble.sampling=mupo
    same stationary_sL_0.25_flow data/scenes/stationary_sL_0.25.toml 1000000 ensemble.init=flow
    same stadium_two_leaks data/scenes/tables/stadium_two_leaks.toml 1000000
    same sinai data/scenes/tables/sinai.toml 1000000
    same mushroom data/scenes/tables/mushroom.toml 300000
    same omega_2_3_mupo_split data/scenes/rotating.toml 100000 leak.omega=2/3 ensemble.sampling=mupo \
      run.splitting=true run.t_max=4000 'observe.collision_density={bins=100}'
    same sinai_split data/scenes/tables/sinai.toml 100000 run.splitting=true run.t_max=2000
    # the deep split run of docs/guide/tails.md: 10^6 lines of 100/101 to P ~ 1e-20 at t = 10^4
    same split_100_101 data/scenes/stationary_sL_0.toml 1000000 ensemble.sampling=mupo run.splitting=true \
      leak.omega=100/101 run.t_max=10000
    echo "== bench_gpu ${BENCH_PARTICLES:=100000000} particles a scene, 3 rounds"
    "$carry/bin/bench_gpu" "$BENCH_PARTICLES" 3 "$((BENCH_PARTICLES / 10))" | tee "$out/bench_gpu.txt"
    echo "== 10^10 quick-start particles with f_c (the target: 15 s on an H100; given 45 s here)"
    if timeout 45 "$rl" simulate data/scenes/quickstart.toml --particles 10000000000 --set observe.escapes=false \
      --set 'observe.collision_density={ bins = 1000, windows = [[0, 20000], [2000, 20000]] }' --engine gpu \
      --out "$out/ten_to_ten" --no-progress >"$out/ten_to_ten.log" 2>&1; then
      python3 - "$out/ten_to_ten/summary.json" <<'PY'
import json, sys
e = json.load(open(sys.argv[1]))["execution"]
print(f"10^10 particles: {e['wall_seconds']:.1f} s, {e['collisions_per_second']:.3g} collisions/s")
PY
    else
      echo "10^10 particles: not done in 45 s ($(tail -n 1 "$out/ten_to_ten.log"))"
    fi
    rm -rf "$out/ten_to_ten" "$out/ten_to_ten.checkpoint"
    echo "docs/performance.md's GPU table: /usr/bin/python3 scripts/gpu_report.py $out/bench_gpu.txt (where the tree is)"
    ;;
  *)
    echo "usage: scripts/gpu_check.sh pack [BUILD] | run [OUT]" >&2
    exit 2
    ;;
esac
