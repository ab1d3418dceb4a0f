#!/usr/bin/python3
"""Plots and tables of a crane run (examples/crane/*.yaml), read from its HDF5 results.

    /usr/bin/python3 scripts/crane_report.py results/crane_lifting/lifting.h5 --out DIR [--title T]

Writes into DIR, named after the results file:
    <name>_load.png     position and velocity of the load's hook (joint load.1) over time, like
                        the thesis's Figures 8-10..8-13
    <name>_path.png     the load's path seen from above (x-y), coloured by time, beside the path
                        of the point it hangs from (the hoisting rope's upper end at the boom head)
    <name>_ropes.png    the force in each rope and strut tie, one panel each with its own range
                        (several carry nearly the same force and would hide each other on one
                        axis), and each drive on its own axis in its unit: rope rest lengths in
                        m, the slewing angle in degrees
    <name>_summary.md   the state at the start (the static equilibrium) and at the end: rope rest
                        lengths and forces, boom angle, load position; the run's extremes
    <name>_summary.csv  the same numbers, one quantity per row
    <name>_members.md   each body's most utilized member over the run (von Mises over the
                        material's yield stress): its utilization, stress, when and which element;
                        with --vs OTHER.h5 (the same maneuver on the other crane model) the two side
                        by side, ordered by the larger utilization
Needs h5py and matplotlib (Debian's python3-h5py, python3-matplotlib).
"""
import argparse
import pathlib
import sys

import h5py
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROPES = ["hoisting_rope", "luffing_rope", "sub_cable", "tie1", "tie2"]
DPI = 110


def strings(ds):
    return [x.decode() if isinstance(x, bytes) else str(x) for x in ds[()]]


class Run:
    def __init__(self, path):
        f = h5py.File(path, "r")
        self.name = pathlib.Path(path).stem
        self.title = f.attrs.get("title", self.name)
        if isinstance(self.title, bytes):
            self.title = self.title.decode()
        self.time = f["time"][()]
        self.joint_names = strings(f["model/joint_names"])
        self.joint_pos = f["joints/position"][()]
        self.joint_vel = f["joints/velocity"][()]
        self.bodies = strings(f["model/body_names"])
        self.element_body = f["model/element_body"][()]
        self.body_types = strings(f["model/body_types"]) if "model/body_types" in f else [""] * len(self.bodies)
        self.axial = f["elements/axial_force"][()]
        self.violation = f["constraints/violation"][()] if "constraints/violation" in f else None
        self.drive_names = strings(f["model/drive_names"]) if "model/drive_names" in f else []
        self.drives = f["drives/value"][()] if "drives/value" in f else np.zeros((len(self.time), 0))
        v = f.get("viz")
        self.utilization = v["utilization"][()] if v is not None and "utilization" in v else None
        self.von_mises = v["von_mises"][()] if v is not None and "von_mises" in v else None
        # Per drawn cell (results format 4: a member is one cell; format 3 drew it as several
        # lines, each with the member's values, which this reads the same way).
        self.cell_body = v["body"][()] if v is not None and "body" in v else None
        self.cell_element = v["element"][()] if v is not None and "element" in v else None
        self.cell_member = v["member"][()] if v is not None and "member" in v else None

    def joint(self, name):
        if name not in self.joint_names:
            sys.exit(f"error: the results have no joint '{name}' (is this a crane run?)")
        k = self.joint_names.index(name)
        return self.joint_pos[:, k, :], self.joint_vel[:, k, :]

    def body_force(self, name):
        """Axial force of a body's elements over time: (mean, minimum over the elements)."""
        if name not in self.bodies:
            return None
        b = self.bodies.index(name)
        cols = [e for e, eb in enumerate(self.element_body) if eb == b]
        forces = self.axial[:, cols]
        return forces.mean(axis=1), forces.min(axis=1)

    def drive(self, name):
        """A drive's values over time in the unit it is shown in, with what it is and that unit:
        (quantity, unit, values); the slewing drive is an angle (rad, shown in degrees), the
        others drive rope rest lengths (m)."""
        y = self.drives[:, self.drive_names.index(name)]
        if name == "slewing":
            return "slewing angle", "deg", np.degrees(y)
        return f"{name} rope rest length", "m", y

    def boom_angle(self):
        """Angle of the main boom (foot hinge to head) above the horizontal, degrees."""
        foot, _ = self.joint("boom1.1")
        head, _ = self.joint("head.1")
        d = head - foot
        return np.degrees(np.arctan2(d[:, 2], np.hypot(d[:, 0], d[:, 1])))


