#!/usr/bin/env bash
# Installs the Debian packages rotleak builds and runs with. Idempotent and quick when all are present:
# apt-get is only called for packages that dpkg does not already report as installed.
set -euo pipefail
# The Python interpreter rotleak's package, scripts and docs run with, named here and nowhere else: Debian's,
# for which the packages below install numpy, pandas and matplotlib (a pyenv or conda python3 first on
# PATH lacks them). `bash scripts/setup.sh --python` prints it: CMake builds the module for it, the
# scripts run it, and the docs call it by this path.
python=/usr/bin/python3
if [ "${1:-}" = --python ]; then
  echo "$python"
  exit 0
fi
packages=(
  build-essential cmake ninja-build pkg-config ccache clang-format git universal-ctags
  clang libclang-rt-14-dev
  libgmp-dev libmpfr-dev libmpfi-dev libqd-dev libboost-dev libcgal-dev
  libgtest-dev libbenchmark-dev librandom123-dev libsleef-dev libtomlplusplus-dev nlohmann-json3-dev libcli11-dev libxsimd-dev
  python3 python3-dev python3-matplotlib python3-numpy python3-pandas python3-yaml pybind11-dev
  jupyter-nbconvert python3-nbformat python3-ipykernel python3-mypy python3-sphinx python3-venv python3-pip
  libopenmpi-dev openmpi-bin
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
