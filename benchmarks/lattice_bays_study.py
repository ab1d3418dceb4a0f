#!/usr/bin/python3
"""Timing studies on the lattice-bays benchmark (benchmarks/lattice_bays.py), one core per rank.

  reuse:   per size, Jacobian reuse settings against fresh Jacobians every Newton iteration: time
           per step and per Newton iteration, and how far the tip's path moves from the fresh run
           (the accuracy a reuse setting keeps; probe bay<N>.e2n1, every step).
  scaling: fresh Jacobians over sizes and rank counts: time per step and per Newton iteration
           (the stepping: the dynamics' wall less its two outputs, which are a column of their
           own), setup time (process wall minus the dynamics' wall), peak memory per unknown; a
           PNG of both against the number of unknowns. --mumps adds MUMPS on several ranks.
  speedup: per size, one rank against the largest of --ranks in interleaved pairs (1, N, 1, N,
           ... --repeat times): the stepping's ratio per pair, its median and range. On a shared
           or virtual machine the speed of one run drifts by tens of per cent from hour to hour;
           pairs taken back to back see the same machine, so their ratio is the honest figure.
           Each pair records both sides' Newton iterations (newton, newton_n) and warns when
           they differ. Few steps from rest weigh the ranks' one-time preconditioner set-up:
           --steps 20 gives the per-step ratio of longer runs.

  /usr/bin/python3 benchmarks/lattice_bays_study.py reuse --bays 10 640 --reuse 1 5 10 20 --steps 100 \\
      --out docs/perf/lattice_reuse
  /usr/bin/python3 benchmarks/lattice_bays_study.py scaling --bays 40 160 640 2560 10240 40960 \\
      --ranks 1 2 --steps 3 --mumps --out docs/perf/lattice_scaling
  /usr/bin/python3 benchmarks/lattice_bays_study.py speedup --bays 10240 40960 --ranks 2 --steps 6 \\
      --repeat 3 --out docs/perf/rank_speedup

Writes <out>.csv and <out>.md (and <out>.png for scaling). Runs go to --work (default
build/lattice_study/), one folder per run; a run whose log exists is not repeated unless --fresh.
Timings are only worth something on an otherwise idle machine.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SUMMARY = re.compile(r"dynamics completed: (\d+) steps.*?, (\d+) Newton iterations.*?, (\d+) Jacobians.*?wall ([0-9.e+-]+) s"
                     r".*?(\d+) outputs in ([0-9.e+-]+) s")
MEMORY = re.compile(r"peak memory: (\d+) MiB(?: on the largest of \d+ ranks, (\d+) MiB in all)?")
UNKNOWNS = re.compile(r"(\d+) unknowns")


def run(bays, steps, reuse, ranks, interval, work, binary, fresh, extra=(), tag=""):
    name = f"bays{bays}_r{reuse}_n{ranks}_s{steps}" + (f"_{tag}" if tag else "")
    folder = os.path.join(work, name)
    os.makedirs(folder, exist_ok=True)
    model = os.path.join(folder, name + ".yaml")
    log = os.path.join(folder, "run.log")
    if fresh or not os.path.exists(log):
        subprocess.run([sys.executable, os.path.join(ROOT, "benchmarks", "lattice_bays.py"), str(bays), "--steps",
                        str(steps), "--reuse", str(reuse), "--interval", str(interval), "--out", model], check=True)
        env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        cmd = [binary, "run", model, "--output", folder, "-assembly_threads", "1"] + list(extra)
        if ranks > 1:
            cmd = ["mpiexec", "-n", str(ranks), "--oversubscribe", "--bind-to", "none"] + cmd
        start = time.monotonic()
        p = subprocess.run(cmd, env=env, capture_output=True, text=True)
        wall = time.monotonic() - start
        with open(log, "w") as f:
            f.write(p.stdout + p.stderr + f"\nprocess wall {wall:.3f} s\n")
        if p.returncode != 0:
            sys.exit(f"{name} failed (exit {p.returncode}); see {log}")
    text = open(log).read()
    m = SUMMARY.search(text)
    if not m:
        sys.exit(f"{name}: no dynamics summary in {log}")
    st, newton, jac, wall = int(m.group(1)), int(m.group(2)), int(m.group(3)), float(m.group(4))
    # The outputs (written by rank 0 alone, within the dynamics' wall) apart from the stepping.
    outputs, output_s = int(m.group(5)), float(m.group(6))
    stepping = wall - output_s
    mem = MEMORY.search(text)
    peak = float(mem.group(1)) if mem else float("nan")
    total = float(mem.group(2)) if mem and mem.group(2) else peak
    process = float(re.search(r"process wall ([0-9.]+) s", text).group(1))
    unknowns = bays * 24
    solver = re.search(r"linear solver: ([^,\n]*)", text)
    return dict(bays=bays, unknowns=unknowns, ranks=ranks, solver=solver.group(1) if solver else "?", reuse=reuse, steps=st, newton=newton, jacobians=jac,
                wall_s=wall, ms_per_step=1e3 * wall / st, ms_per_iteration=1e3 * wall / newton,
                stepping_ms_per_step=1e3 * stepping / st, stepping_ms_per_iteration=1e3 * stepping / newton,
                outputs=outputs, ms_per_output=1e3 * output_s / max(outputs, 1),
                setup_s=process - wall, peak_mib_largest=peak, peak_mib_total=total,
                bytes_per_unknown=total * 2**20 / unknowns, probes=os.path.join(folder, name + "_probes.csv"))


def tip_path(probes):
    """Times and positions of the probe (the tip node) from the run's probe table."""
    # Columns by position: time, then x, y, z of the probe (the header carries units, "tip.x [m]").
    data = np.genfromtxt(probes, delimiter=",", skip_header=1, ndmin=2)
    return data[:, 0], data[:, 1:4]


