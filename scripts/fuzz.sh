#!/usr/bin/env bash
# Builds the libFuzzer targets of the readers (build-fuzz/: clang, -DROTLEAK_FUZZ=ON, ASan + UBSan) and
# runs each: first every kept regression input (tests/fuzz/regressions/<target>/: crashes found and
# fixed), then SECONDS of fuzzing from the seed corpus (tests/fuzz/corpus/<target>/) in a scratch copy,
# so the committed corpus does not grow. Prints per target the executions and the coverage libFuzzer
# reports; exits non-zero on a crash, a hang, a leak or an out-of-memory, with the input kept in
# build-fuzz/findings/<target>/.
# Usage: [FUZZ_TARGETS="fuzz_scene ..."] scripts/fuzz.sh [SECONDS_EACH]   (default 10, the suite's short
# run; 600 for the long run)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
# FUZZ_TARGETS: a subset, space-separated (two shells can share the machine's cores)
read -r -a targets <<<"${FUZZ_TARGETS:-fuzz_scene fuzz_tally fuzz_survival_csv fuzz_run_documents fuzz_orbit_code fuzz_orbit_checkpoint fuzz_certify_checkpoint}"
bash scripts/setup.sh
bash scripts/ninja_tree.sh build-fuzz
cmake -G Ninja -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DROTLEAK_FUZZ=ON \
  -DROTLEAK_TESTS=OFF -DROTLEAK_BENCH=OFF -DROTLEAK_PYTHON_MODULE=OFF -DROTLEAK_MPI=OFF -DROTLEAK_GPU=OFF -DROTLEAK_WARNINGS=OFF >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
for t in "${targets[@]}"; do
  bin=build-fuzz/tests/fuzz/$t
  findings=build-fuzz/findings/$t
  mkdir -p "$findings" "$work/$t"
  if compgen -G "tests/fuzz/regressions/$t/*" >/dev/null; then
    "$bin" -runs=0 tests/fuzz/regressions/$t/* >"$work/$t.regressions.log" 2>&1 ||
      { echo "fuzz: $t: a kept regression input fails again"; tail -30 "$work/$t.regressions.log"; status=1; continue; }
  fi
  start=$(date +%s)
  if ! "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
    -artifact_prefix="$findings/" "$work/$t" "tests/fuzz/corpus/$t" >"$work/$t.log" 2>&1; then
    echo "fuzz: $t FAILED (input in $findings/)"
    grep -E "ERROR|SUMMARY|==[0-9]+==|Test unit written" "$work/$t.log" | head -20
    status=1
  fi
  runs=$(grep -oE 'stat::number_of_executed_units: *[0-9]+' "$work/$t.log" | grep -oE '[0-9]+$' || echo "?")
  cov=$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$work/$t.log" | tail -1 || echo "cov: ?")
  corpus=$(find "$work/$t" -type f | wc -l)
  printf 'fuzz: %-20s %ss  %s executions  %s  corpus %s new inputs\n' "$t" "$(($(date +%s) - start))" "$runs" "$cov" \
    "$corpus"
done
exit $status
