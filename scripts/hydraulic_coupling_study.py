#!/usr/bin/env python3
"""Monolithic solve against co-simulation of a hydraulic circuit and its mechanism.

Runs examples/hydraulics/luffing_cylinder.yaml (or --model) with the circuit and the mechanism as one
implicit system and as a co-simulation at several coupling steps, all at the model's time step,
and compares each run's boom tip path (--probe) with a monolithic reference at a fine time step:
largest distance over the run, the energy account's imbalance and the Newton iterations (time the
runs with farm-bench --vs: one run's wall time on a shared machine says little).
Writes a Markdown table (stdout and --table) and a PNG of the tip paths' error over time.

  /usr/bin/python3 scripts/hydraulic_coupling_study.py --latticedyn build/drivers/latticedyn \
      --output docs/images/hydraulic_coupling.png --table docs/hydraulic_coupling_table.md
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def run(latticedyn, model, directory, dynamics):
    """Runs `model` with solver.dynamics replaced by `dynamics` (a YAML flow map); returns the probe
    CSV's columns and the numbers of the run's summary."""
    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, "model.yaml")
    with open(path, "w") as f:
        f.write(f"base: {os.path.abspath(model)}\nsolver:\n  dynamics: {dynamics}\n")
    out = subprocess.run([latticedyn, "run", path, "--output", directory], capture_output=True, text=True)
    text = out.stdout + out.stderr
    summary = {"failed": out.returncode != 0, "text": text}
    m = re.search(r"(\d+) Newton iterations", text)
    if m:
        summary["newton"] = int(m.group(1))
    m = re.search(r"imbalance [-0-9.e+]+ J \(([-0-9.e+]+) of the largest term", text)
    if m:
        summary["imbalance"] = float(m.group(1))
    probes = [os.path.join(directory, f) for f in os.listdir(directory) if f.endswith("_probes.csv")]
    columns = {}
    if probes:
        with open(probes[0]) as f:
            rows = list(csv.reader(f))
        for k, name in enumerate(rows[0]):
            columns[name] = [float(r[k]) for r in rows[1:]]
    return columns, summary


def path_error(columns, reference, probe):
    """Largest distance of the probe's path from the reference's at the common output times."""
    times = {round(t, 9): i for i, t in enumerate(reference["time [s]"])}
    errors = []
    for i, t in enumerate(columns.get("time [s]", [])):
        j = times.get(round(t, 9))
        if j is None:
            continue
        d2 = sum((columns[f"{probe}.{c} [m]"][i] - reference[f"{probe}.{c} [m]"][j]) ** 2 for c in "xyz")
        errors.append((t, d2**0.5))
    return errors


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--latticedyn", default="build/drivers/latticedyn")
    p.add_argument("--model", default="examples/hydraulics/luffing_cylinder.yaml")
    p.add_argument("--probe", default="boom.tip")
    p.add_argument("--time-step", type=float, default=0.005)
    p.add_argument("--rho-infinity", type=float, default=0.8)
    p.add_argument("--t-end", type=float, default=12.0)
    p.add_argument("--coupling-steps", default="0.005,0.01,0.02,0.03,0.04")
    p.add_argument("--output", default="hydraulic_coupling.png")
    p.add_argument("--table", default="")
    args = p.parse_args()

    work = tempfile.mkdtemp(prefix="coupling_")
    common = f"t_end: {args.t_end}, rho_infinity: {args.rho_infinity}"
    reference, ref_summary = run(args.latticedyn, args.model, os.path.join(work, "reference"),
                                 f"{{{common}, time_step: {args.time_step / 8}}}")
    if ref_summary["failed"]:
        sys.exit("the reference run failed:\n" + ref_summary["text"])
    runs = [("monolithic", f"{{{common}, time_step: {args.time_step}}}")]
    for H in args.coupling_steps.split(","):
        runs.append((f"co-simulation, H = {H} s", f"{{{common}, time_step: {args.time_step}, "
                                                     f"hydraulic_coupling: cosimulation, coupling_step: {H}}}"))
    lines = [f"| solve (h = {args.time_step} s) | largest {args.probe} path error (m) | energy imbalance | "
             "Newton iterations |", "| --- | --- | --- | --- |"]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for k, (label, dynamics) in enumerate(runs):
        columns, s = run(args.latticedyn, args.model, os.path.join(work, f"run{k}"), dynamics)
        errors = path_error(columns, reference, args.probe)
        if s["failed"]:
            last = errors[-1][0] if errors else 0.0
            lines.append(f"| {label} | unstable: failed at t = {last:.2f} s | | |")
            continue
        worst = max(e for _, e in errors)
        lines.append(f"| {label} | {worst:.2e} | {s.get('imbalance', float('nan')):.1e} | {s.get('newton', 0)} |")
        ax.semilogy([t for t, _ in errors], [max(e, 1e-12) for _, e in errors], label=label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"|{args.probe} - reference| [m]")
    ax.set_title(f"Monolithic against co-simulation ({os.path.basename(args.model)}; reference h = "
                 f"{args.time_step / 8:g} s)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    table = "\n".join(lines) + "\n"
    print(table, end="")
    if args.table:
        with open(args.table, "w") as f:
            f.write(table)


if __name__ == "__main__":
    main()
