#!/usr/bin/python3
"""Plots the probe CSV of a latticedyn run (joint positions and velocities over time) to a PNG.

    /usr/bin/python3 scripts/plot_probes.py results/double_pendulum/double_pendulum_probes.csv \
        --output docs/images/double_pendulum_probes.png

One row of panels per probe joint: position components on the left, velocities on the right.
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("csv")
    p.add_argument("--output", required=True)
    p.add_argument("--title", default=None)
    a = p.parse_args()
    with open(a.csv, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], [[float(x) for x in r] for r in rows[1:]]
    cols = {name: [r[i] for r in data] for i, name in enumerate(header)}
    t = cols["time"]
    joints = list(dict.fromkeys(name.rsplit(".", 1)[0] for name in header[1:]))
    fig, axes = plt.subplots(len(joints), 2, figsize=(11, 3.2 * len(joints)), squeeze=False, sharex=True)
    for row, joint in enumerate(joints):
        for c in "xyz":
            axes[row][0].plot(t, cols[f"{joint}.{c}"], label=c)
            axes[row][1].plot(t, cols[f"{joint}.v{c}"], label="v" + c)
        axes[row][0].set_ylabel(f"{joint} position [m]")
        axes[row][1].set_ylabel(f"{joint} velocity [m/s]")
        for ax in axes[row]:
            ax.grid(True, alpha=0.3)
            ax.legend(loc="upper right", fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    fig.suptitle(a.title or a.csv)
    fig.tight_layout()
    fig.savefig(a.output, dpi=110)
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
