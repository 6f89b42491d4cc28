#!/usr/bin/env bash
# What ptxas makes of the GPU engine's kernels (docs/performance.md, "The GPU engine"): gpu_engine.cu compiled again
# with the build's own nvcc command (ninja's) plus -Xptxas -v, into a temporary object; one line a kernel: the model,
# f_c or not, the blocks a multiprocessor its registers are capped for (1: uncapped), registers a thread, stack frame
# and spill bytes; then bench_gpu's plain loop the same way. Needs no device.
# Usage: scripts/gpu_registers.sh [BUILD (default build)]
set -euo pipefail
build=${1:-build}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ptxas() {  # OBJECT: its build command again, the object elsewhere, no dependency file or cache, ptxas's report
  local cmd
  cmd=$(ninja -C "$build" -t commands "$1" 2>/dev/null | tail -n 1)
  [[ $cmd == *nvcc* ]] || { echo "gpu_registers: $build has no CUDA build of $1 (no nvcc found)" >&2; exit 2; }
  cmd=$(sed -E "s# -o [^ ]+# -o $work/k.o#; s#-MD -MT [^ ]+ -MF [^ ]+##; s#[^ ]*ccache ##" <<<"$cmd")
  (cd "$build" && eval "$cmd -Xptxas -v") 2>&1
}
ptxas src/CMakeFiles/rotleak_core.dir/sim/gpu/gpu_engine.cu.o | awk '
  /Compiling entry function/ {
    match($0, /run_batchINS_[0-9]+[A-Za-z]+IdEELb[01]ELi[0-9]+E/)
    k = substr($0, RSTART, RLENGTH)
    model = (k ~ /TableModel/) ? "any table" : "the stadium"
    fc = (k ~ /Lb1E/) ? "f_c" : "-"
    match(k, /ELi[0-9]+E/)
    cap = substr(k, RSTART + 3, RLENGTH - 4)
  }
  /bytes stack frame/ { stack = $1; stores = $5; loads = $9 }
  /Used [0-9]+ registers/ {
    match($0, /Used [0-9]+ registers/)
    regs = substr($0, RSTART + 5, RLENGTH - 15)
    printf "%-12s %-4s blocks %-2s registers %-4s stack %-4s spill stores %-5s loads %s\n", model, fc, cap, regs, stack, stores, loads
  }'
# bench_gpu's plain one-thread-a-particle loop, for comparison
ptxas bench/CMakeFiles/bench_gpu.dir/bench_gpu.cu.o | awk '
  /Compiling entry function.*plain_batch/ { plain = 1; next }
  /Compiling entry function/ { plain = 0 }
  plain && /bytes stack frame/ { stack = $1; stores = $5; loads = $9 }
  plain && /Used [0-9]+ registers/ {
    match($0, /Used [0-9]+ registers/)
    printf "%-12s %-4s blocks %-2s registers %-4s stack %-4s spill stores %-5s loads %s\n", "plain loop", "-", "1", substr($0, RSTART + 5, RLENGTH - 15), stack, stores, loads
  }'
