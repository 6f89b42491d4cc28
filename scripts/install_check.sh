#!/usr/bin/env bash
# rotleak from its install tree, with the source tree out of reach: cmake --install into a temporary
# prefix, then (in a private mount namespace where the source tree, and the build if it lies outside
# it, are hidden under an empty directory) the quick-start scene with its plots, rotleak plot, verify
# --tier all, a 3-point scan and its plots, the Python package (an in-process run, read_run and
# read_scan, the version), and a CMake project of its own that finds the package and links
# rotleak::core. Exit 1 on any failure.   Usage: scripts/install_check.sh BUILD_DIR  (as root, or
# where unshare --map-root-user works)
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
build=$(realpath "$1")
src=$(realpath "$(dirname "$0")/..")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >/dev/null
cp -r "$src/tests/install_consumer" "$work/consumer-src"
mkdir "$work/empty" "$work/out"
hide="mount --bind $work/empty $src"
case "$build" in "$src"/*) ;; *) hide="$hide && mount --bind $work/empty $build" ;; esac

cat >"$work/steps.sh" <<STEPS
set -euo pipefail
P=$prefix
W=$work/out
export PATH=\$P/bin:\$PATH
unset ROTLEAK_DATA ROTLEAK_PYTHONPATH PYTHONPATH
[ ! -e "$src/data" ] || { echo "the source tree is still visible"; exit 1; }
scene=\$P/share/rotleak/data/scenes/quickstart.toml
echo "installed: \$(command -v rotleak): \$(rotleak --version)"
rotleak simulate "\$scene" --particles 20000 --out "\$W/run" --no-progress --plot | tail -1
test -s "\$W/run/survival.png" && test -s "\$W/run/fc.png"
rotleak plot "\$W/run" >/dev/null
rotleak verify --tier all | tail -1
rotleak scan "\$scene" --over leak.omega=0,1,2/3 --set ensemble.particles=5000 --out "\$W/scan" --no-progress | tail -1
rotleak plot "\$W/scan" | tail -1
PYTHONPATH=\$P/$(grep -m1 '^ROTLEAK_PYTHON_INSTALL_DIR:' "$build/CMakeCache.txt" | cut -d= -f2) "$py" - "\$scene" "\$W" <<'PY'
import sys, rotleak
scene, W = sys.argv[1], sys.argv[2]
assert rotleak.__file__.startswith("$prefix"), rotleak.__file__
r = rotleak.simulate(scene, particles=10**5)
print("python (installed package %s): in-process kappa = %.5g" % (rotleak.__version__, r.summary["kappa"]["value"]))
assert r.summary["execution"]["rotleak"]["version"] == rotleak.__version__
run = rotleak.read_run(W + "/run")
assert run.survival.columns.tolist() == ["t", "survivors", "P", "P_err"] and run.summary["particles"] == 20000
scan = rotleak.read_scan(W + "/scan")
assert scan.table["leak.omega"].tolist() == ["0", "1", "2/3"], scan.table["leak.omega"].tolist()
print("python: read_run and read_scan of the installed command's output: %d survival rows, %d scan rows"
      % (len(run.survival), len(scan.table)))
PY
cmake -S $work/consumer-src -B \$W/consumer -DCMAKE_PREFIX_PATH=\$P -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build \$W/consumer >/dev/null
\$W/consumer/consumer
STEPS

if unshare --mount true 2>/dev/null; then
  unshare --mount bash -c "$hide && bash $work/steps.sh"
else
  unshare --mount --map-root-user bash -c "$hide && bash $work/steps.sh"
fi
echo "install tree: simulate, plot, verify, scan, Python and find_package(rotleak) all work without the source tree"
