#!/usr/bin/env bash
# Usage: scripts/ninja_tree.sh DIR: a build tree DIR that another generator (make) configured is configured
# afresh with Ninja: its CMake cache goes (ccache keeps the objects). Called by build.sh, sanitize.sh, fuzz.sh.
set -euo pipefail
dir=$1
if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir/CMakeCache.txt"; then
  echo "$dir/ was made by another generator; configuring it afresh with Ninja" >&2
  rm -rf "$dir/CMakeCache.txt" "$dir/CMakeFiles"
fi
