#!/usr/bin/env bash
# Installs every Debian package nsf needs to build, test and run. Idempotent:
# packages already present are skipped quickly, so the other scripts call it every time.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config clang-format
  libtorch-dev libopenblas-dev
  libeigen3-dev libhdf5-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libpng-dev libfreetype-dev fonts-dejavu-core gnuplot-nox ffmpeg
  libassimp-dev
  openmpi-bin libopenmpi-dev
  pybind11-dev python3-dev python3-numpy python3-pytest python3-h5py
  # `pip install .` into a venv, offline (docs/PYTHON.md): venv (with pip's and setuptools' wheels),
  # the build backend for the system's python and the wheel package's wheel for a venv's.
  python3-venv python3-setuptools python3-wheel python3-wheel-whl
  # The exported files read back by meshio, VTK and the Xdmf3 library (tests/check_export_readers.py).
  python3-meshio python3-vtk9 libxdmf3
  # The page of `nsf serve` checked in a headless browser (tests/cli/test_app_serve.cpp, ...Chromium...).
  chromium
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "nsf: installing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# libtorch links libblas.so.3 / liblapack.so.3, which the alternatives system may resolve to the
# reference BLAS (6-10x slower training and inference). Point both at OpenBLAS when they are not.
# `nsf train` prints the BLAS it actually loaded.
multiarch="$(gcc -dumpmachine 2>/dev/null || echo x86_64-linux-gnu)"
for lib in libblas.so.3 liblapack.so.3; do
  target="/usr/lib/${multiarch}/openblas-pthread/${lib}"
  current="$(readlink -f "/usr/lib/${multiarch}/${lib}" 2>/dev/null || true)"
  if [ -e "$target" ] && [[ "$current" != *openblas* ]]; then
    echo "nsf: pointing ${lib} at OpenBLAS (was ${current:-unset})"
    $SUDO update-alternatives --set "${lib}-${multiarch}" "$target"
  fi
done
