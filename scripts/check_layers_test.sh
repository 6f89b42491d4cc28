#!/usr/bin/env bash
# scripts/check_layers.py must see every kind of upward dependency it exists for, each in a small tree
# of its own that is clean before the one bad line is added:
#  1. an include from src/sim up to app/run in the kernel's .ipp (named with its line, and as crossing folders);
#  2. an include inside src/sim from a lower folder up to a higher one (sim/model -> sim/engine);
#  3. a file of src/sim outside its folders;
#  4. an include from src/io up to analysis/output (the writers of analysis results: a folder above);
#  5. a relative import in the Python package from rotleak.readers up to rotleak.plot.
# Exit 1 when the checker misses one.
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
checker=$(realpath "$(dirname "$0")/check_layers.py")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/src/sim/kernel" "$work/src/sim/model" "$work/src/sim/engine" "$work/app/run" "$work/src/io" \
  "$work/analysis/output" "$work/python/rotleak/plot"
printf '#pragma once\n' >"$work/app/run/pipeline.hpp"
printf '#pragma once\n' >"$work/src/io/files.hpp"
printf '#include "io/files.hpp"\n' >"$work/analysis/output/run_output.hpp"
printf '#include "sim/model/scene.hpp"\n' >"$work/src/sim/kernel/kernel.ipp"
printf '#pragma once\n' >"$work/src/sim/model/scene.hpp"
printf '#include "sim/model/scene.hpp"\n' >"$work/src/sim/engine/engine.hpp"
printf 'import json\n' >"$work/python/rotleak/readers.py"
printf 'from .readers import json\n' >"$work/python/rotleak/__init__.py"
printf 'from ..readers import json\nfrom . import run\n' >"$work/python/rotleak/plot/__init__.py"
"$py" "$checker" "$work" >/dev/null || { echo "a clean tree was refused: $("$py" "$checker" "$work")"; exit 1; }
refused() {  # refused FILE LINE TEXT WHAT [WORDS]: appending TEXT to FILE fails the check, naming FILE:LINE (and WORDS)
  local file=$1 line=$2 text=$3 what=$4 words=${5:-} out
  cp "$work/$file" "$work/$file.bak"
  printf '%s\n' "$text" >>"$work/$file"
  if out=$("$py" "$checker" "$work"); then
    echo "$what passed: $out"
    exit 1
  fi
  echo "$out" | grep -q "$file:$line" || { echo "$what: the violation does not name $file:$line: $out"; exit 1; }
  echo "$out" | grep -qF "$words" || { echo "$what: the violation does not say '$words': $out"; exit 1; }
  mv "$work/$file.bak" "$work/$file"
}
refused src/sim/kernel/kernel.ipp 2 '#include "run/pipeline.hpp"' "an upward include in an .ipp file" "from src/ up to app/"
refused src/io/files.hpp 2 '#include "analysis/output/run_output.hpp"' "an include from src/io up to analysis/output" \
  "from src/ up to analysis/"
refused src/sim/model/scene.hpp 2 '#include "sim/engine/engine.hpp"' "an include from sim/model up to sim/engine"
printf '#pragma once\n' >"$work/src/sim/loose.hpp"
refused src/sim/loose.hpp 2 '#include "sim/model/scene.hpp"' "a file of src/sim outside its folders"
rm "$work/src/sim/loose.hpp"
refused python/rotleak/readers.py 2 'from .plot import run' "an import from rotleak.readers up to rotleak.plot"
"$py" "$checker" "$work" >/dev/null || { echo "the tree is not clean again after the cases"; exit 1; }
echo "check_layers.py: upward includes (.ipp, across src/sim's folders, src/ up to app/ and analysis/), a loose src/sim file and an upward Python import are refused and named"
