#!/usr/bin/env bash
# Installs the dependencies, builds latticedyn and runs the whole test suite under ctest:
# unit tests, verification cases and the MPI cases, then the unit tests and verification cases
# of a sanitizer build (scripts/sanitize.sh). This is the README's test command.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
# Open MPI refuses to start as root unless told; the MPI tests oversubscribe small machines.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
ctest --test-dir "${LATTICEDYN_BUILD_DIR:-build}" --output-on-failure -j "$(nproc)" "$@"
# Then the unit tests and verification cases again under AddressSanitizer and
# UndefinedBehaviorSanitizer (a second build, about half an hour on two cores;
# LATTICEDYN_SKIP_SANITIZE=1 leaves it out).
if [ "${LATTICEDYN_SKIP_SANITIZE:-0}" != 1 ]; then
  scripts/sanitize.sh
fi