def reuse_study(a):
    rows = []
    for bays in a.bays:
        ref = None
        for reuse in a.reuse:
            r = run(bays, a.steps, reuse, 1, 0.01, a.work, a.binary, a.fresh)
            t, p = tip_path(r["probes"])
            if ref is None:
                ref = (t, p)
                r["tip_deviation_mm"] = 0.0
            else:
                n = min(len(t), len(ref[0]))
                r["tip_deviation_mm"] = 1e3 * float(np.max(np.linalg.norm(p[:n] - ref[1][:n], axis=1)))
            r["tip_travel_mm"] = 1e3 * float(np.max(np.linalg.norm(ref[1] - ref[1][0], axis=1)))
            rows.append(r)
            print(f"{bays} bays, reuse {reuse}: {r['ms_per_step']:.3f} ms/step, {r['ms_per_iteration']:.3f} ms/iteration, "
                  f"{r['newton'] / r['steps']:.2f} iterations and {r['jacobians']} Jacobians, tip {r['tip_deviation_mm']:.2e} mm "
                  f"from the fresh run (travel {r['tip_travel_mm']:.1f} mm)")
    keys = ["bays", "unknowns", "reuse", "steps", "newton", "jacobians", "wall_s", "ms_per_step", "ms_per_iteration",
            "tip_deviation_mm", "tip_travel_mm"]
    write_table(a.out, rows, keys)


def scaling_study(a):
    rows = []
    # The default solvers on every rank count, and on several ranks also MUMPS (-pc_type lu), the
    # distributed direct solver the additive Schwarz default replaced for models without constraints.
    series = [(ranks, (), "") for ranks in a.ranks]
    if a.mumps:
        series += [(ranks, ("-pc_type", "lu"), "mumps") for ranks in a.ranks if ranks > 1]
    for bays in a.bays:
        for ranks, extra, tag in series:
            r = run(bays, a.steps, 1, ranks, 1000.0, a.work, a.binary, a.fresh, extra, tag)
            # Per step and per iteration: the stepping alone; the two outputs (first and last
            # step) in their own column, as they are written by rank 0 alone.
            r["ms_per_step"], r["ms_per_iteration"] = r["stepping_ms_per_step"], r["stepping_ms_per_iteration"]
            rows.append(r)
            print(f"{bays} bays ({r['unknowns']} unknowns), {ranks} rank(s), {r['solver']}: {r['ms_per_step']:.1f} ms/step, "
                  f"{r['ms_per_iteration']:.1f} ms/iteration, {r['ms_per_output']:.0f} ms/output, setup {r['setup_s']:.2f} s, "
                  f"{r['bytes_per_unknown']:.0f} B/unknown")
    keys = ["bays", "unknowns", "ranks", "solver", "steps", "newton", "wall_s", "ms_per_step", "ms_per_iteration",
            "outputs", "ms_per_output", "setup_s",
            "peak_mib_largest", "peak_mib_total", "bytes_per_unknown"]
    write_table(a.out, rows, keys)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    for ranks, solver in sorted(set((r["ranks"], r["solver"]) for r in rows)):
        sel = sorted((r for r in rows if r["ranks"] == ranks and r["solver"] == solver), key=lambda r: r["unknowns"])
        n = [r["unknowns"] for r in sel]
        what = f"{ranks} rank(s), {solver}"
        ax[0].loglog(n, [r["ms_per_step"] / 1e3 for r in sel], "o-", label=f"per step, {what}")
        ax[0].loglog(n, [r["ms_per_iteration"] / 1e3 for r in sel], "s--", label=f"per Newton iteration, {what}")
        ax[1].loglog(n, [r["setup_s"] for r in sel], "o-", label=what)
        ax[2].semilogx(n, [r["bytes_per_unknown"] / 1024 for r in sel], "o-", label=f"{what}, all ranks")
    n = np.array(sorted(set(r["unknowns"] for r in rows)), dtype=float)
    base = min(rows, key=lambda r: r["unknowns"])
    ax[0].loglog(n, base["ms_per_step"] / 1e3 * n / n[0], "k:", label="linear")
    ax[0].set(xlabel="unknowns", ylabel="wall (s)", title="fresh Jacobians, h = 0.01 s, outputs excluded")
    ax[1].set(xlabel="unknowns", ylabel="setup (s)", title="process start to first step")
    ax[2].set(xlabel="unknowns", ylabel="peak memory (KiB per unknown)", title="peak resident memory")
    for x in ax:
        x.grid(True, which="both", alpha=0.3)
        x.legend(fontsize=7, loc="upper left")
    fig.suptitle("lattice-bays, one core per rank")
    fig.tight_layout()
    fig.savefig(a.out + ".png", dpi=110)
    print(f"wrote {a.out}.png")


