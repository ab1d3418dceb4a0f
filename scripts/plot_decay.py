#!/usr/bin/python3
"""Plots a decaying oscillation from a latticedyn probe CSV with its fitted damping ratio.

    /usr/bin/python3 scripts/plot_decay.py results/damping_cantilever_probes.csv beam.2.z \
        --from 0.5 --expected 0.0200153 --output docs/images/damping_cantilever.png

The ratio is measured like the verification runner's `damping_ratio` check: extrema refined by a
parabola, a least-squares line through the logarithms of the half-cycle ranges for the decay rate
sigma, the damped frequency from the extrema's spacing, zeta = sigma / sqrt(sigma^2 + omega_d^2).
The plot shows the signal, the fitted envelope about the mean of the last cycle and, with
--expected, the envelope of the expected ratio.
"""
import argparse
import csv
import math
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

UNIT = re.compile(r"^(.*?)\s*\[([^\]]*)\]$")


def column(path, name):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = [(UNIT.match(c).group(1) if UNIT.match(c) else c) for c in rows[0]]
    if name not in names:
        raise SystemExit(f"{path}: no column '{name}' (has {', '.join(names[1:])})")
    i, t = names.index(name), names.index("time")
    return [float(r[t]) for r in rows[1:]], [float(r[i]) for r in rows[1:]]


def extrema(t, x, start):
    out = []
    for i in range(1, len(t) - 1):
        if t[i - 1] < start:
            continue
        a, b, c = x[i - 1], x[i], x[i + 1]
        if not ((b > a and b >= c) or (b < a and b <= c)):
            continue
        h, curv = 0.5 * (t[i + 1] - t[i - 1]), a - 2 * b + c
        s = 0.5 * (a - c) / curv if curv else 0.0
        out.append((t[i] + s * h, b - 0.25 * (a - c) * s))
    return out


def damping_ratio(ext):
    pts = [(0.5 * (ext[k][0] + ext[k + 1][0]), math.log(abs(ext[k + 1][1] - ext[k][1]))) for k in range(len(ext) - 1)]
    n = len(pts)
    st, sy = sum(p[0] for p in pts), sum(p[1] for p in pts)
    stt, sty = sum(p[0] ** 2 for p in pts), sum(p[0] * p[1] for p in pts)
    slope = (n * sty - st * sy) / (n * stt - st * st)
    sigma, intercept = -slope, (sy - slope * st) / n
    omega_d = math.pi * n / (ext[-1][0] - ext[0][0])
    return sigma / math.hypot(sigma, omega_d), sigma, omega_d, intercept


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("probe", help="column, e.g. beam.2.z")
    ap.add_argument("--from", dest="start", type=float, default=-1e300, help="fit from this time, s")
    ap.add_argument("--expected", type=float, help="expected damping ratio (closed form)")
    ap.add_argument("--output", required=True)
    a = ap.parse_args()
    t, x = column(a.csv, a.probe)
    ext = extrema(t, x, a.start)
    if len(ext) < 4:
        raise SystemExit(f"{a.csv}: fewer than 4 extrema of {a.probe} after t = {a.start} s")
    zeta, sigma, omega_d, intercept = damping_ratio(ext)
    centre = sum(x[i] for i in range(len(t)) if t[i] >= t[-1] - 2 * math.pi / omega_d) / \
        sum(1 for i in range(len(t)) if t[i] >= t[-1] - 2 * math.pi / omega_d)
    fig, ax = plt.subplots(figsize=(8, 4))
    scale = 1e3
    ax.plot(t, [scale * v for v in x], lw=0.8, label=a.probe)
    # Half-cycle range 2 A(t) (1 + e^{-sigma T/2}) / ... : the envelope is half the fitted range
    # corrected for the half-cycle's decay.
    k = 1 + math.exp(-sigma * math.pi / omega_d)
    tt = [v for v in t if v >= ext[0][0]]
    env = [math.exp(intercept - sigma * v) / k for v in tt]
    for sign in (1, -1):
        ax.plot(tt, [scale * (centre + sign * e) for e in env], "k--", lw=0.8,
                label=f"fitted envelope, zeta = {zeta:.5f}" if sign > 0 else None)
    if a.expected:
        omega_n = math.hypot(sigma, omega_d)
        s_exp = a.expected * omega_n
        env0 = env[0]
        for sign in (1, -1):
            ax.plot(tt, [scale * (centre + sign * env0 * math.exp(-s_exp * (v - tt[0]))) for v in tt], "r:", lw=1.0,
                    label=f"closed form, zeta = {a.expected:.5f}" if sign > 0 else None)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"{a.probe} (mm)")
    ax.legend(loc="upper right", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.output, dpi=120)
    print(f"{a.probe}: zeta = {zeta:.7f}, sigma = {sigma:.6g} 1/s, f_d = {omega_d / (2 * math.pi):.6g} Hz -> {a.output}")


if __name__ == "__main__":
    main()
