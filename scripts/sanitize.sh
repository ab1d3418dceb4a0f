#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build of latticedyn in ./build-asan and its unit
# tests and verification cases under them (GCC's libasan and libubsan). Open MPI's and PETSc's
# own allocations are not ours: leak checking is off; any other finding fails the test.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${LATTICEDYN_ASAN_DIR:-build-asan}
jobs=${LATTICEDYN_JOBS:-$(nproc)}
# Line tables only (-g1), compressed (-gz): the sanitizers' reports still name file and line, and
# the build takes a fraction of the disk full debug information needs (every test program links
# the static layers; full -g filled a CI machine's disk). -O1, ASan's recommended level: every
# check stays and the build, CI's largest phase, is a quarter shorter than at -O2
# (docs/reliability.md).
debug_flags="-O1 -g1 -gz -DNDEBUG"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLATTICEDYN_SANITIZE=address,undefined \
      -DCMAKE_C_FLAGS_RELWITHDEBINFO="$debug_flags" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$debug_flags" \
      -DLATTICEDYN_BUILD_BENCHMARKS=OFF >/dev/null
# gtest_discover_tests runs the test programs while building: the options apply there too.
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
cmake --build "$build_dir" -j "$jobs"
echo "sanitize.sh: the build took $((SECONDS / 60)) min $((SECONDS % 60)) s"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# A test that hangs (an MPI rank left waiting) fails after 15 minutes instead of spinning until CI's
# limit; the slowest test takes about 3.5 minutes under the sanitizers. Tests with their own
# TIMEOUT keep it.
ctest --test-dir "$build_dir" --output-on-failure --timeout 900 -j "$(nproc)" -L "unit|verification" -LE "mpi|study" "$@"
