#!/usr/bin/env bash
# Runs the chapter 8 verification studies (verification/studies/*.yaml) and writes their tables
# (CSV, markdown), figures (PNG) and report to docs/verification/beams/. Every run's model and
# ParaView results stay in build/studies/<study>/{models,results}/. Builds first if needed.
#   scripts/verification-studies.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${LATTICEDYN_BUILD_DIR:-build}
out=docs/verification/beams
work="$build/studies"
[[ -x "$build/verification/latticedyn_study" ]] || scripts/build.sh
mkdir -p "$out" "$work"
status=0
for study in verification/studies/*.yaml; do
  name=$(basename "$study" .yaml)
  "$build/verification/latticedyn_study" "$study" --out "$work/$name" || status=1
  cp "$work/$name"/*.csv "$work/$name"/*.md "$out"/
done
# A look at one run in ParaView's renderer (needs paraview and xvfb; skipped without them).
angle_run="$work/rotation_angle/results/rotation_angle_C10/rotation_angle_C10.xdmf"
if command -v pvpython >/dev/null && command -v xvfb-run >/dev/null && [[ -f "$angle_run" ]]; then
  xvfb-run -a pvpython scripts/render.py "$angle_run" --output "$out/rotation_angle_C10.png" \
    --times 0 1 2 3 4 5 --view xz --size 1200 700 2>&1 | grep -v "Cannot find DataItem" || true
fi
/usr/bin/python3 scripts/plot_studies.py "$out"
echo "report: $out/README.md; models and ParaView results of every run: $work/<study>/"
exit $status
