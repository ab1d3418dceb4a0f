#!/usr/bin/python3
"""Draws the sub-beam pattern of latticedyn's lattice generator (docs/lattice.md, "The section
and the pattern chosen"), one labelled picture per connection form:

    docs/images/lattice_pattern_type1.png          rectangle, type1 (crane.yaml main boom
                                                   type 2 with order 4 and length 6)
    docs/images/lattice_pattern_tp_type1.png       triangular prism, apex at end 1, tp_type1
                                                   (main boom type 1, the foot)
    docs/images/lattice_pattern_tp_anti_type1.png  anti triangular prism, apex at end 2,
                                                   tp_anti_type1 (derrick type 3, the tip)

    /usr/bin/python3 scripts/lattice_pattern.py [--latticedyn build/drivers/latticedyn]
                                                [--outdir docs/images]

The geometry comes from latticedyn itself, not from a copy of the generator: for each section
(read from examples/crane/crane.yaml `truss_sections`) the script writes into a temporary folder
a model with one `lattice` body (one Timoshenko element per member, no gravity, clamped at
its joint 1 by a fixed constraint to ground, like verification/cases/lattice_axial.yaml), runs
`latticedyn static MODEL --output DIR` and reads every member's end points from DIR/<name>.h5
(/viz/points, /viz/cells, /viz/element; docs/output-format.md). Members are then classified by
geometry alone: main beams (chord segments between consecutive stations of one main beam),
cross-section beams (both ends in an end-section plane) and sub-beams (the rest: diagonals and
the transverse members of apex bays).

Each picture has a 3-D view, the two end sections seen along the axis (node numbers as the
YAML counts them) and every face (two consecutive main beams) unrolled: seen from outside, the
axis x to the right, true distances across the face upward, station indices along the bottom.
"""
import argparse
import pathlib
import subprocess
import sys
import tempfile

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402
from matplotlib.gridspec import GridSpec  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
CRANE = ROOT / "examples" / "crane" / "crane.yaml"

COLOR = {"main": "black", "cross": "tab:blue", "sub": "darkorange"}
WIDTH = {"main": 2.4, "cross": 2.0, "sub": 1.6}
LABEL = {"main": "main beams (chords, one segment per bay)",
         "cross": "cross-section beams (end sections)",
         "sub": "sub-beams (diagonals; transverse member in an apex bay)"}

# (output name, section of crane.yaml, overrides, title)
MODELS = [
    ("type1", "type2", {"length": 6.0, "order": 4},
     "connection form type1: rectangle (4 + 4 end nodes)",
     "crane.yaml main boom type 2 with order 4 and length 6 m"),
    ("tp_type1", "type1", {},
     "connection form tp_type1: triangular prism, apex at end 1 (2 + 4 end nodes)",
     "crane.yaml main boom type 1, the foot: order 3, length 5 m"),
    ("tp_anti_type1", "type6", {},
     "connection form tp_anti_type1: anti triangular prism, apex at end 2 (4 + 2 end nodes)",
     "crane.yaml derrick type 3 (section type6), the tip: order 3, length 5 m"),
]


def model_yaml(name, section):
    """A model of one lattice body made of `section`, clamped at its joint 1, no gravity."""
    section = dict(section, material="steel", main_section="chord", sub_section="lacing")
    section.pop("cross_section", None)
    return {
        "title": f"lattice pattern: {name}",
        "materials": {"steel": {"density": 7800, "youngs_modulus": 2.06e11, "poisson_ratio": 0.25}},
        "sections": {"chord": {"type": "round_tube", "outer_radius": 0.1, "inner_radius": 0.08},
                     "lacing": {"type": "round_tube", "outer_radius": 0.05, "inner_radius": 0.04}},
        "truss_sections": {name: section},
        "ground": {"joints": [{"name": "clamp"}]},
        "bodies": [{"name": "truss", "type": "lattice", "section": name,
                    "member_type": "timoshenko_beam", "elements_per_member": 1}],
        "constraints": [{"name": "clamp", "type": "fixed", "joints": ["ground.clamp", "truss.1"]}],
    }


