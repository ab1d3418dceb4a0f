#!/usr/bin/env bash
# The README's main job: installs the dependencies, builds latticedyn and runs an example model
# (default: the combined motion of the Appendix D crane, thesis 8.3.2), then plots the load's
# motion when matplotlib is there. Results go to the model's output folder (HDF5, XDMF, probe CSV).
set -euo pipefail
cd "$(dirname "$0")/.."
model=${1:-examples/crane/combined.yaml}
scripts/install-deps.sh
scripts/build.sh
build/drivers/latticedyn run "$model"
if [[ "$model" == examples/crane/* ]]; then
  name=$(basename "$model" .yaml)
  h5=$(ls results/crane_"$name"/"$name".h5 2>/dev/null || true)
  if [[ -n "$h5" ]] && /usr/bin/python3 -c "import h5py, matplotlib" 2>/dev/null; then
    /usr/bin/python3 scripts/crane_report.py "$h5" --out "$(dirname "$h5")"
  fi
fi
