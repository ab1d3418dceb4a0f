#!/usr/bin/env bash
# ctest's check of latticedyn as an installed library (tests/CMakeLists.txt): installs the build
# tree into a scratch prefix, builds examples/library against it twice, with find_package(latticedyn)
# in a separate CMake project and with pkg-config on one compiler line, and runs both programs;
# then examples/api (the facade) with find_package, run on the crane with external drives.
#   tests/install/install-test.sh BUILD_DIR SCRATCH_DIR
set -euo pipefail
build=$1
scratch=$2
root="$(cd "$(dirname "$0")/../.." && pwd)"
rm -rf "$scratch" && mkdir -p "$scratch"
prefix="$scratch/prefix"
cmake --install "$build" --prefix "$prefix" > "$scratch/install.log"
for f in bin/latticedyn include/latticedyn/assembly/model_state.hpp include/latticedyn/api/simulator.hpp; do
  [[ -e "$prefix/$f" ]] || { echo "install-test: $prefix/$f not installed" >&2; exit 1; }
done
"$prefix/bin/latticedyn" --version

# find_package in a project of its own.
cmake -S "$root/examples/library" -B "$scratch/app" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  > "$scratch/configure.log"
cmake --build "$scratch/app" > "$scratch/build.log"
"$scratch/app/clamped_rod"
# The facade's example (api/simulator.hpp), the same way.
cmake -S "$root/examples/api" -B "$scratch/api" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  > "$scratch/configure_api.log"
cmake --build "$scratch/api" > "$scratch/build_api.log"
"$scratch/api/hoist_and_slew" "$root/examples/api/crane_external.yaml" > "$scratch/hoist_and_slew.log"
grep -q "^800 steps to t = 40 s" "$scratch/hoist_and_slew.log" ||
  { echo "install-test: hoist_and_slew did not reach t = 40 s:" >&2; cat "$scratch/hoist_and_slew.log" >&2; exit 1; }

# pkg-config, relocatable: the .pc file finds the prefix from where it lies.
pcdir=$(dirname "$(find "$prefix" -name latticedyn.pc)")
flags=$(PKG_CONFIG_PATH="$pcdir" pkg-config --cflags --libs latticedyn)
# shellcheck disable=SC2086
mpicxx "$root/examples/library/clamped_rod.cpp" -o "$scratch/clamped_rod_pc" $flags
"$scratch/clamped_rod_pc"
echo "install-test: find_package and pkg-config builds ran"
