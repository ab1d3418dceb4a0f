#!/usr/bin/python3
"""Generates the "lattice-bays" benchmark model: a cantilevered rectangular lattice of N bays.

Bays of 2.5 m along x, four chords at (y, z) = (+-0.75, +-0.70); per bay 4 chord members, 4 cross
members around the rectangle at the bay's far end and 4 face diagonals (one per face, alternating
direction bay to bay: the bays alternate between two sections whose main beams run in opposite
cyclic order); chord tubes 0.1 / 0.08 m outer / inner radius, all other members 0.05 / 0.04 m;
steel (E 2.06e11, nu 0.3, rho 7800); one co-rotational Timoshenko beam per member, members rigidly
joined at shared nodes (one `lattice` body per bay, bays joined by shared fixed connections); the
4 base nodes fixed; gravity -z; from rest; generalized-alpha rho_inf 0.667, h = 0.01 s, Newton
absolute tolerance 1e-6. Every bay adds 4 nodes of 6 DoFs: 10 bays are 240 free DoFs, 640 bays
15,360, 40,960 bays 983,040.

  /usr/bin/python3 benchmarks/lattice_bays.py 640 --steps 10 --out /tmp/bays640.yaml
  build/drivers/latticedyn run /tmp/bays640.yaml -assembly_threads 1
"""
import argparse
import os

END = [(0.75, 0.70), (-0.75, 0.70), (-0.75, -0.70), (0.75, -0.70)]
BAY = 2.5


def section(name, main_beams):
    ends = ", ".join(f"[{y}, {z}]" for y, z in END)
    beams = ", ".join(f"[{a}, {a}]" for a in main_beams)
    return (f"  {name}:\n"
            f"    length: {BAY}\n    order: 1\n"
            f"    end1: [{ends}]\n"
            f"    main_beams: [{beams}]\n"
            f"    cross_beams2: [[1, 2], [2, 3], [3, 4], [4, 1]]\n"
            f"    connection: type1\n    material: steel\n"
            f"    main_section: chord\n    cross_section: lacing\n    sub_section: lacing\n")


def write(bays, steps, reuse, interval, out):
    lines = [f"title: lattice-bays, {bays} bays\n", "gravity: [0, 0, -9.81]\n",
             "materials:\n  steel: {density: 7800, youngs_modulus: 2.06e11, poisson_ratio: 0.3}\n",
             "sections:\n  chord: {type: round_tube, outer_radius: 0.1, inner_radius: 0.08}\n"
             "  lacing: {type: round_tube, outer_radius: 0.05, inner_radius: 0.04}\n",
             "truss_sections:\n", section("bay_a", [1, 2, 3, 4]), section("bay_b", [1, 4, 3, 2]),
             "ground:\n  joints:\n"]
    for k, (y, z) in enumerate(END, 1):
        lines.append(f"    - {{name: base{k}, position: [0, {y}, {z}]}}\n")
    lines.append("bodies:\n")
    for i in range(bays):
        sec = "bay_a" if i % 2 == 0 else "bay_b"
        lines.append(f"  - {{name: bay{i + 1}, type: lattice, section: {sec}, position: [{BAY * i}, 0, 0], "
                     f"rigid_ends: false}}\n")
    lines.append("constraints:\n")
    for k in range(1, 5):
        lines.append(f"  - {{name: base{k}, type: fixed, joints: [ground.base{k}, bay1.e1n{k}], shared: true}}\n")
    for i in range(1, bays):
        for k in range(1, 5):
            lines.append(f"  - {{name: joint{i}_{k}, type: fixed, joints: [bay{i}.e2n{k}, bay{i + 1}.e1n{k}], "
                         f"shared: true}}\n")
    lines.append("solver:\n  static: {enabled: false}\n"
                 f"  dynamics: {{t_end: {0.01 * steps:.10g}, time_step: 0.01, rho_infinity: 0.667, "
                 f"jacobian_reuse: {reuse}}}\n"
                 "  petsc_options: \"-snes_atol 1e-6 -snes_rtol 1e-50\"\n")
    lines.append(f"output:\n  interval: {interval}\n  probes: [bay{bays}.e2n1]\n")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out, "w") as f:
        f.writelines(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bays", type=int)
    ap.add_argument("--steps", type=int, default=10, help="time steps of 0.01 s")
    ap.add_argument("--reuse", type=int, default=1, help="solver.dynamics.jacobian_reuse")
    ap.add_argument("--interval", type=float, default=1000.0, help="output interval (s); default: first and last")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    if a.bays < 1:
        ap.error("at least one bay")
    write(a.bays, a.steps, a.reuse, a.interval, a.out)


if __name__ == "__main__":
    main()
