#!/usr/bin/python3
"""Plots of a `latticedyn control` run (thesis Figures 8-14..8-18), from the CSVs it writes.

usage: /usr/bin/python3 scripts/control_report.py RESULTS_DIR

writes into RESULTS_DIR:
    control_map.png         the mapped equilibria and the fitted surfaces x, z over the rope lengths (8-14)
    control_optimal.png     the optimal end point trajectory: positions, velocities, accelerations, path (8-15)
    control_trajectory.png  the path over the mapped end points and the rope lengths along it (8-16)
    control_table.png       the control table (resampled and steady points) and its spline drives (8-17)
    control_tracking.png    the load in the verification run against the optimal trajectory (8-18)
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header = rows[0]
    data = np.array([[float(v) for v in r] for r in rows[1:] if r], dtype=float)
    return {h: data[:, k] for k, h in enumerate(header)}, header


def plot_map(d, header, out):
    l0, l1 = header[0], header[1]
    fig = plt.figure(figsize=(13, 5.5))
    for k, (name, fit) in enumerate((("x", "x_fit"), ("z", "z_fit"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        ax.plot_trisurf(d[l0], d[l1], d[fit], alpha=0.35, color="tab:orange", linewidth=0)
        ax.scatter(d[l0], d[l1], d[name], s=6, color="tab:blue", label="static equilibria")
        ax.set_xlabel(f"{l0} rope rest length (m)")
        ax.set_ylabel(f"{l1} rope rest length (m)")
        ax.set_zlabel(f"end point {name} (m)")
        res = d[name] - d[fit]
        ax.set_title(f"{name}: fitted surface (orange), RMS residual {np.sqrt(np.mean(res ** 2)):.3g} m")
    fig.suptitle("Quasi-static map: equilibria (points) and fitted surface")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def plot_optimal(o, out):
    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    t = o["t"]
    axes[0][0].plot(t, o["x"], label="x")
    axes[0][0].plot(t, o["z"], label="z")
    axes[0][0].set_ylabel("position (m)")
    axes[0][1].plot(t, o["vx"], label="vx")
    axes[0][1].plot(t, o["vz"], label="vz")
    axes[0][1].set_ylabel("velocity (m/s)")
    axes[1][0].step(t, o["ax"], where="post", label="ax")
    axes[1][0].step(t, o["az"], where="post", label="az")
    axes[1][0].set_ylabel("acceleration (m/s²)")
    for ax in (axes[0][0], axes[0][1], axes[1][0]):
        ax.set_xlabel("time (s)")
        ax.legend()
        ax.grid(alpha=0.3)
    axes[1][1].plot(o["x"], o["z"], color="tab:green")
    axes[1][1].plot(o["x"][0], o["z"][0], "o", label="start")
    axes[1][1].plot(o["x"][-1], o["z"][-1], "*", markersize=12, label="end")
    axes[1][1].set_xlabel("x (m)")
    axes[1][1].set_ylabel("z (m)")
    axes[1][1].set_title("path of the end point")
    axes[1][1].legend()
    axes[1][1].grid(alpha=0.3)
    fig.suptitle("Optimal end point trajectory (QR, TAO)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def plot_trajectory(d, o, names, out):
    fig, axes = plt.subplots(1, 2, figsize=(13, 5))
    axes[0].scatter(d["x"], d["z"], s=6, color="tab:blue", label="mapped equilibria")
    axes[0].plot(o["x"], o["z"], color="tab:red", linewidth=2, label="optimal path")
    axes[0].set_xlabel("end point x (m)")
    axes[0].set_ylabel("end point z (m)")
    axes[0].set_title("projection of the path on the map")
    axes[0].legend()
    axes[0].grid(alpha=0.3)
    for n in names:
        axes[1].plot(o["t"], o[n], label=f"{n} rope")
    axes[1].set_xlabel("time (s)")
    axes[1].set_ylabel("rest length (m)")
    axes[1].set_title("control trajectory from the inverse surfaces")
    axes[1].legend()
    axes[1].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def plot_table(tab, spl, names, out):
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.5))
    for ax, n in zip(axes, names):
        ax.plot(spl["t"], spl[n], color="tab:orange", label="spline drive")
        ax.plot(tab["t"], tab[n], "o", color="tab:blue", markersize=4, label="table points")
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"{n} rest length (m)")
        ax.grid(alpha=0.3)
        ax.legend()
    fig.suptitle("Control table: resampled points with steady points at both ends, spline with zero end rates")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def plot_tracking(tr, out):
    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    t = tr["t"]
    for ax, c in ((axes[0][0], "x"), (axes[0][1], "z")):
        ax.plot(t, tr[f"{c}_optimal"], "--", color="black", label="optimal (theory)")
        ax.plot(t, tr[c], color="tab:blue", label="crane run")
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"load {c} (m)")
        ax.grid(alpha=0.3)
        ax.legend()
    axes[1][0].plot(tr["x_optimal"], tr["z_optimal"], "--", color="black", label="optimal")
    axes[1][0].plot(tr["x"], tr["z"], color="tab:blue", label="crane run")
    axes[1][0].set_xlabel("x (m)")
    axes[1][0].set_ylabel("z (m)")
    axes[1][0].legend()
    axes[1][0].grid(alpha=0.3)
    axes[1][1].plot(t, tr["error"], color="tab:red")
    axes[1][1].set_xlabel("time (s)")
    axes[1][1].set_ylabel("distance to the optimal point (m)")
    axes[1][1].grid(alpha=0.3)
    fig.suptitle("Verification: the load under the quasi-static control against the optimal trajectory")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    folder = sys.argv[1]
    d, header = load(os.path.join(folder, "map_fit.csv"))
    names = header[:2]
    o, _ = load(os.path.join(folder, "optimal_trajectory.csv"))
    plot_map(d, header, os.path.join(folder, "control_map.png"))
    plot_optimal(o, os.path.join(folder, "control_optimal.png"))
    plot_trajectory(d, o, names, os.path.join(folder, "control_trajectory.png"))
    tab, _ = load(os.path.join(folder, "control_table.csv"))
    spl, _ = load(os.path.join(folder, "control_spline.csv"))
    plot_table(tab, spl, names, os.path.join(folder, "control_table.png"))
    written = ["control_map.png", "control_optimal.png", "control_trajectory.png", "control_table.png"]
    tracking = os.path.join(folder, "tracking.csv")
    if os.path.exists(tracking):
        tr, _ = load(tracking)
        plot_tracking(tr, os.path.join(folder, "control_tracking.png"))
        written.append("control_tracking.png")
    print("plots: " + ", ".join(os.path.join(folder, w) for w in written))


if __name__ == "__main__":
    main()
