#!/usr/bin/env bash
# scripts/check_layers.py must see an upward include in every kind of source file, the kernel's .ipp
# included: a tree whose src/sim/kernel.ipp includes run/pipeline.hpp fails, and names that file;
# the same tree without that include passes. Exit 1 when the checker misses it.
set -euo pipefail
checker=$(realpath "$(dirname "$0")/check_layers.py")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/src/sim" "$work/src/run"
printf '#pragma once\n' >"$work/src/run/pipeline.hpp"
printf '#include "sim/engine.hpp"\n' >"$work/src/sim/kernel.ipp"
printf '#pragma once\n' >"$work/src/sim/engine.hpp"
python3 "$checker" "$work" >/dev/null || { echo "a clean tree was refused"; exit 1; }
printf '#include "run/pipeline.hpp"\n' >>"$work/src/sim/kernel.ipp"
if out=$(python3 "$checker" "$work"); then
  echo "an upward include in an .ipp file passed: $out"
  exit 1
fi
echo "$out" | grep -q "src/sim/kernel.ipp:2" || { echo "the violation does not name the .ipp file: $out"; exit 1; }
echo "check_layers.py: an upward include in src/sim/kernel.ipp is refused and named"