def run_latticedyn(latticedyn, name, section, workdir):
    """Writes and solves the model; returns the members' end points, shape (nMembers, 2, 3)."""
    model = workdir / f"{name}.yaml"
    model.write_text(yaml.safe_dump(model_yaml(name, section), sort_keys=False, default_flow_style=None))
    out = workdir / name
    proc = subprocess.run([str(latticedyn), "static", str(model), "--output", str(out)],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"latticedyn failed on {model}:\n{proc.stdout}{proc.stderr}")
    with h5py.File(out / f"{name}.h5", "r") as f:
        points = f["/viz/points"][0]
        cells = f["/viz/cells"][()]
        offsets = f["/viz/cell_offsets"][()]
        element = f["/viz/element"][()]
        types = [t.decode() if isinstance(t, bytes) else t for t in f["/model/element_types"][()]]
    members = []
    for e in range(len(types)):
        # An element draws one polyline cell through its axis points (per cell: type, count,
        # points): its ends are the cell's first and last point.
        mine = np.flatnonzero(element == e)
        if len(mine) != 1:
            sys.exit(f"{name}: element {e} is not drawn as one polyline")
        cell = cells[offsets[mine[0]] + 2:offsets[mine[0] + 1]]
        if len(cell) < 2 or cell[0] == cell[-1]:
            sys.exit(f"{name}: element {e} does not draw an open polyline")
        members.append(points[[cell[0], cell[-1]]])
    return np.array(members)


class Lattice:
    """Nodes and classified members of one section, from the member end points."""

    def __init__(self, section, ends):
        self.section = section
        self.L = float(section["length"])
        self.order = int(section["order"])
        self.end1 = np.array(section["end1"], float)
        self.end2 = np.array(section.get("end2", section["end1"]), float)
        self.main_beams = [(a - 1, b - 1) for a, b in section["main_beams"]]
        tol = 1e-6 * self.L
        # Merge coincident end points into nodes.
        self.nodes = []
        member_nodes = []
        for pair in ends:
            ids = []
            for p in pair:
                for i, q in enumerate(self.nodes):
                    if np.linalg.norm(p - q) < tol:
                        break
                else:
                    i = len(self.nodes)
                    self.nodes.append(p)
                ids.append(i)
            member_nodes.append(tuple(ids))
        self.nodes = np.array(self.nodes)
        # Station index of every node along the axis.
        h = self.L / self.order
        self.station = np.rint(self.nodes[:, 0] / h).astype(int)
        if np.max(np.abs(self.nodes[:, 0] - self.station * h)) > tol:
            sys.exit("a node lies between stations")
        # End-section node numbers (1-based, as in the YAML).
        self.end_label = {}
        for i, p in enumerate(self.nodes):
            for k, table in ((0, self.end1), (self.order, self.end2)):
                if self.station[i] == k:
                    d = np.linalg.norm(table - p[1:], axis=1)
                    if d.min() > tol:
                        sys.exit(f"end-section node at {p} is not in the YAML")
                    self.end_label[i] = int(d.argmin()) + 1
        # Main-beam lines, end node of end 1 to end node of end 2.
        self.lines = [(np.array([0.0, *self.end1[a]]), np.array([self.L, *self.end2[b]])) for a, b in self.main_beams]
        self.members = []  # (node a, node b, kind, transverse)
        for a, b in member_nodes:
            sa, sb = self.station[a], self.station[b]
            if sa == sb and sa in (0, self.order):
                kind = "cross"
            elif abs(sa - sb) == 1 and any(self.on_line(a, m) and self.on_line(b, m) for m in range(len(self.lines))):
                kind = "main"
            else:
                kind = "sub"
            self.members.append((a, b, kind, kind == "sub" and sa == sb))

    def on_line(self, node, m):
        a, b = self.lines[m]
        p = self.nodes[node]
        t = np.clip(np.dot(p - a, b - a) / np.dot(b - a, b - a), 0, 1)
        return np.linalg.norm(a + t * (b - a) - p) < 1e-6 * self.L

    def count(self, kind):
        return sum(1 for m in self.members if m[2] == kind)

    def face(self, m):
        """Main beams m and n = m + 1 (cyclic): outward normal and an in-plane basis seen from outside."""
        n = (m + 1) % len(self.lines)
        A, B = self.lines[m]
        D, C = self.lines[n]
        normal = np.cross(C - A, D - B)
        normal /= np.linalg.norm(normal)
        centre = self.nodes.mean(axis=0)
        if np.dot(0.25 * (A + B + C + D) - centre, normal) < 0:
            normal = -normal
        e1 = np.array([1.0, 0, 0]) - normal[0] * normal
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(normal, e1)  # up, for a viewer outside looking in with x to the right
        return n, normal, e2, 0.25 * (A + B + C + D)


def node_badge(ax, x, y, text, end, **kw):
    face = "#fff3b0" if end == 1 else "#d8f0d0"
    ax.text(x, y, text, ha="center", va="center", fontsize=9, fontweight="bold", zorder=6,
            bbox=dict(boxstyle="circle,pad=0.25", fc=face, ec="0.3", lw=0.8), **kw)


