#!/usr/bin/python3
"""Step size and Jacobian reuse against accuracy for the crane's maneuvers (thesis 8.3).

Runs each maneuver with a reference setting (h = 0.01 s, a fresh Jacobian every Newton iteration)
and with the variants asked for, on one core, and compares with the reference at common output
times:
  - the load's path (probe load.1): the largest distance from the reference path;
  - rope forces: per rope element, the largest |N - N_ref| over the run relative to its largest
    reference force (pointwise in time), and the error of the largest force over the run (the
    peak a rope is sized for); the worst rope element is reported for each;
  - member forces (every drawn member: the super truss members, strut ties, rope elements): the
    largest |N - N_ref| relative to the largest reference member force.
Writes <out>/<name>.csv and <name>.md (a table per maneuver) and <name>.png (--name, default
step_study).

  /usr/bin/python3 scripts/crane_step_study.py --out docs/crane \
      --maneuvers lifting luffing slewing combined --variants 0.05:50 0.05:50::1e-6 0.1:50 0.2:50 0.05:1 0.1:1
Variants are h:reuse[:rho_infinity[:newton_tolerance]] (an empty field keeps the maneuver file's
value); the reference runs once per maneuver and is kept in build/step_study/ (delete it to
recompute). --reference 0.0025:1::1e-6 --name step_study_converged measures the same against a
4 times finer run, which shows how far the h = 0.01 s run itself is from the converged answer.
Rope forces are compared pointwise, as --window-second moving averages (the force
without the rope and boom vibration near 2 and 4 Hz) and by their peaks.
"""
import argparse
import csv
import os
import re
import subprocess
import sys

import h5py
import numpy as np
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SUMMARY = re.compile(r"dynamics completed: (\d+) steps.*?, (\d+) Newton iterations.*?, (\d+) Jacobians.*?wall ([0-9.e+]+) s")


def maneuver_solver(path):
    """The solver section a maneuver file uses (its own or its base's: a top-level key replaces the base's)."""
    with open(path) as f:
        doc = yaml.safe_load(f)
    if "solver" in doc:
        return doc["solver"]
    return maneuver_solver(os.path.join(os.path.dirname(path), doc["base"]))


def run(maneuver, h, reuse, rho, tol, work, binary, interval, full):
    name = (f"{maneuver}{'_full' if full else ''}_h{h}_r{reuse}" + (f"_rho{rho}" if rho is not None else "") +
            (f"_tol{tol}" if tol is not None else ""))
    folder = os.path.join(work, name)
    os.makedirs(folder, exist_ok=True)
    model = os.path.join(folder, name + ".yaml")
    base = os.path.join(ROOT, "examples", "crane", f"{maneuver}{'_full' if full else ''}.yaml")
    solver = maneuver_solver(base)
    solver["dynamics"].update(time_step=h, jacobian_reuse=reuse)
    if rho is not None:
        solver["dynamics"]["rho_infinity"] = rho
    if tol is not None:
        solver["dynamics"]["newton_tolerance"] = tol
    with open(model, "w") as f:
        yaml.safe_dump({"base": base, "solver": solver,
                        "output": {"directory": folder, "name": "run", "interval": interval, "probes": ["load.1"]}},
                       f, default_flow_style=None)
    h5 = os.path.join(folder, "run.h5")
    log = os.path.join(folder, "run.log")
    if not os.path.exists(h5) or not os.path.exists(log):
        env = dict(os.environ, OMP_NUM_THREADS="1")
        out = subprocess.run([binary, "run", model, "-assembly_threads", "1"], capture_output=True, text=True, env=env)
        with open(log, "w") as f:
            f.write(out.stdout + out.stderr)
        if out.returncode != 0:
            sys.exit(f"{model}: exit {out.returncode}\n{out.stdout[-2000:]}\n{out.stderr[-2000:]}")
    text = open(log).read()
    m = SUMMARY.search(text)
    steps, newton, jac, wall = (int(m.group(1)), int(m.group(2)), int(m.group(3)), float(m.group(4)))
    return h5, dict(steps=steps, newton=newton, jacobians=jac, wall=wall)