def plot_load(run, out, title):
    p, v = run.joint("load.1")
    fig, axes = plt.subplots(2, 3, figsize=(13, 6), sharex=True)
    for c, axis in enumerate("xyz"):
        axes[0][c].plot(run.time, p[:, c], color="tab:blue")
        axes[0][c].set_ylabel(f"load {axis} (m)")
        axes[1][c].plot(run.time, v[:, c], color="tab:red")
        axes[1][c].set_ylabel(f"load v{axis} (m/s)")
        axes[1][c].set_xlabel("time (s)")
        for ax in (axes[0][c], axes[1][c]):
            ax.grid(alpha=0.3)
    fig.suptitle(f"{title}: position and velocity of the load's hook")
    fig.tight_layout()
    path = out / f"{run.name}_load.png"
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    print(f"wrote {path}")


def plot_path(run, out, title):
    """The load's path seen from above, coloured by time, and the path of the point it hangs from
    (the hoisting rope's upper end): their distance is the load's swing."""
    p, _ = run.joint("load.1")
    fig, ax = plt.subplots(figsize=(7, 6.2), layout="constrained")
    if "hoisting_rope.1" in run.joint_names:
        top, _ = run.joint("hoisting_rope.1")
        ax.plot(top[:, 0], top[:, 1], color="0.55", ls="--", lw=1,
                label="hoisting rope's upper end (boom head)")
    ax.plot(p[:, 0], p[:, 1], color="0.8", lw=0.8, zorder=1)
    dots = ax.scatter(p[:, 0], p[:, 1], c=run.time, cmap="viridis", s=6, zorder=2, label="load (load.1)")
    ax.plot(p[0, 0], p[0, 1], "o", mfc="none", mec="black", ms=10, label=f"start, t = {run.time[0]:g} s")
    ax.plot(p[-1, 0], p[-1, 1], "s", mfc="none", mec="black", ms=10, label=f"end, t = {run.time[-1]:g} s")
    fig.colorbar(dots, ax=ax, label="time (s)", shrink=0.8)
    # Same scale on both axes, so the path keeps its shape; the limits grow to fill the panel.
    ax.set_aspect("equal", adjustable="datalim")
    ax.ticklabel_format(useOffset=False)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    ax.set_title(f"{title}: the load's path seen from above", fontsize=10)
    path = out / f"{run.name}_path.png"
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    print(f"wrote {path}")


def plot_ropes(run, out, title):
    """Rope and tie forces on the left, drives on the right, one panel each with its own y range."""
    ropes = [(name, run.body_force(name)) for name in ROPES if run.body_force(name) is not None]
    rows = max(len(ropes), len(run.drive_names), 1)
    fig = plt.figure(figsize=(13, 1.0 + 1.5 * rows), layout="constrained")
    left, right = fig.subfigures(1, 2)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    if ropes:
        left.suptitle("rope and tie forces (mean over each body's elements)", fontsize=10)
        axes = left.subplots(len(ropes), 1, sharex=True, squeeze=False)[:, 0]
        for k, ((name, force), ax) in enumerate(zip(ropes, axes)):
            ax.plot(run.time, force[0] / 1e6, color=colours[k % len(colours)])
            ax.set_title(name.replace("_", " "), fontsize=9, loc="left")
            ax.set_ylabel("force (MN)")
            ax.grid(alpha=0.3)
        axes[-1].set_xlabel("time (s)")
    if run.drive_names:
        right.suptitle("drives (Table 7-3: u1 slewing, u2 luffing, u3 hoisting)", fontsize=10)
        axes = right.subplots(len(run.drive_names), 1, sharex=True, squeeze=False)[:, 0]
        for k, (name, ax) in enumerate(zip(run.drive_names, axes)):
            quantity, unit, y = run.drive(name)
            ax.plot(run.time, y, color=colours[k % len(colours)])
            ax.set_title(quantity, fontsize=9, loc="left")
            ax.set_ylabel(f"({unit})")
            ax.grid(alpha=0.3)
        axes[-1].set_xlabel("time (s)")
    fig.suptitle(title)
    path = out / f"{run.name}_ropes.png"
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    print(f"wrote {path}")


