#!/usr/bin/env bash
# Runs the four maneuvers of thesis 8.3 (examples/crane/{lifting,luffing,slewing,combined}.yaml)
# on the reduced crane and on the full crane, and writes their plots, tables, pictures and one
# movie to docs/crane/ (results stay in results/crane_<maneuver>[_full]/). Builds first if needed.
#   scripts/crane-maneuvers.sh [maneuver ...]       (default: all four)
# THREADS=1 scripts/crane-maneuvers.sh measures on one core (one assembly thread); the timings go
# to docs/crane/timing.csv with the thread count.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${LATTICEDYN_BUILD_DIR:-build}
out=docs/crane
[[ -x "$build/drivers/latticedyn" ]] || scripts/build.sh
mkdir -p "$out"
maneuvers=("$@")
[[ ${#maneuvers[@]} -gt 0 ]] || maneuvers=(lifting luffing slewing combined)
have_paraview() { command -v pvpython >/dev/null && command -v xvfb-run >/dev/null; }
render() {  # ParaView's X connection under xvfb-run fails now and then at start-up: retry
  have_paraview || return 0
  for attempt in 1 2 3; do
    if xvfb-run -a pvpython scripts/render.py "$@" 2>&1 | grep -v "Cannot find DataItem" | grep "^wrote"; then return 0; fi
  done
  echo "warning: could not render $1" >&2
}
threads=${THREADS:-2}
export OMP_NUM_THREADS=$threads
timing="$out/timing.csv"
[[ -f "$timing" ]] || echo "maneuver,model,threads,steps,newton,jacobians,wall_s,realtime_factor" > "$timing"
for m in "${maneuvers[@]}"; do
  for variant in "" _full; do
    log="results/crane_${m}${variant}/run.log"
    mkdir -p "results/crane_${m}${variant}"
    "$build/drivers/latticedyn" run "examples/crane/${m}${variant}.yaml" -assembly_threads "$threads" | tee "$log" | grep -v "^t = "
    # "dynamics completed: N steps (..), M Newton iterations (..), J Jacobians, .. wall W s (F x real time)"
    sed -n 's/^dynamics completed: \([0-9]*\) steps.*, \([0-9]*\) Newton iterations.*, \([0-9]*\) Jacobians.*wall \([0-9.e+]*\) s (\([0-9.e+]*\) x real time).*/\1,\2,\3,\4,\5/p' "$log" |
      sed "s/^/${m},$([[ -n $variant ]] && echo full || echo reduced),${threads},/" >> "$timing"
    /usr/bin/python3 scripts/crane_report.py "results/crane_${m}${variant}/${m}${variant}.h5" --out "$out"
  done
  # Each body's most utilized member, reduced beside full (<m>_members.md).
  /usr/bin/python3 scripts/crane_report.py "results/crane_${m}/${m}.h5" --out "$out" --vs "results/crane_${m}_full/${m}_full.h5"
  render "results/crane_${m}/${m}.xdmf" --output "$out/${m}.png" --times 0 20 40 --view iso --size 900 700
  render "results/crane_${m}_full/${m}_full.xdmf" --output "$out/${m}_full.png" --times 0 20 40 --view iso --size 900 700
done
if [[ " ${maneuvers[*]} " == *" slewing "* ]]; then
  render "results/crane_slewing/slewing.xdmf" --movie "$out/slewing.mp4" --view iso --frames 140 --fps 10 --size 480 360
fi
echo "plots, tables and pictures: $out/; timings: $timing"
