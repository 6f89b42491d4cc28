#!/usr/bin/env bash
# `pip install .` into a fresh virtual environment (with the system's site packages, for numpy, pandas and
# matplotlib): the in-tree build backend (python/build_backend) packs the package CMake builds into a wheel,
# here packing the build directory BUILD as it is (--config-settings build-dir=BUILD build=no), and from outside the source
# tree `import rotleak` gives the installed package, which runs a scene in process and reads it back.
# Everything is written to a temporary directory, removed at the end.   Usage: scripts/pip_check.sh BUILD
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$1" && pwd)
python=${PYTHON:-$(bash "$(dirname "$0")/setup.sh" --python)}
work=$(mktemp -d /tmp/rotleak-pip-XXXXXX)
trap 'rm -rf "$work"' EXIT
"$python" -m venv --system-site-packages "$work/venv"
# build=no: pack the suite's build as it is (a test does not rebuild what the other tests run)
PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 "$work/venv/bin/pip" install --quiet --config-settings "build-dir=$build" \
  --config-settings build=no "$src"
cd "$work"
"$work/venv/bin/python" - "$src/data/scenes/quickstart.toml" "$work/venv" <<'PY'
import os, sys
import rotleak
scene, venv = sys.argv[1], sys.argv[2]
assert rotleak.__file__.startswith(venv), "imported %s, not the installed package" % rotleak.__file__
run = rotleak.simulate(scene, particles=20000)
run.write("run")
again = rotleak.read_run("run")
assert again.text("survival.csv") == run.text("survival.csv")
print("pip install .: rotleak %s in %s; a run of %d particles, kappa = %.4g +- %.1g"
      % (rotleak.__version__, os.path.dirname(rotleak.__file__), run.summary["particles"], run.kappa.value,
         run.kappa.error))
PY