def speedup_study(a):
    ranks = max(a.ranks)
    if ranks < 2:
        sys.exit("speedup study: --ranks needs a count above 1")
    rows, summary = [], []
    for bays in a.bays:
        ratios = []
        for rep in range(a.repeat):
            # Always rerun: a pair is only worth something if both halves ran back to back.
            one = run(bays, a.steps, 1, 1, 1000.0, a.work, a.binary, True, tag=f"pair{rep}")
            many = run(bays, a.steps, 1, ranks, 1000.0, a.work, a.binary, True, tag=f"pair{rep}")
            s1 = one["stepping_ms_per_step"]
            sn = many["stepping_ms_per_step"]
            ratios.append(s1 / sn)
            # A pair compares like with like only if both sides took the same Newton iterations.
            if many["newton"] != one["newton"]:
                print(f"{bays} bays, pair {rep + 1}: {one['newton']} Newton iterations on 1 rank, {many['newton']} on "
                      f"{ranks}: the ratio mixes solver work with speed", file=sys.stderr)
            rows.append(dict(bays=bays, unknowns=one["unknowns"], pair=rep + 1, ranks=ranks, newton=one["newton"],
                             newton_n=many["newton"], ms_per_step_1=s1, ms_per_step_n=sn, speedup=s1 / sn))
            print(f"{bays} bays ({one['unknowns']} unknowns), pair {rep + 1}: {s1:.1f} ms/step on 1 rank, {sn:.1f} on "
                  f"{ranks}: {s1 / sn:.3f} x")
        summary.append((one["unknowns"], float(np.median(ratios)), min(ratios), max(ratios)))
    write_table(a.out, rows,
                ["bays", "unknowns", "pair", "ranks", "newton", "newton_n", "ms_per_step_1", "ms_per_step_n", "speedup"])
    with open(a.out + ".md", "a") as f:
        f.write(f"\n| unknowns | {ranks} ranks against 1: median | min | max | pairs |\n| --- | --- | --- | --- | --- |\n")
        for unknowns, med, lo, hi in summary:
            f.write(f"| {unknowns:,} | {med:.3f} | {lo:.3f} | {hi:.3f} | {a.repeat} |\n")
    for unknowns, med, lo, hi in summary:
        print(f"{unknowns} unknowns: {ranks} ranks {med:.3f} x faster than 1 (median of {a.repeat} pairs; {lo:.3f}-{hi:.3f})")


def write_table(out, rows, keys):
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    with open(out + ".md", "w") as f:
        f.write("| " + " | ".join(keys) + " |\n| " + " | ".join("---" for _ in keys) + " |\n")
        for r in rows:
            f.write("| " + " | ".join(f"{r[k]:.4g}" if isinstance(r[k], float) else str(r[k]) for k in keys) + " |\n")
    print(f"wrote {out}.csv, {out}.md")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("study", choices=["reuse", "scaling", "speedup"])
    ap.add_argument("--bays", type=int, nargs="+", required=True)
    ap.add_argument("--reuse", type=int, nargs="+", default=[1, 5, 10, 20], help="reuse study: the first is the reference")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1])
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--out", required=True, help="path without extension")
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "lattice_study"))
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "drivers", "latticedyn"))
    ap.add_argument("--fresh", action="store_true", help="rerun even where a log exists")
    ap.add_argument("--repeat", type=int, default=5, help="speedup study: interleaved pairs per size")
    ap.add_argument("--mumps", action="store_true", help="scaling study: also MUMPS (-pc_type lu) on several ranks")
    a = ap.parse_args()
    if a.study == "reuse" and a.reuse[0] != 1:
        ap.error("the reuse study's first setting is the reference: 1")
    {"reuse": reuse_study, "scaling": scaling_study, "speedup": speedup_study}[a.study](a)


if __name__ == "__main__":
    main()
