#!/usr/bin/python3
"""Plots the probe CSV of a latticedyn run (joint positions and velocities over time) to a PNG.

    /usr/bin/python3 scripts/plot_probes.py results/double_pendulum/double_pendulum_probes.csv \
        --output docs/images/double_pendulum_probes.png

One row of panels per probe joint: position components on the left, velocities on the right.
Columns are found by name, with or without a unit in the header ("load.1.x [m]" or "load.1.x"):
the units come from the header where it has them, otherwise they are the format's (s, m, m/s;
docs/output-format.md).
"""
import argparse
import csv
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

UNIT = re.compile(r"^(.*?)\s*\[([^\]]*)\]$")  # "load.1.vx [m/s]": name, unit


def format_unit(name):
    """The unit of a column by the format, for a header without units: time in s, the joint's
    position .x .y .z in m, its velocity .vx .vy .vz in m/s."""
    if name == "time":
        return "s"
    return "m/s" if name.rsplit(".", 1)[-1].startswith("v") else "m"


def read(path):
    """The probe table as {name: values} and {name: unit}, names without their unit."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    cols, units = {}, {}
    for i, column in enumerate(rows[0]):
        m = UNIT.match(column)
        name = m.group(1) if m else column
        units[name] = m.group(2) if m else format_unit(name)
        cols[name] = [float(r[i]) for r in rows[1:]]
    return cols, units


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("csv")
    p.add_argument("--output", required=True)
    p.add_argument("--title", default=None)
    a = p.parse_args()
    cols, units = read(a.csv)
    t = cols["time"]
    # A circuit's columns after the joints: pressures ("node.p [Pa]") and flows ("valve.Q [m^3/s]")
    # in one row of panels, the energy account ("... [J]") in another.
    pressures = [name for name in cols if name.endswith(".p")]
    flows = [name for name in cols if units[name] == "m^3/s"]
    works = [name for name in cols if units[name] == "J"]
    hydraulic = set(pressures) | set(flows) | set(works)
    joints = list(dict.fromkeys(name.rsplit(".", 1)[0] for name in cols if name != "time" and name not in hydraulic))
    extra = (1 if pressures or flows else 0) + (1 if works else 0)
    rows = len(joints) + extra
    fig, axes = plt.subplots(rows, 2, figsize=(11, 3.2 * rows), squeeze=False, sharex=True)
    row = len(joints)
    if pressures or flows:
        left, right = axes[row]
        for name in pressures:
            left.plot(t, [x / 1e5 for x in cols[name]], label=name[:-2])
        left.set_ylabel("pressure [bar]" if pressures and units[pressures[0]] == "Pa" else "pressure")
        for name in flows:
            right.plot(t, [q * 6e4 for q in cols[name]], label=name)
        right.set_ylabel("flow [l/min]")
        row += 1
    if works:
        left, right = axes[row]
        for name in works:
            (right if name.startswith("energy imbalance") else left).plot(t, [w / 1e3 for w in cols[name]], label=name)
        left.set_ylabel("work, energy change [kJ]")
        right.set_ylabel("energy imbalance [kJ]")
    for r in range(len(joints), rows):
        for ax in axes[r]:
            if ax.lines:
                ax.grid(True, alpha=0.3)
                ax.legend(loc="best", fontsize=7)
            else:
                ax.axis("off")
    for row, joint in enumerate(joints):
        for c in "xyz":
            axes[row][0].plot(t, cols[f"{joint}.{c}"], label=c)
            axes[row][1].plot(t, cols[f"{joint}.v{c}"], label="v" + c)
        axes[row][0].set_ylabel(f"{joint} position [{units[joint + '.x']}]")
        axes[row][1].set_ylabel(f"{joint} velocity [{units[joint + '.vx']}]")
        for ax in axes[row]:
            ax.grid(True, alpha=0.3)
            ax.legend(loc="upper right", fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel(f"time [{units['time']}]")
        ax.tick_params(labelbottom=True)
    fig.suptitle(a.title or a.csv)
    fig.tight_layout()
    fig.savefig(a.output, dpi=110)
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