def draw_3d(ax, lat):
    for a, b, kind, _ in lat.members:
        p, q = lat.nodes[a], lat.nodes[b]
        ax.plot(*zip(p, q), color=COLOR[kind], lw=WIDTH[kind] * 0.8)
    ax.scatter(*lat.nodes.T, s=8, color="0.2", depthshade=False)
    ymax = np.abs(lat.nodes[:, 1]).max()
    zmax = np.abs(lat.nodes[:, 2]).max()
    for i, k in lat.end_label.items():
        p = lat.nodes[i]
        dx = -0.09 * lat.L if lat.station[i] == 0 else 0.09 * lat.L
        end = 1 if lat.station[i] == 0 else 2
        ax.text(p[0] + dx, p[1], p[2], str(k), fontsize=9, fontweight="bold", ha="center", va="center",
                bbox=dict(boxstyle="circle,pad=0.2", fc="#fff3b0" if end == 1 else "#d8f0d0", ec="0.3", lw=0.8))
    # Station indices on the axis.
    ax.set_xticks([k * lat.L / lat.order for k in range(lat.order + 1)])
    ax.set_xticklabels([f"k={k}" for k in range(lat.order + 1)])
    ax.set_xlabel(f"x (axis), station k at k\u00b7{lat.L / lat.order:.3g} m", labelpad=4)
    ax.set_ylabel("y, m", labelpad=0)
    ax.set_zlabel("z, m", labelpad=0)
    ax.set_box_aspect((lat.L, 2 * ymax + 0.6, 2 * max(zmax, 0.3) + 0.9), zoom=1.25)
    ax.view_init(elev=24, azim=-62)
    ax.tick_params(labelsize=7, pad=0)
    ax.set_title("3-D view; node numbers of end section 1 yellow, of end section 2 green",
                 fontsize=9.5)


def draw_end(ax, lat, end):
    k = 0 if end == 1 else lat.order
    table = lat.end1 if end == 1 else lat.end2
    # The whole section's outline, faint, for orientation: every main beam projected on y-z.
    for a, b in lat.lines:
        ax.plot([a[1], b[1]], [a[2], b[2]], color="0.8", lw=1, ls=":", zorder=1)
    for a, b, kind, _ in lat.members:
        if kind == "cross" and lat.station[a] == k:
            p, q = lat.nodes[a], lat.nodes[b]
            ax.plot([p[1], q[1]], [p[2], q[2]], color=COLOR["cross"], lw=WIDTH["cross"], zorder=2)
    for i, lab in lat.end_label.items():
        if lat.station[i] == k:
            node_badge(ax, lat.nodes[i, 1], lat.nodes[i, 2], str(lab), end)
    ax.set_aspect("equal")
    ext = max(np.abs(lat.end1).max(), np.abs(lat.end2).max()) + 0.5
    ax.set_xlim(-ext, ext)
    ax.set_ylim(-ext + 0.2, ext - 0.2)
    ax.set_xlabel("y, m", fontsize=8)
    ax.set_ylabel("z, m", fontsize=8)
    ax.tick_params(labelsize=7)
    where = "x = 0" if end == 1 else f"x = {lat.L:g} m"
    ax.set_title(f"end section {end} ({where}), {len(table)} nodes\n"
                 "seen from +x; dotted: main beams projected", fontsize=9)


