#!/usr/bin/python3
"""Work-precision diagram of latticedyn's time integrators: error against the dynamics' wall time
for generalized-alpha and the implicit Runge-Kutta route (ARKIMEX 3, 4, 5; ROSW ra34pw2) on the
double pendulum (examples/double_pendulum.yaml, 1 s), a flexible cantilever of cubic spline beams
under self-weight (examples/cantilever.yaml, 1 s) and the reduced crane's lifting maneuver
(examples/crane/lifting.yaml, 60 s). The error is the largest distance of a probe (the pendulum's
tip, the beam's tip, the crane's load) from a reference run over the common output times:
ARKIMEX 5 with a step 100 (pendulum) or 12.5 (beam) times below the finest compared, and the
crane's step-study reference (generalized-alpha, h = 0.01 s, fresh Jacobians, Newton 1e-6) for
the crane. One core; run it on an otherwise idle machine.

  /usr/bin/python3 scripts/work_precision.py --out docs/perf/work_precision [--cases pendulum beam crane]

Writes <out>.csv (case, method, h, steps, Newton iterations, wall, error) and <out>.png.
"""
import argparse
import csv
import math
import os
import re
import subprocess
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BINARY = os.path.join(ROOT, "build", "drivers", "latticedyn")

CASES = {
    "pendulum": dict(model="examples/double_pendulum.yaml", probe="lower.tip", t_end=1.0, interval=0.01, static="",
                     steps=[0.04, 0.02, 0.01, 0.005, 0.0025], reference=("implicit_rk", "arkimex:5", 2.5e-5),
                     title="double pendulum, 1 s (tip)"),
    "beam": dict(model="examples/cantilever.yaml", probe="beam.2", t_end=1.0, interval=0.02,
                 static="  static: {enabled: false}\n", steps=[0.02, 0.01, 0.005, 0.0025, 0.00125],
                 reference=("implicit_rk", "arkimex:5", 1e-4), title="cantilever, 10 spline beams, 1 s (tip)"),
    "crane": dict(model="examples/crane/lifting.yaml", probe="load.1", t_end=60.0, interval=0.1,
                  static="  static: {load_steps: 4}\n", steps=[0.2, 0.1, 0.05, 0.025],
                  reference=("generalized_alpha", None, 0.01), title="reduced crane, lifting, 60 s (load)"),
}
METHODS = [("generalized_alpha", None), ("implicit_rk", "arkimex:3"), ("implicit_rk", "arkimex:4"),
           ("implicit_rk", "arkimex:5"), ("implicit_rk", "rosw:ra34pw2")]


def label(integrator, method):
    return "generalized-alpha" if integrator == "generalized_alpha" else method.replace(":", " ").upper()


def run(case, integrator, method, h, workdir, reference=False):
    c = CASES[case]
    dyn = f"integrator: {integrator}, t_end: {c['t_end']}, time_step: {h}"
    if integrator == "generalized_alpha":
        # The maneuvers' settings for the crane (reuse 50, tolerance 1e-4 of the load); the
        # reference takes fresh Jacobians and a tight tolerance.
        dyn += ", rho_infinity: 0.8"
        if case == "crane" and not reference:
            dyn += ", jacobian_reuse: 50, newton_tolerance: 1e-4"
        else:
            dyn += ", newton_tolerance: 1e-9"
    else:
        dyn += f", implicit_method: \"{method}\", newton_tolerance: {1e-4 if case == 'crane' else 1e-9}"
    name = f"{case}_{integrator}_{method or 'ga'}_{h}".replace(":", "_").replace(".", "p")
    text = (f"base: {os.path.join(ROOT, c['model'])}\nsolver:\n{c['static']}  dynamics: {{{dyn}}}\n"
            f"output:\n  directory: {workdir}\n  name: {name}\n  interval: {c['interval']}\n  probes: [{c['probe']}]\n")
    path = os.path.join(workdir, name + ".yaml")
    with open(path, "w") as f:
        f.write(text)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    out = subprocess.run([BINARY, "run", path, "-assembly_threads", "1"], capture_output=True, text=True, env=env)
    m = re.search(r"dynamics completed: (\d+) steps.*?, (\d+) Newton iterations.*?wall ([0-9.e+-]+) s", out.stdout)
    if out.returncode != 0 or not m:
        raise RuntimeError(f"{name}: {out.stdout[-400:]}{out.stderr[-400:]}")
    with open(os.path.join(workdir, name + "_probes.csv")) as f:
        rows = list(csv.reader(f))[1:]
    path_ = {round(float(r[0]), 6): tuple(float(x) for x in r[1:4]) for r in rows}
    return dict(steps=int(m.group(1)), newton=int(m.group(2)), wall=float(m.group(3)), path=path_)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="docs/perf/work_precision")
    ap.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    ap.add_argument("--plot-only", action="store_true", help="draw <out>.png from an existing <out>.csv")
    args = ap.parse_args()
    results = []
    if args.plot_only:
        with open(args.out + ".csv") as f:
            for r in csv.DictReader(f):
                results.append(dict(r, h=float(r["h"]), wall=float(r["wall"]), error=float(r["error"])))
        args.cases = [c for c in CASES if any(r["case"] == c for r in results)]
        plot(results, args)
        return
    with tempfile.TemporaryDirectory() as workdir:
        for case in args.cases:
            c = CASES[case]
            ri, rm, rh = c["reference"]
            ref = run(case, ri, rm, rh, workdir, reference=True)
            for integrator, method in METHODS:
                for h in c["steps"]:
                    try:
                        r = run(case, integrator, method, h, workdir)
                    except RuntimeError as failure:  # a step too large for the method: left out, said
                        print(f"{case:8s} {label(integrator, method):18s} h={h:<8g} failed: "
                              f"{str(failure).splitlines()[0][:160]}", flush=True)
                        continue
                    common = set(r["path"]) & set(ref["path"])
                    err = max(math.dist(r["path"][t], ref["path"][t]) for t in common)
                    results.append(dict(case=case, method=label(integrator, method), h=h, steps=r["steps"],
                                        newton=r["newton"], wall=r["wall"], error=err, compared=len(common)))
                    print(f"{case:8s} {label(integrator, method):18s} h={h:<8g} steps={r['steps']:6d} "
                          f"newton={r['newton']:7d} wall={r['wall']:.4g} s error={err:.3e} m", flush=True)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(results[0]))
        w.writeheader()
        w.writerows(results)
    plot(results, args)


def plot(results, args):
    fig, axes = plt.subplots(1, len(args.cases), figsize=(5.2 * len(args.cases), 4.4))
    axes = axes if len(args.cases) > 1 else [axes]
    for ax, case in zip(axes, args.cases):
        for method in dict.fromkeys(r["method"] for r in results):
            # One line through the step sizes, largest first (a failed or cut run may cost more).
            pts = sorted(((r["wall"], r["error"], r["h"]) for r in results if r["case"] == case and r["method"] == method),
                         key=lambda p: -p[2])
            if not pts:
                continue
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=method)
        ax.set_title(CASES[case]["title"], fontsize=10)
        ax.set_xlabel("wall time of the dynamics [s], one core")
        ax.set_ylabel("largest probe error [m]")
        ax.grid(True, which="both", alpha=0.3)
        if case == "crane":
            ax.axhline(2e-3, color="gray", ls="--", lw=1)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out + ".png", dpi=120)
    print(f"wrote {args.out}.csv and {args.out}.png")


if __name__ == "__main__":
    main()
