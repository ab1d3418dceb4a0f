#!/usr/bin/python3
"""Every example and verification model on 1, 2 and 3 MPI ranks: the static equilibrium (where the
model asks for one) and the first time steps must give the same state on every rank count.

  mpi_sweep.py LATTICEDYN WORKDIR MODEL [--steps N] [--ranks 1 2 3] [--tolerance T] [--serial-solver TEXT]
               [--parallel-solver TEXT] [--same-newton]

Runs `latticedyn run` (or `static` for a model without dynamics) with -ts_max_steps N on each
rank count, reads the last recorded coordinate vector (/state/coordinates, in model order: the
same numbering on any number of ranks) and compares the runs on several ranks with the one-rank
run: max |q_n - q_1| <= T (1 + max |q_1|). The ranks differ in their linear solver (PETSc's own LU
or UMFPACK on one rank, MUMPS or GMRES on additive Schwarz on several) and in the order of their
sums, so the Newton iterations end at different points inside their tolerance: T (default 1e-6) is
that, not round-off. --serial-solver, --parallel-solver: the runs on one and on several ranks must
report that linear solver. --same-newton: each rank count must take as many Newton iterations as
the first.
Exit 0 when every rank count agrees, 1 with the differences otherwise.
"""
import argparse
import os
import re
import subprocess
import sys

import h5py
import numpy as np
import yaml


def has_dynamics(path):
    with open(path) as f:
        doc = yaml.safe_load(f)
    if "solver" in doc:
        return "dynamics" in doc["solver"]
    if "base" in doc:
        return has_dynamics(os.path.join(os.path.dirname(path), doc["base"]))
    return False


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("work")
    ap.add_argument("model")
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--tolerance", type=float, default=1e-6)
    ap.add_argument("--parallel-solver", help="text the 'linear solver:' line must hold on several ranks")
    ap.add_argument("--serial-solver", help="text the 'linear solver:' line must hold on one rank")
    ap.add_argument("--same-newton", action="store_true",
                    help="every rank count takes as many Newton iterations as the first (exact Jacobians, "
                         "accurate linear solves: a wrong Jacobian entry shows here before it shows in the state)")
    a = ap.parse_args()
    command = "run" if has_dynamics(a.model) else "static"
    name = os.path.splitext(os.path.basename(a.model))[0]
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    states, newton = {}, {}
    for n in a.ranks:
        out = os.path.join(a.work, f"{name}_n{n}")
        cmd = [a.binary, command, a.model, "--output", out, "-ts_max_steps", str(a.steps), "-assembly_threads", "1"]
        if n > 1:
            cmd = ["mpiexec", "-n", str(n), "--bind-to", "none"] + cmd
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
        if p.returncode != 0:
            print(f"{name} on {n} rank(s): exit {p.returncode}\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}")
            return 1
        expected = a.parallel_solver if n > 1 else a.serial_solver
        if expected:
            line = next((l for l in p.stdout.splitlines() if l.startswith("linear solver:")), "(no 'linear solver:' line)")
            if expected not in line:
                print(f"{name} on {n} rank(s): expected a linear solver with '{expected}', got {line}")
                return 1
            print(f"{name} on {n} rank(s): {line}")
        m = re.search(r"(\d+) Newton iterations", p.stdout)
        newton[n] = int(m.group(1)) if m else None
        h5 = [f for f in os.listdir(out) if f.endswith(".h5")]
        with h5py.File(os.path.join(out, h5[0]), "r") as f:
            states[n] = f["state/coordinates"][-1, :]
            multipliers = int(np.sum(f["model/constraint_rows"][:])) if "model/constraint_rows" in f else 0
    # Model order: the coordinates (m, rad, ...), then the multipliers (N, N m), each judged on its
    # own scale.
    ok = True
    if a.same_newton:
        print(f"{name}: Newton iterations per rank count {newton}")
        ok = newton[a.ranks[0]] is not None and len(set(newton.values())) == 1
    ref = states[a.ranks[0]]
    nq = ref.size - multipliers
    for n in a.ranks[1:]:
        if states[n].shape != ref.shape:
            print(f"{name}: {n} rank(s) recorded {states[n].size} coordinates, {a.ranks[0]} rank(s) {ref.size}")
            ok = False
            continue
        for part, sl in (("coordinates", slice(0, nq)), ("multipliers", slice(nq, ref.size))):
            if sl.start == sl.stop:
                continue
            # Floors: a metre for the coordinates; a micronewton for the multipliers, whose round-off
            # is all an unloaded model has (1e-20 N between rank counts).
            scale = np.max(np.abs(ref[sl])) + (1.0 if part == "coordinates" else 1e-6)
            diff = np.max(np.abs(states[n][sl] - ref[sl]))
            print(f"{name}: {n} rank(s) against {a.ranks[0]}, {part}: max difference {diff:.3g} "
                  f"({diff / max(scale, 1e-300):.3g} of their largest)")
            ok = ok and diff <= a.tolerance * scale
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
