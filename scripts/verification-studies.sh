#!/usr/bin/env bash
# Runs the chapter 8 verification studies (verification/studies/*.yaml) and writes their tables
# (CSV, markdown), figures (PNG) and reports: the beam studies of 8.1 to docs/verification/beams/,
# each super truss reduction study of 8.2 to docs/verification/lattice/<study>/. Every run's model
# and ParaView results stay in build/studies/<study>/{models,results}/. Builds first if needed.
#   scripts/verification-studies.sh              all studies
#   scripts/verification-studies.sh lattice_type2 ...   only these (reports of the others kept)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${LATTICEDYN_BUILD_DIR:-build}
beams=docs/verification/beams
work="$build/studies"
[[ -x "$build/verification/latticedyn_study" ]] || scripts/build.sh
mkdir -p "$beams" "$work"
have_paraview() { command -v pvpython >/dev/null && command -v xvfb-run >/dev/null; }
# ParaView's X connection under xvfb-run fails now and then at start-up: one retry.
render() {
  have_paraview || return 0
  for attempt in 1 2; do
    if xvfb-run -a pvpython scripts/render.py "$@" 2>&1 | grep -v "Cannot find DataItem" | grep "^wrote"; then
      return 0
    fi
  done
  echo "warning: could not render $1" >&2
}

wanted=("$@")
selected() { [[ ${#wanted[@]} -eq 0 ]] || [[ " ${wanted[*]} " == *" $1 "* ]]; }

status=0
beam_studies=0
for study in verification/studies/*.yaml; do
  name=$(basename "$study" .yaml)
  selected "$name" || continue
  "$build/verification/latticedyn_study" "$study" --out "$work/$name" || status=1
  if grep -q "^study: lattice_reduction" "$study"; then
    out="docs/verification/lattice/$name"
    mkdir -p "$out"
    cp "$work/$name"/*.csv "$work/$name"/*.md "$out"/
    # The members near the root under self-weight and a tip force, both models in one colour scale.
    scale=$(awk -F, 'NR > 1 { for (i = 5; i <= 6; ++i) { v = $i < 0 ? -$i : $i; if (v > m) m = v } }
                     END { printf "%.3g", m }' "$out/members.csv")
    for model in full reduced; do
      run="$work/$name/results/members_$model/members_$model.xdmf"
      [[ -f "$run" ]] && render "$run" --output "$out/${model}_members.png" --view iso \
        --color axial_force --range "$scale" --size 1000 600
    done
    title=$(sed -n 's/^title: *//p' "$study")
    /usr/bin/python3 scripts/plot_lattice_study.py "$out" "${title^}"
  else
    beam_studies=1
    cp "$work/$name"/*.csv "$work/$name"/*.md "$beams"/
  fi
done
if [[ $beam_studies -eq 1 ]]; then
  # A look at one run in ParaView's renderer (needs paraview and xvfb; skipped without them).
  angle_run="$work/rotation_angle/results/rotation_angle_C10/rotation_angle_C10.xdmf"
  [[ -f "$angle_run" ]] && render "$angle_run" --output "$beams/rotation_angle_C10.png" \
    --times 0 1 2 3 4 5 --view xz --size 1200 700
  /usr/bin/python3 scripts/plot_studies.py "$beams"
fi
echo "reports: $beams/README.md, docs/verification/lattice/<study>/README.md;" \
  "models and ParaView results of every run: $work/<study>/"
exit $status
