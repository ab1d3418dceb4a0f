#!/usr/bin/env bash
# ctest's rendering check (verification/CMakeLists.txt): runs a short crane case and draws it with
# scripts/render.py in ParaView under xvfb, a PNG at three times coloured by body and a
# low-resolution MP4 coloured by axial force (from results with the XDMF's body blocks,
# output.body_blocks), then checks both files exist and are not empty and that render.py printed
# nothing but its "wrote" line (no VTK messages). Exit 77 (skipped) without
# pvpython, xvfb-run or ffmpeg.
#   scripts/render-test.sh LATTICEDYN_EXE OUT_DIR
set -euo pipefail
exe=$1
out=$2
root="$(cd "$(dirname "$0")/.." && pwd)"
for tool in pvpython xvfb-run ffmpeg; do
  command -v "$tool" >/dev/null || { echo "render-test: $tool not installed, skipped"; exit 77; }
done
rm -rf "$out" && mkdir -p "$out"
"$exe" run "$root/verification/cases/crane_short.yaml" --output "$out" > "$out/run.log" 2>&1
xdmf="$out/crane_short.xdmf"
# ParaView's X connection under xvfb-run fails now and then at start-up: up to three tries.
render() {
  for attempt in 1 2 3; do
    if xvfb-run -a pvpython "$root/scripts/render.py" "$xdmf" "$@" > "$out/render.log" 2>&1; then
      if grep -qv "^wrote " "$out/render.log"; then
        echo "render-test: render.py printed more than its result:" >&2
        cat "$out/render.log" >&2
        return 1
      fi
      return 0
    fi
  done
  cat "$out/render.log" >&2
  return 1
}
render --output "$out/crane.png" --times 0 1 2 --view iso --size 320 240
# The same run with a block per body in the XDMF.
cat > "$out/crane_bodies.yaml" <<EOF
base: $root/verification/cases/crane_short.yaml
output: {interval: 0.1, probes: [load.1], body_blocks: true}
EOF
"$exe" run "$out/crane_bodies.yaml" --output "$out" > "$out/run_bodies.log" 2>&1
xdmf="$out/crane_bodies.xdmf"
grep -q '<Grid Name="hoisting_rope" GridType="Collection" CollectionType="Temporal">' "$xdmf" ||
  { echo "render-test: $xdmf has no block named after the body hoisting_rope" >&2; exit 1; }
render --movie "$out/crane.mp4" --view iso --frames 21 --fps 10 --size 320 240 --color axial_force
for f in crane.png crane.mp4; do
  [[ -s "$out/$f" ]] || { echo "render-test: $out/$f missing or empty" >&2; exit 1; }
done
echo "render-test: wrote $out/crane.png and $out/crane.mp4"