def draw_face(ax, lat, m):
    n, normal, e2, centre = lat.face(m)
    mb = lat.section["main_beams"]

    def uv(i):
        p = lat.nodes[i]
        return p[0], float(np.dot(p - centre, e2))

    h = lat.L / lat.order
    for k in range(lat.order + 1):
        ax.axvline(k * h, color="0.9", lw=0.8, zorder=0)
    on_face = [i for i in range(len(lat.nodes)) if lat.on_line(i, m) or lat.on_line(i, n)]
    transverse_members = []
    for a, b, kind, transverse in lat.members:
        if a in on_face and b in on_face:
            (x1, y1), (x2, y2) = uv(a), uv(b)
            ax.plot([x1, x2], [y1, y2], color=COLOR[kind], lw=WIDTH[kind], solid_capstyle="round", zorder=2)
            if transverse:
                transverse_members.append((x1, max(y1, y2), min(y1, y2)))
    for i in on_face:
        x, y = uv(i)
        ax.plot(x, y, "o", ms=3.5, color="0.15", zorder=3)
        if i in lat.end_label:
            end = 1 if lat.station[i] == 0 else 2
            node_badge(ax, x + (-0.04 if end == 1 else 0.04) * lat.L, y, str(lat.end_label[i]), end)
    # Main-beam names beside their chords, at mid-length, on the outside of the face.
    # On a tapered face the label sits towards the wide end, clear of the sloping chord.
    for beam in (m, n):
        a, b = lat.lines[beam]
        va, vb = float(np.dot(a - centre, e2)), float(np.dot(b - centre, e2))
        t = 0.5 if abs(abs(va) - abs(vb)) < 0.05 else (0.72 if abs(vb) > abs(va) else 0.28)
        v = va + t * (vb - va)
        side = 1 if v >= 0 else -1
        rise = abs(vb - va) / lat.L * 0.12 * lat.L
        ax.text(a[0] + t * (b[0] - a[0]), v + side * (0.22 + rise),
                f"main beam {beam + 1} ({mb[beam][0]}\u2192{mb[beam][1]})",
                fontsize=8, ha="center", va="bottom" if side > 0 else "top", color="0.1", zorder=5,
                bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.85))
    ax.set_xticks([k * h for k in range(lat.order + 1)])
    ax.set_xticklabels([str(k) for k in range(lat.order + 1)], fontsize=8)
    ax.set_xlim(-0.08 * lat.L, 1.08 * lat.L)
    vmax = max(abs(uv(i)[1]) for i in on_face)
    ax.set_ylim(-vmax - 0.6, vmax + 0.6)
    # The transverse member of an apex bay: the note goes into the empty corner beside the apex.
    for x, top, bottom in transverse_members:
        at_end1 = x < 0.5 * lat.L
        ax.annotate("apex bay: transverse\nmember, no diagonal", xy=(x, top - 0.35 * (top - bottom)),
                    xytext=(-0.06 * lat.L if at_end1 else 1.06 * lat.L, vmax + 0.05),
                    fontsize=8, color="saddlebrown", ha="left" if at_end1 else "right", va="center",
                    arrowprops=dict(arrowstyle="->", color="saddlebrown", lw=0.9), zorder=7)
    ax.set_aspect("equal")
    ax.tick_params(axis="y", labelsize=7)
    ax.set_xlabel("station k along the main beams (0: end section 1, "
                  f"{lat.order}: end section 2)", fontsize=8)
    ax.set_ylabel("across face, m", fontsize=8)
    ax.set_title(f"face {m + 1}: main beams {m + 1} and {n + 1}, unrolled, seen from outside", fontsize=9.5)


def draw(lat, name, title, origin, path):
    nfaces = len(lat.lines)
    rows = (nfaces + 1) // 2
    fig = plt.figure(figsize=(12.5, 5.0 + 3.9 * rows))
    gs = GridSpec(1 + rows, 4, figure=fig, height_ratios=[1.3] + [1] * rows,
                  hspace=0.38, wspace=0.3, left=0.05, right=0.98, top=0.865, bottom=0.045)
    ax3 = fig.add_subplot(gs[0, 0:2], projection="3d")
    draw_3d(ax3, lat)
    draw_end(fig.add_subplot(gs[0, 2]), lat, 1)
    draw_end(fig.add_subplot(gs[0, 3]), lat, 2)
    for m in range(nfaces):
        r, c = divmod(m, 2)
        draw_face(fig.add_subplot(gs[1 + r, 2 * c:2 * c + 2]), lat, m)
    transverse = sum(1 for mem in lat.members if mem[3])
    fig.suptitle(f"latticedyn lattice pattern, {title}", fontsize=14, fontweight="bold", y=0.985)
    fig.text(0.5, 0.952,
             f"{origin}; {len(lat.members)} members: {lat.count('main')} main, {lat.count('cross')} cross-section, "
             f"{lat.count('sub')} sub-beams ({lat.count('sub') - transverse} diagonals, {transverse} transverse)\n"
             f"geometry read from `latticedyn static` (/viz of {name}.h5), members classified by geometry",
             ha="center", va="center", fontsize=9.5)
    handles = [Line2D([], [], color=COLOR[k], lw=WIDTH[k], label=LABEL[k]) for k in ("main", "cross", "sub")]
    fig.legend(handles=handles, loc="upper center", ncol=3, fontsize=9.5, frameon=False, bbox_to_anchor=(0.5, 0.933))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--latticedyn", default=str(ROOT / "build" / "drivers" / "latticedyn"))
    parser.add_argument("--outdir", default=str(ROOT / "docs" / "images"))
    args = parser.parse_args(argv)
    sections = yaml.safe_load(CRANE.read_text())["truss_sections"]
    outdir = pathlib.Path(args.outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="lattice_pattern_") as tmp:
        for name, source, overrides, title, origin in MODELS:
            section = dict(sections[source], **overrides)
            lat = Lattice(section, run_latticedyn(args.latticedyn, name, section, pathlib.Path(tmp)))
            path = outdir / f"lattice_pattern_{name}.png"
            draw(lat, name, title, origin, path)
            print(f"{path}: {len(lat.members)} members ({lat.count('main')} main, {lat.count('cross')} cross, "
                  f"{lat.count('sub')} sub)")


if __name__ == "__main__":
    main(sys.argv[1:])