def summary(run, out, title):
    p, v = run.joint("load.1")
    angle = run.boom_angle()
    rows = []  # (quantity, start, end, unit)
    for name in run.drive_names:
        quantity, unit, y = run.drive(name)
        rows.append((quantity, y[0], y[-1], unit))
    for name in ROPES:
        f = run.body_force(name)
        if f is not None:
            rows.append((f"{name.replace('_', ' ')} force", f[0][0] / 1e3, f[0][-1] / 1e3, "kN"))
    rows.append(("main boom angle above horizontal", angle[0], angle[-1], "deg"))
    for c, axis in enumerate("xyz"):
        rows.append((f"load hook {axis}", p[0, c], p[-1, c], "m"))
    lines = [f"### {title}", "", f"`{run.name}.h5`, t = {run.time[0]:g} .. {run.time[-1]:g} s, "
             f"{len(run.time)} outputs", "",
             "| quantity | start (static equilibrium) | end | unit |", "|---|---|---|---|"]
    for q, a, b, u in rows:
        lines.append(f"| {q} | {a:.6g} | {b:.6g} | {u} |")
    minimum = min((run.body_force(n)[1].min() for n in ROPES if run.body_force(n) is not None), default=float("nan"))
    viol = float(np.max(run.violation)) if run.violation is not None and run.violation.size else 0.0
    extremes = [("smallest rope or tie force over the run", minimum / 1e3, "kN"),
                ("largest constraint violation over the run", viol, "m or rad"),
                ("largest load speed", float(np.max(np.linalg.norm(v, axis=1))), "m/s"),
                ("load's largest |y|", float(np.max(np.abs(p[:, 1]))), "m")]
    lines += ["", "| over the run | value | unit |", "|---|---|---|"]
    lines += [f"| {q} | {x:.6g} | {u} |" for q, x, u in extremes]
    (out / f"{run.name}_summary.md").write_text("\n".join(lines) + "\n")
    with open(out / f"{run.name}_summary.csv", "w") as f:
        f.write("quantity,start,end,unit\n")
        for q, a, b, u in rows:
            f.write(f"{q},{a:.10g},{b:.10g},{u}\n")
        for q, x, u in extremes:
            f.write(f"{q},{x:.10g},,{u}\n")
    print(f"wrote {out / (run.name + '_summary.md')}")


def member_peaks(run):
    """Each body's most utilized member over the run: {body: (utilization, von Mises [Pa], time,
    "member k" of a lattice or super truss, or "element k" of another body)}; bodies whose members
    have no utilization (no yield stress) are left out."""
    if run.utilization is None:
        return {}
    peaks = {}
    first_element = {}
    for e, b in enumerate(run.element_body):
        first_element.setdefault(int(b), e)
    for b in sorted(set(int(x) for x in run.cell_body if x >= 0)):
        cols = np.flatnonzero(run.cell_body == b)
        u = run.utilization[:, cols]
        if not np.isfinite(u).any():
            continue
        k, c = np.unravel_index(np.nanargmax(u), u.shape)
        cell = cols[c]
        element = int(run.cell_element[cell]) - first_element[b] + 1
        # A lattice body has one element per member, in the truss section's member order, and a
        # super truss's members come in that order too: "member k" names the same member in both.
        if run.body_types[b] == "super_truss":
            where = f"member {int(run.cell_member[cell]) + 1}"
        elif run.body_types[b] == "lattice":
            where = f"member {element}"
        else:
            where = f"element {element}"
        peaks[run.bodies[b]] = (float(u[k, c]), float(run.von_mises[k, cell]), float(run.time[k]), where)
    return peaks


def members(run, out, other=None):
    """<name>_members.md: each body's most utilized member, beside the other run's."""
    mine = member_peaks(run)
    if not mine:
        return
    theirs = member_peaks(other) if other is not None else {}
    order = sorted(mine, key=lambda b: -max(mine[b][0], theirs.get(b, (0,))[0]))
    head = f"| body | {run.name}: utilization | von Mises (MPa) | t (s) | where |"
    rule = "|---|---|---|---|---|"
    if other is not None:
        head += f" {other.name}: utilization | von Mises (MPa) | t (s) | where |"
        rule += "---|---|---|---|"
    lines = [head, rule]
    for b in order:
        u, vm, t, e = mine[b]
        row = f"| {b} | {u:.3f} | {vm / 1e6:.4g} | {t:.4g} | {e} |"
        if other is not None:
            if b in theirs:
                u2, vm2, t2, e2 = theirs[b]
                row += f" {u2:.3f} | {vm2 / 1e6:.4g} | {t2:.4g} | {e2} |"
            else:
                row += " | | | |"
        lines.append(row)
    (out / f"{run.name}_members.md").write_text("\n".join(lines) + "\n")
    print(f"wrote {out / (run.name + '_members.md')}")


def main():
    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("h5")
    a.add_argument("--out", required=True)
    a.add_argument("--title", default=None)
    a.add_argument("--vs", default=None, help="the same maneuver on the other crane model, for the members table")
    args = a.parse_args()
    if not pathlib.Path(args.h5).is_file():
        sys.exit(f"error: no results file {args.h5}")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    run = Run(args.h5)
    if len(run.time) < 1:
        sys.exit(f"error: {args.h5} holds no output step")
    title = args.title or run.title
    plot_load(run, out, title)
    plot_path(run, out, title)
    plot_ropes(run, out, title)
    summary(run, out, title)
    members(run, out, Run(args.vs) if args.vs else None)


if __name__ == "__main__":
    main()
