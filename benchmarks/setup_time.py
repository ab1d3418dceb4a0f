#!/usr/bin/python3
"""Model setup time against model size on the lattice-bays benchmark (benchmarks/lattice_bays.py).

For each size: `latticedyn check` on one process, and `latticedyn run` up to its first time step
(-ts_max_steps 0) on each rank count asked for. Records the process wall, the stages the program
reports in its `setup:` line (YAML parse, model building, numbering and assembly plan, results
file; the slowest rank's), the rest (start-up of MPI and PETSc, the initial state, tearing down)
and the peak memory; writes <out>.csv, <out>.md and <out>.png (setup time and time per unknown
against the number of unknowns).

  /usr/bin/python3 benchmarks/setup_time.py --bays 10 40 160 640 2560 10240 40960 --ranks 1 2 \\
      --out docs/perf/setup_time

Models and logs go to --work (default build/setup_study/). Timings are only worth something on an
otherwise idle machine.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SETUP = re.compile(r"setup: parse ([0-9.e+-]+) s, model ([0-9.e+-]+) s, numbering and assembly plan ([0-9.e+-]+) s"
                   r"(?:, results file ([0-9.e+-]+) s)?")
MEMORY = re.compile(r"peak memory: (\d+) MiB")
DOFS = re.compile(r"(\d+) free DoFs")


def run(cmd, env):
    start = time.monotonic()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.monotonic() - start
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed (exit {p.returncode}):\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return p.stdout + p.stderr, wall


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bays", type=int, nargs="+", default=[10, 40, 160, 640, 2560, 10240, 40960])
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "perf", "setup_time"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "setup_study"))
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "drivers", "latticedyn"))
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    rows = []
    for bays in args.bays:
        model = os.path.join(args.work, f"bays{bays}.yaml")
        subprocess.run([sys.executable, os.path.join(ROOT, "benchmarks", "lattice_bays.py"), str(bays), "--steps", "1",
                        "--out", model], check=True)
        cases = [("check", 1, [args.binary, "check", model])]
        for ranks in args.ranks:
            cmd = [args.binary, "run", model, "--output", os.path.join(args.work, f"out{bays}_n{ranks}"),
                   "-assembly_threads", "1", "-ts_max_steps", "0"]
            if ranks > 1:
                cmd = ["mpiexec", "-n", str(ranks), "--oversubscribe", "--bind-to", "none"] + cmd
            cases.append(("run to the first step", ranks, cmd))
        for what, ranks, cmd in cases:
            text, wall = run(cmd, env)
            m = SETUP.search(text)
            dofs = int(DOFS.search(text).group(1))
            mem = MEMORY.search(text)
            parse, build, numbering = (float(m.group(i)) for i in (1, 2, 3))
            results = float(m.group(4)) if m.group(4) else 0.0
            rows.append(dict(bays=bays, unknowns=dofs, what=what, ranks=ranks, wall=wall, parse=parse, build=build,
                             numbering=numbering, results=results,
                             rest=wall - parse - build - numbering - results,
                             us_per_unknown=1e6 * (parse + build + numbering + results) / dofs,
                             peak_mib=int(mem.group(1)) if mem else ""))
            print(f"{bays} bays ({dofs} unknowns), {what}, {ranks} rank(s): {wall:.2f} s (parse {parse:.2f}, "
                  f"model {build:.2f}, numbering {numbering:.2f}, results {results:.2f})", flush=True)
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    keys = ["bays", "unknowns", "what", "ranks", "wall", "parse", "build", "numbering", "results", "rest",
            "us_per_unknown", "peak_mib"]
    with open(args.out + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: r[k] for k in keys})
    with open(args.out + ".md", "w") as f:
        f.write("| bays | unknowns | command | ranks | wall (s) | parse (s) | model (s) | numbering and assembly plan (s) "
                "| results file (s) | rest (s) | setup per unknown (µs) | peak memory (MiB) |\n")
        f.write("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n")
        for r in rows:
            f.write(f"| {r['bays']} | {r['unknowns']} | {r['what']} | {r['ranks']} | {r['wall']:.2f} | {r['parse']:.3g} | "
                    f"{r['build']:.3g} | {r['numbering']:.3g} | {r['results']:.3g} | {r['rest']:.2f} | "
                    f"{r['us_per_unknown']:.1f} | {r['peak_mib']} |\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        for (what, ranks), style in zip(sorted({(r["what"], r["ranks"]) for r in rows}), ["o-", "s--", "^:", "d-."]):
            sel = sorted((r for r in rows if r["what"] == what and r["ranks"] == ranks), key=lambda r: r["unknowns"])
            label = f"{what}, {ranks} rank{'s' if ranks > 1 else ''}"
            ax[0].loglog([r["unknowns"] for r in sel], [r["wall"] for r in sel], style, label=label)
            ax[1].semilogx([r["unknowns"] for r in sel], [r["us_per_unknown"] for r in sel], style, label=label)
        ax[0].set(xlabel="unknowns", ylabel="process wall (s)", title="setup of the lattice-bays model")
        ax[1].set(xlabel="unknowns", ylabel="setup stages per unknown (µs)",
                  title="parse + model + numbering + results file")
        ax[1].set_ylim(bottom=0)
        for a in ax:
            a.grid(True, which="both", alpha=0.3)
            a.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.out + ".png", dpi=110)
    except ImportError:
        pass
    print(f"wrote {args.out}.csv, .md, .png")


if __name__ == "__main__":
    main()
