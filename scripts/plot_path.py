#!/usr/bin/env python3
"""Plots the load-displacement path that `latticedyn path` writes (<name>_path.csv): the load
factor against each probe joint's displacement components that move, limit points marked.

    /usr/bin/python3 scripts/plot_path.py results/path_lee_frame_path.csv --output lee.png
    /usr/bin/python3 scripts/plot_path.py A_path.csv B_path.csv --title "two models" --output both.png
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2 or rows[0][:2] != ["step", "load_factor"]:
        sys.exit(f"{path}: not a latticedyn path CSV (expected a header starting with step,load_factor)")
    header, data = rows[0], [[float(x) for x in r] for r in rows[1:]]
    return header, data


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+")
    ap.add_argument("--output", required=True, help="PNG to write")
    ap.add_argument("--title", default="load-displacement path")
    ap.add_argument("--reference", help="a CSV of displacement,load_factor drawn as a line (e.g. a closed form)")
    ap.add_argument("--reference-label", default="reference")
    a = ap.parse_args()
    fig, ax = plt.subplots(figsize=(7, 5))
    for path in a.csv:
        header, data = read(path)
        lam = [r[1] for r in data]
        for c in range(4, len(header)):
            u = [r[c] for r in data]
            if max(abs(x) for x in u) < 1e-9 * (1 + max(abs(x) for r in data for x in r[4:])):
                continue  # a component that does not move
            label = header[c] if len(a.csv) == 1 else f"{path.rsplit('/', 1)[-1]}: {header[c]}"
            ax.plot(u, lam, ".-", ms=3, lw=1, label=label)
            for k in range(1, len(lam) - 1):
                if (lam[k] > lam[k - 1] and lam[k] >= lam[k + 1]) or (lam[k] < lam[k - 1] and lam[k] <= lam[k + 1]):
                    ax.plot(u[k], lam[k], "o", mfc="none", mec="k")
                    ax.annotate(f"{lam[k]:.4g}", (u[k], lam[k]), textcoords="offset points", xytext=(6, 4), fontsize=8)
    if a.reference:
        with open(a.reference, newline="") as f:
            ref = [[float(x) for x in r] for r in csv.reader(f) if r and not r[0].startswith("#")]
        ax.plot([r[0] for r in ref], [r[1] for r in ref], "k-", lw=0.8, alpha=0.6, label=a.reference_label)
    ax.axhline(0, color="grey", lw=0.5)
    ax.set_xlabel("displacement of the probe joint [m, or the model's length unit]")
    ax.set_ylabel("load factor (times the model's loads)")
    ax.set_title(a.title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.output, dpi=120)
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