def load(h5):
    with h5py.File(h5, "r") as f:
        t = f["time"][:]
        types = [x.decode() for x in f["model/element_types"][:]]
        ropes = [i for i, x in enumerate(types) if x == "rope"]
        axial = f["elements/axial_force"][:]
        members = f["viz/axial_force"][:]
    with open(h5.replace(".h5", "_probes.csv"), newline="") as f:
        rows = list(csv.reader(f))
    # Header entries with or without their unit: "load.1.x [m]" or "load.1.x".
    names = [re.sub(r"\s*\[[^\]]*\]$", "", n) for n in rows[0]]
    cols = [names.index(f"load.1.{c}") for c in "xyz"]
    load_path = np.array([[float(r[i]) for i in cols] for r in rows[1:]])
    return t, load_path, axial[:, ropes], members


def moving_average(x, t, window):
    """Centred moving average over `window` seconds of the rows of x (samples at times t)."""
    out = np.empty_like(x)
    for k, tk in enumerate(t):
        sel = np.abs(t - tk) <= 0.5 * window + 1e-9
        out[k] = x[sel].mean(axis=0)
    return out


def compare(ref, run, window):
    t0, p0, r0, m0 = ref
    t1, p1, r1, m1 = run
    # Common output times (the coarser run's); times agree to round-off.
    idx0 = [int(np.argmin(np.abs(t0 - t))) for t in t1]
    keep = [k for k, i in enumerate(idx0) if abs(t0[i] - t1[k]) < 1e-9]
    i0 = [idx0[k] for k in keep]
    path = np.max(np.linalg.norm(p1[keep] - p0[i0], axis=1))
    peak = np.maximum(np.max(np.abs(r0), axis=0), 1e-300)
    rope = np.max(np.max(np.abs(r1[keep] - r0[i0]), axis=0) / peak)
    # The ropes' force without the vibration above 1/window Hz (the rope and boom modes near
    # 2 and 4 Hz, whose phase neither a coarse step nor the reference resolves).
    tk = t1[keep]
    smooth = np.max(np.max(np.abs(moving_average(r1[keep], tk, window) - moving_average(r0[i0], tk, window)), axis=0)
                    / peak)
    rope_peak = np.max(np.abs(np.max(np.abs(r1), axis=0) - peak) / peak)
    member = np.max(np.abs(m1[keep] - m0[i0])) / max(np.max(np.abs(m0)), 1e-300)
    return path, rope, smooth, rope_peak, member


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "crane"))
    ap.add_argument("--maneuvers", nargs="+", default=["lifting", "luffing", "slewing", "combined"])
    ap.add_argument("--variants", nargs="+", default=["0.05:50", "0.1:50", "0.2:50", "0.05:1", "0.1:1"])
    ap.add_argument("--reference", default="0.01:1::1e-6", help="h:reuse[:rho[:tol]] of the reference run")
    ap.add_argument("--interval", type=float, default=0.2, help="output interval of every run (s)")
    ap.add_argument("--window", type=float, default=1.0, help="moving-average window of the smoothed rope forces (s)")
    ap.add_argument("--full", action="store_true", help="the full crane instead of the reduced one")
    ap.add_argument("--name", default="step_study", help="file name (without extension) of the table and plot")
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "step_study"))
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "drivers", "latticedyn"))
    args = ap.parse_args()

    def parse(v):
        parts = v.split(":")
        opt = [float(x) if x else None for x in parts[2:]] + [None, None]
        return float(parts[0]), int(parts[1]), opt[0], opt[1]

    rows = []
    reference = parse(args.reference)
    for man in args.maneuvers:
        h, r, rho, tol = reference
        ref_h5, ref_cost = run(man, h, r, rho, tol, args.work, args.binary, args.interval, args.full)
        ref = load(ref_h5)
        rows.append(dict(maneuver=man, h=h, reuse=r, rho=rho or "", tol=tol or "", path_mm=0.0, rope_pct=0.0,
                         smooth_pct=0.0, peak_pct=0.0, member_pct=0.0, **ref_cost))
        for v in args.variants:
            h, r, rho, tol = parse(v)
            h5, cost = run(man, h, r, rho, tol, args.work, args.binary, args.interval, args.full)
            path, rope, smooth, rope_peak, member = compare(ref, load(h5), args.window)
            rows.append(dict(maneuver=man, h=h, reuse=r, rho=rho or "", tol=tol or "", path_mm=1e3 * path,
                             rope_pct=100 * rope, smooth_pct=100 * smooth, peak_pct=100 * rope_peak,
                             member_pct=100 * member, **cost))
            print(f"{man} h={h} reuse={r} tol={tol}: load path {1e3 * path:.3f} mm, ropes {100 * rope:.3f} % "
                  f"({args.window:g} s mean {100 * smooth:.3f} %, peak {100 * rope_peak:.3f} %), members "
                  f"{100 * member:.3f} %, {cost['wall']:.2f} s", flush=True)
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, args.name + ("_full" if args.full else ""))
    keys = ["maneuver", "h", "reuse", "rho", "tol", "steps", "newton", "jacobians", "wall", "path_mm", "rope_pct",
            "smooth_pct", "peak_pct", "member_pct"]
    with open(stem + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for row in rows:
            w.writerow({k: row[k] for k in keys})
    with open(stem + ".md", "w") as f:
        f.write("| maneuver | h (s) | reuse | rho_inf | Newton tol. | steps | Newton | Jacobians | wall (s) | "
                f"load path (mm) | rope forces (%) | ropes, {args.window:g} s mean (%) | rope peak (%) | members (%) |\n")
        f.write("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n")
        for row in rows:
            f.write(f"| {row['maneuver']} | {row['h']} | {row['reuse']} | {row['rho'] or 'file'} | {row['tol'] or 'file'} | "
                    f"{row['steps']} | {row['newton']} | {row['jacobians']} | {row['wall']:.2f} | {row['path_mm']:.3f} | "
                    f"{row['rope_pct']:.3f} | {row['smooth_pct']:.3f} | {row['peak_pct']:.3f} | {row['member_pct']:.3f} |\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
        for c, man in enumerate(args.maneuvers):
            # The maneuver files' own settings (Jacobian reuse, Newton tolerance) at each step size.
            sel = [r for r in rows if r["maneuver"] == man and r["path_mm"] > 0 and r["reuse"] > 1 and not r["tol"]]
            sel.sort(key=lambda r: r["h"])
            if not sel:
                continue
            color = f"C{c}"
            hs = [r["h"] for r in sel]
            ax[0].loglog(hs, [r["path_mm"] for r in sel], "o-", color=color, label=man)
            ax[1].loglog(hs, [r["rope_pct"] for r in sel], "o-", color=color, label=man + " pointwise")
            ax[1].loglog(hs, [max(r["smooth_pct"], 1e-4) for r in sel], "^:", color=color,
                         label=f"{man} {args.window:g} s mean")
            ax[1].loglog(hs, [max(r["peak_pct"], 1e-4) for r in sel], "s--", color=color, label=man + " peak")
            # Runs with fresh Jacobians and a tolerance of their own (a reference-like setting).
            fresh = [r for r in rows if r["maneuver"] == man and r["path_mm"] > 0 and r["reuse"] == 1 and r["tol"]]
            if fresh:
                ax[1].loglog([r["h"] for r in fresh], [r["rope_pct"] for r in fresh], "*", ms=11, color=color,
                             label=man + " fresh Jacobians")
        ax[0].axhline(2.0, color="k", ls="--", lw=0.8)
        ax[1].axhline(0.5, color="k", ls="--", lw=0.8)
        ax[0].set(xlabel="time step h (s)", ylabel="load path error (mm)", title=f"load path vs. h = {reference[0]:g} s, fresh Jacobians")
        ax[1].set(xlabel="time step h (s)", ylabel="rope force error (% of peak)", title="rope forces")
        for a in ax:
            a.grid(True, which="both", alpha=0.3)
            a.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(stem + ".png", dpi=110)
    except ImportError:
        pass
    print(f"wrote {stem}.csv, .md, .png")


if __name__ == "__main__":
    main()
