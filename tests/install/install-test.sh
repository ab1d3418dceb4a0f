#!/usr/bin/env bash
# ctest's check of latticedyn as an installed library (tests/CMakeLists.txt): installs the build
# tree into a scratch prefix, builds examples/library against it twice, with find_package(latticedyn)
# in a separate CMake project and with pkg-config on one compiler line, and runs both programs.
#   tests/install/install-test.sh BUILD_DIR SCRATCH_DIR
set -euo pipefail
build=$1
scratch=$2
root="$(cd "$(dirname "$0")/../.." && pwd)"
rm -rf "$scratch" && mkdir -p "$scratch"
prefix="$scratch/prefix"
cmake --install "$build" --prefix "$prefix" > "$scratch/install.log"
for f in bin/latticedyn include/latticedyn/assembly/model_state.hpp; do
  [[ -e "$prefix/$f" ]] || { echo "install-test: $prefix/$f not installed" >&2; exit 1; }
done
"$prefix/bin/latticedyn" --version

# find_package in a project of its own.
cmake -S "$root/examples/library" -B "$scratch/app" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  > "$scratch/configure.log"
cmake --build "$scratch/app" > "$scratch/build.log"
"$scratch/app/clamped_rod"

# pkg-config, relocatable: the .pc file finds the prefix from where it lies.
pcdir=$(dirname "$(find "$prefix" -name latticedyn.pc)")
flags=$(PKG_CONFIG_PATH="$pcdir" pkg-config --cflags --libs latticedyn)
# shellcheck disable=SC2086
mpicxx "$root/examples/library/clamped_rod.cpp" -o "$scratch/clamped_rod_pc" $flags
"$scratch/clamped_rod_pc"
echo "install-test: find_package and pkg-config builds ran"
