#!/usr/bin/env bash
# Configures and builds latticedyn in ./build (Release, all cores); used by the README's commands.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${LATTICEDYN_BUILD_DIR:-build}
jobs=${LATTICEDYN_JOBS:-$(nproc)}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE:-Release} >/dev/null
cmake --build "$build_dir" -j "$jobs"
