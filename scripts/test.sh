#!/usr/bin/env bash
# Installs the dependencies, builds latticedyn and runs the whole test suite under ctest:
# unit tests, verification cases and the MPI cases, then the unit tests and verification cases
# of a sanitizer build (scripts/sanitize.sh), then two minutes of fuzzing the model reader
# (scripts/fuzz.sh). This is the README's test command.
set -euo pipefail
cd "$(dirname "$0")/.."
# The builds need about 2.5 GB of free disk in all (build/ 0.1 GB, build-asan/ 1.9 GB with line
# tables only, build-fuzz/ the reader's layers): say what there is, so a full disk is seen as one.
disk_free() { echo "test.sh: $(df -h --output=avail . | tail -1 | tr -d ' ') free on $(df --output=target . | tail -1) ($1)"; }
# Each phase's time, so that a run near CI's limit shows which phase grew.
phase_start=$SECONDS
phase_done() {
  echo "test.sh: $1 took $(((SECONDS - phase_start) / 60)) min $(((SECONDS - phase_start) % 60)) s (total $((SECONDS / 60)) min)"
  phase_start=$SECONDS
}
disk_free "before the builds"
scripts/install-deps.sh
phase_done "installing the dependencies"
scripts/build.sh
phase_done "the build"
# Open MPI refuses to start as root unless told; the MPI tests oversubscribe small machines.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
# A test that hangs (an MPI rank left waiting) fails after 15 minutes instead of spinning until CI's
# limit; the slowest test takes about 3.5 minutes under the sanitizers. Tests with their own
# TIMEOUT keep it.
ctest --test-dir "${LATTICEDYN_BUILD_DIR:-build}" --output-on-failure --timeout 900 -j "$(nproc)" "$@"
phase_done "the test suite"
# Then the unit tests and verification cases again under AddressSanitizer and
# UndefinedBehaviorSanitizer (a second build at -O1, with its tests about 40 minutes on two cores;
# LATTICEDYN_SKIP_SANITIZE=1 leaves it out).
if [ "${LATTICEDYN_SKIP_SANITIZE:-0}" != 1 ]; then
  disk_free "before the sanitizer build"
  scripts/sanitize.sh
  phase_done "the sanitizer build and its tests"
fi
# The model reader's libFuzzer target for a bounded time on its corpus (clang-14; a third build,
# of the reader's layers only; LATTICEDYN_SKIP_FUZZ=1 leaves it out, LATTICEDYN_FUZZ_SECONDS
# changes the time).
if [ "${LATTICEDYN_SKIP_FUZZ:-0}" != 1 ]; then
  disk_free "before the fuzzing build"
  scripts/fuzz.sh "${LATTICEDYN_FUZZ_SECONDS:-120}"
  phase_done "the fuzzing build and run"
fi
