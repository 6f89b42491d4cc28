#!/usr/bin/env bash
# The Debian package: cpack -G DEB from a build, its control fields (Depends from dpkg-shlibdeps plus
# Python's), then extracted with dpkg -x into a temporary root (no change to this system) and run from
# there: the quick-start scene with its plots, rotleak verify, and the Python package in process.
# With --install (root only) it also installs the .deb with dpkg -i, runs the quick-start scene from
# /usr/bin/rotleak and removes the package again.   Usage: scripts/deb_check.sh BUILD_DIR [--install]
set -euo pipefail
py=$(bash "$(dirname "$0")/setup.sh" --python)  # the interpreter setup.sh names
build=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$build" && cpack -G DEB -B "$work/pkg" >/dev/null)
deb=$(ls "$work"/pkg/*.deb)
echo "built $(basename "$deb") ($(du -h "$deb" | cut -f1))"
dpkg-deb -f "$deb" Package Version Depends | sed 's/^/  /'
dpkg -x "$deb" "$work/root"
r=$work/root/usr
scene=$r/share/rotleak/data/scenes/quickstart.toml
"$r/bin/rotleak" --version
# the package carries the version of what it holds: the binary's git hash is in the package's Version
hash=$("$r/bin/rotleak" --version | sed -n 's/^[^ ]*+g\([0-9a-f]*\).*/\1/p')
if [ -n "$hash" ] && ! dpkg-deb -f "$deb" Version | grep -q "g$hash"; then
  echo "the package's Version $(dpkg-deb -f "$deb" Version) is not the binary's ($("$r/bin/rotleak" --version))"
  exit 1
fi
"$r/bin/rotleak" simulate "$scene" --particles 20000 --out "$work/run" --no-progress --plot | tail -2
test -s "$work/run/survival.png"
"$r/bin/rotleak" verify --tier double | tail -1
PYTHONPATH=$r/lib/python3/dist-packages "$py" -c '
import sys, rotleak
assert rotleak.__file__.startswith(sys.argv[2]), rotleak.__file__
r = rotleak.simulate(sys.argv[1], particles=10**5)
print("python from the package: rotleak %s, kappa = %.5g" % (rotleak.__version__, r.summary["kappa"]["value"]))' "$scene" "$r"
if [ "${2:-}" = "--install" ]; then
  dpkg -i "$deb" >/dev/null
  trap 'dpkg -r rotleak >/dev/null; rm -rf "$work"' EXIT
  /usr/bin/rotleak simulate /usr/share/rotleak/data/scenes/quickstart.toml --particles 20000 --out "$work/sys" \
    --no-progress | tail -1
  "$py" -c 'import rotleak; print("python3 finds the installed package:", rotleak.__file__)'
fi
echo "the .deb builds, extracts and runs the quick-start scene"
