#!/usr/bin/env bash
# Installs the Debian packages latticedyn builds, tests and plots with.
# Idempotent: packages already present are left alone and apt is not touched at all.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  petsc-dev slepc-dev
  libeigen3-dev libhdf5-openmpi-dev libopenmpi-dev openmpi-bin
  libmetis-dev libyaml-cpp-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-14 libclang-rt-14-dev libomp-14-dev
  python3 python3-numpy python3-h5py python3-matplotlib python3-yaml python3-dev pybind11-dev python3-pybind11 python3-torch
  paraview python3-paraview xvfb xauth ffmpeg libgl1-mesa-dri libglx-mesa0
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
