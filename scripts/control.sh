#!/bin/sh
# The quasi-static optimal control pipeline in one command (docs/control.md): the mapping batch
# on RANKS MPI ranks, surfaces, optimal trajectory, control table, verification run, report and
# plots into OUTPUT.
#   scripts/control.sh [CONTROL.yaml] [OUTPUT] [RANKS]
# defaults: examples/control/control.yaml results/control 1. Builds nothing: run scripts/build.sh first.
set -eu
cd "$(dirname "$0")/.."
control=${1:-examples/control/control.yaml}
output=${2:-results/control}
ranks=${3:-1}
exe=build/drivers/latticedyn
if [ ! -x "$exe" ]; then
    echo "control.sh: $exe is missing; build first (scripts/build.sh)" >&2
    exit 2
fi
export OMP_NUM_THREADS=1
if [ "$ranks" -gt 1 ]; then
    # Open MPI refuses root without these; --oversubscribe allows more ranks than cores.
    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
        mpiexec --oversubscribe -n "$ranks" "$exe" control "$control" --output "$output"
else
    "$exe" control "$control" --output "$output"
fi
/usr/bin/python3 scripts/control_report.py "$output"
echo "report: $output/control_report.md"
