#!/usr/bin/env bash
# Formats the C++ tree with the checked-in .clang-format; --check only reports (exit 1 if a file would change).
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files -- 'src/*.hpp' 'src/*.cpp' 'app/*.hpp' 'app/*.cpp' 'analysis/*.hpp' 'analysis/*.cpp' 'verify/*.hpp' 'verify/*.cpp' \
  'tests/*.hpp' 'tests/*.cpp' 'bench/*.cpp' | grep -v '\.in$')
if [ "${1:-}" = "--check" ]; then
  clang-format --dry-run --Werror "${files[@]}"
else
  clang-format -i "${files[@]}"
fi
