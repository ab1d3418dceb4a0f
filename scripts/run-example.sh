#!/usr/bin/env bash
# The README's main job: installs the dependencies, builds latticedyn and runs an example model
# (default: the double pendulum). Results go to results/<model name>/ (HDF5, XDMF, probe CSV).
set -euo pipefail
cd "$(dirname "$0")/.."
model=${1:-examples/double_pendulum.yaml}
scripts/install-deps.sh
scripts/build.sh
build/drivers/latticedyn run "$model"
