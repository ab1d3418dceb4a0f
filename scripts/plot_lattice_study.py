#!/usr/bin/python3
"""Draws the figures and the README of a super truss reduction-accuracy study (thesis 8.2).

    /usr/bin/python3 scripts/plot_lattice_study.py DIR [TITLE]

DIR holds the tables a `lattice_reduction` study writes (scripts/verification-studies.sh):
statics.csv, mass.csv, modes.csv, members.csv, cost.csv, dynamics_series.csv, summary.csv and
lattice.md. This script only draws and collects; pass/fail is decided by the C++ study against
the acceptance bounds of its YAML file. It writes into DIR:

    ratios.png      reduced / full for every static load, rigid-motion mass and frequency
    modes.png       natural frequencies of both models, paired by MAC
    dynamics.png    tip deflection in time, full against reduced, for the three dynamic tests
    members.png     axial forces of the chords and diagonals at the root, full against reduced
    README.md       the figures, the pictures (if rendered) and the markdown tables
"""
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

DPI = 110
FULL = dict(color="tab:blue", label="full (every member a beam)")
REDUCED = dict(color="tab:red", label="reduced (super truss)")
REQUIRED = ["statics.csv", "mass.csv", "modes.csv", "members.csv", "cost.csv",
            "dynamics_series.csv", "summary.csv", "lattice.md"]


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")


def finish(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    print(f"wrote {path}")


def plot_ratios(directory, summary):
    groups = [("static", "static stiffness\n(tip displacement reduced / full)", "tab:orange"),
              ("mass", "rigid-motion mass", "tab:green"),
              ("frequency", "natural frequency", "tab:purple")]
    fig, ax = plt.subplots(figsize=(10, 4.2))
    labels, values, colours = [], [], []
    for prefix, _, colour in groups:
        for name in sorted(k for k in summary if k.startswith(prefix + ".")):
            labels.append(name.split(".", 1)[1])
            values.append(summary[name])
            colours.append(colour)
    x = range(len(values))
    ax.bar(x, values, color=colours)
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xticks(list(x), labels, rotation=50, ha="right", fontsize=8)
    ax.set_ylabel("reduced / full")
    ax.legend(handles=[Patch(color=c, label=t.replace("\n", " ")) for _, t, c in groups],
              fontsize=8, loc="upper left")
    ax.set_title("Super truss against the full lattice: ratio of each measured quantity")
    finish(fig, directory / "ratios.png")


def plot_modes(directory, modes):
    fig, ax = plt.subplots(figsize=(7, 4))
    k = [int(r["mode"]) for r in modes]
    ax.plot(k, [number(r["full_hz"]) for r in modes], "o-", **FULL)
    ax.plot(k, [number(r["reduced_hz"]) for r in modes], "s--", **REDUCED)
    for r in modes:
        ax.annotate(f"MAC {number(r['mac']):.2f}\n(reduced {r['reduced_mode']})",
                    (int(r["mode"]), number(r["reduced_hz"])), textcoords="offset points",
                    xytext=(0, 8), ha="center", fontsize=7)
    ax.set_xlabel("mode of the full model")
    ax.set_ylabel("natural frequency (Hz)")
    ax.set_title("Cantilever natural frequencies; reduced mode paired by MAC")
    ax.legend(fontsize=8)
    ax.margins(y=0.2)
    finish(fig, directory / "modes.png")


def plot_dynamics(directory, series):
    tests = []
    for r in series:
        if r["test"] not in tests:
            tests.append(r["test"])
    titles = {"self_weight": "self-weight applied suddenly (8.2.1)",
              "torque": "end torque about the axis (8.2.2)",
              "angle": "root swung by an angle drive (8.2.2)"}
    fig, axes = plt.subplots(1, len(tests), figsize=(4.2 * len(tests), 3.6), squeeze=False)
    for ax, test in zip(axes[0], tests):
        for style, model, ls in ((FULL, "full", "-"), (REDUCED, "reduced", "--")):
            rows = [r for r in series if r["test"] == test and r["model"] == model]
            ax.plot([number(r["time"]) for r in rows],
                    [1e3 * number(r["tip_deflection"]) for r in rows], ls=ls, lw=1.2, **style)
        ax.set_title(titles.get(test, test), fontsize=9)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("tip deflection (mm)")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    finish(fig, directory / "dynamics.png")


def plot_members(directory, members):
    fig, ax = plt.subplots(figsize=(9, 4))
    labels = [f"{r['kind']} {r['member']}\n{r['node_a']}-{r['node_b']}" for r in members]
    x = list(range(len(members)))
    width = 0.4
    ax.bar([i - width / 2 for i in x], [1e-3 * number(r["full"]) for r in members], width, **FULL)
    ax.bar([i + width / 2 for i in x], [1e-3 * number(r["reduced"]) for r in members], width,
           **REDUCED)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xticks(x, labels, fontsize=7)
    ax.set_ylabel("axial force (kN)")
    ax.set_title("Members at the root: self-weight and a tip force")
    ax.legend(fontsize=8)
    finish(fig, directory / "members.png")


def write_readme(directory, title):
    pictures = [(p, text) for p, text in (
        ("full_members.png", "The full model under self-weight and the tip force, every member a "
                             "beam, coloured by axial force"),
        ("reduced_members.png", "The super truss under the same load, members drawn from its end "
                                "sections, same colours"))
        if (directory / p).is_file()]
    lines = [f"# {title}", "",
             "Generated by `scripts/verification-studies.sh` (the C++ study "
             "`latticedyn_study` writes the tables, `scripts/plot_lattice_study.py` draws). "
             "The reading of these numbers is in [docs/lattice.md](../../../lattice.md).", ""]
    lines += ["![ratios](ratios.png)", "", "![modes](modes.png)", "", "![dynamics](dynamics.png)",
              "", "![members](members.png)", ""]
    for path, text in pictures:
        lines += [f"{text}:", "", f"![{path}]({path})", ""]
    lines += [(directory / "lattice.md").read_text().rstrip("\n"), ""]
    (directory / "README.md").write_text("\n".join(lines))
    print(f"wrote {directory / 'README.md'}")


def main(argv):
    if len(argv) not in (2, 3):
        print("usage: /usr/bin/python3 scripts/plot_lattice_study.py DIR [TITLE]", file=sys.stderr)
        return 2
    directory = pathlib.Path(argv[1])
    title = argv[2] if len(argv) == 3 else "Super truss reduction accuracy"
    missing = [n for n in REQUIRED if not (directory / n).is_file()]
    if missing:
        for n in missing:
            print(f"error: required file {directory / n} is missing", file=sys.stderr)
        return 1
    summary = {r["quantity"]: number(r["value"]) for r in read_csv(directory / "summary.csv")}
    plot_ratios(directory, summary)
    plot_modes(directory, read_csv(directory / "modes.csv"))
    plot_dynamics(directory, read_csv(directory / "dynamics_series.csv"))
    plot_members(directory, read_csv(directory / "members.csv"))
    write_readme(directory, title)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
