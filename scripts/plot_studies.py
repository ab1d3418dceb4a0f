#!/usr/bin/python3
"""Draws the figures and the README of the beam cross-validation studies (thesis chapter 8.1).

    /usr/bin/python3 scripts/plot_studies.py DIR

DIR holds the tables the C++ studies write (scripts/verification-studies.sh): end_moment.csv,
self_weight.csv, self_weight_series.csv, rotation_torque_series.csv, rotation_angle_series.csv
and the markdown tables end_moment.md, self_weight.md, rotation_torque.md, rotation_angle.md.
This script only draws and collects; pass/fail is decided on the C++ side. It writes into DIR:

    fig_8_1_end_moment.png      tip locus and tip error of the end-moment (roll-up) study
    fig_8_2_self_weight.png     tip displacement under suddenly applied self weight, period error
    fig_8_3_rotation_torque.png beam spun up by a constant torque: deflection, angle lag, energy
    fig_8_4_rotation_angle.png  beam swung by a prescribed hinge angle: drive, deflection
    README.md                   the figures with the markdown tables

Models are named C<n> (cubic spline beam) and T<n> (Timoshenko beam) with n segments; every
figure draws a segment count in the same colour, C solid and T dashed. Missing columns are
skipped, 'nan' cells are left out of the curves.
"""
import csv
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# required tables and the columns each cannot do without (the others are optional)
REQUIRED_CSV = {
    "end_moment.csv": ["type", "segments", "K"],
    "self_weight.csv": ["type", "segments"],
    "self_weight_series.csv": ["model", "time"],
    "rotation_torque_series.csv": ["model", "time"],
    "rotation_angle_series.csv": ["model", "time"],
}
TYPE_LETTER = {"cubic_spline_beam": "C", "timoshenko_beam": "T"}
TYPE_NAME = {"C": "cubic spline beam", "T": "Timoshenko beam"}
SEGMENT_COLOURS = {1: "tab:red", 3: "tab:orange", 5: "tab:green", 10: "tab:blue"}
EXTRA_COLOURS = ["tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "tab:gray"]
LINESTYLE = {"C": "-", "T": "--"}
MARKER = {"C": "o", "T": "s"}
REFERENCE_MODEL = "C10"
DPI = 110


# ---------------------------------------------------------------- reading

def parse_cell(text):
    """A float if the cell is numeric (including 'nan'), else the stripped text."""
    text = text.strip()
    try:
        return float(text)
    except ValueError:
        return text


class TableError(Exception):
    """A table lacks what the script cannot do without."""


def read_csv(path, key_columns):
    """Rows of a CSV as dicts of parsed cells; key_columns (model identity, time) must exist."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        header = [name.strip() for name in reader.fieldnames or []]
        missing = [name for name in key_columns if name not in header]
        if missing:
            raise TableError(f"{path} has no column {', '.join(missing)}")
        return [{k.strip(): parse_cell(v or "") for k, v in row.items() if k is not None}
                for row in reader]


def finite(x):
    return isinstance(x, float) and math.isfinite(x)


def columns(rows, *names):
    """Parallel lists of the named columns, keeping only rows where every one is finite.
    None if a column is absent from the table."""
    if not rows or any(name not in rows[0] for name in names):
        return None
    kept = [r for r in rows if all(finite(r[n]) for n in names)]
    return [[r[n] for r in kept] for n in names]


def model_name(row):
    """C<n> / T<n> from the type and segments columns of a summary table."""
    letter = TYPE_LETTER.get(row["type"], str(row["type"])[:1].upper())
    return f"{letter}{int(row['segments'])}"


def group_summary(rows):
    groups = {}
    for row in rows:
        groups.setdefault(model_name(row), []).append(row)
    return groups


def group_series(rows):
    groups = {}
    for row in rows:
        groups.setdefault(str(row["model"]), []).append(row)
    return groups


# ---------------------------------------------------------------- styling

def split_model(model):
    """('C', 10) from 'C10'; segments 0 if unparsable."""
    letter, digits = model[:1], model[1:]
    return letter, int(digits) if digits.isdigit() else 0


def model_order(model):
    letter, segments = split_model(model)
    return ("CT".find(letter) % 3, segments, model)


def sorted_models(models):
    return sorted(models, key=model_order)


def colour(segments):
    if segments in SEGMENT_COLOURS:
        return SEGMENT_COLOURS[segments]
    return EXTRA_COLOURS[segments % len(EXTRA_COLOURS)]


def style(model, **extra):
    """Line style of a model: colour by segment count, solid C / dashed T."""
    letter, segments = split_model(model)
    s = dict(color=colour(segments), linestyle=LINESTYLE.get(letter, ":"), label=model)
    s.update(extra)
    return s


def reference_model(models):
    """C10 if present, else the finest C model, else the first."""
    models = sorted_models(models)
    if REFERENCE_MODEL in models:
        return REFERENCE_MODEL
    c_models = [m for m in models if m.startswith("C")]
    return c_models[-1] if c_models else models[0]


def energy_unit(values):
    """(scale, unit) so that the largest magnitude reads in J, kJ or MJ."""
    top = max((abs(v) for v in values), default=0.0)
    for scale, unit in ((1e6, "MJ"), (1e3, "kJ")):
        if top >= 10 * scale:
            return scale, unit
    return 1.0, "J"


def label_levels(ax, levels):
    """Names horizontal reference lines on a right-hand axis: levels = [(y, text), ...]."""
    right = ax.twinx()
    right.set_ylim(ax.get_ylim())
    right.set_yticks([y for y, _ in levels], [text for _, text in levels], fontsize=8)
    ax.callbacks.connect("ylim_changed", lambda a: right.set_ylim(a.get_ylim()))


def finish(fig, path):
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    print(f"wrote {path}")


def add_legend(ax, **kwargs):
    """A legend if anything was labelled, else a note that the panel has no data."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kwargs)
    else:
        ax.text(0.5, 0.5, "no data (column missing or all nan)", transform=ax.transAxes,
                ha="center", va="center", color="0.4")


def legend_note(ax, text):
    ax.text(0.01, 0.01, text, transform=ax.transAxes, fontsize=8, color="0.35", va="bottom")


# ---------------------------------------------------------------- figure 8.1

def plot_end_moment(directory, tables):
    rows = tables["end_moment.csv"]
    groups = group_summary(rows)
    fig, (ax_tip, ax_err) = plt.subplots(1, 2, figsize=(14, 6.2),
                                         gridspec_kw=dict(width_ratios=[1, 1.15]))
    exact = columns(sorted(rows, key=lambda r: r["K"]), "K", "exact_x", "exact_y")
    if exact:
        locus = sorted(set(zip(*exact)))
        ax_tip.plot([p[1] for p in locus], [p[2] for p in locus], color="black", linewidth=1.3,
                    label="exact (circular arc)", zorder=5)
    omitted = 0
    for model in sorted_models(groups):
        mrows = sorted(groups[model], key=lambda r: r["K"])
        converged = [r for r in mrows if r.get("converged", 1.0) == 1.0]
        omitted += len(mrows) - len(converged)
        letter = split_model(model)[0]
        tip = columns(converged, "tip_x", "tip_y")
        if tip:
            ax_tip.plot(*tip, **style(model, marker=MARKER.get(letter, "^"), markersize=4,
                                      linewidth=1.0))
        err = columns(converged, "K", "error_over_L")
        points = [(k, 100 * v) for k, v in zip(*err) if v > 0] if err else []  # log axis
        if points:
            ax_err.plot(*zip(*points), **style(model, marker=MARKER.get(letter, "^"),
                                               markersize=4, linewidth=1.2))
    ax_tip.set_aspect("equal", adjustable="datalim")
    ax_tip.set_xlabel("tip x [m]")
    ax_tip.set_ylabel("tip y [m]")
    ax_tip.set_title("(a) tip position for K = 0.05 … 1.0")
    ax_tip.grid(True, alpha=0.3)
    add_legend(ax_tip, fontsize=8, ncol=2, loc="upper right")
    if omitted:
        legend_note(ax_tip, f"{omitted} non-converged solutions omitted")
    for limit in (0.5, 1.0):
        ax_err.axhline(limit, color="black", linestyle=":", linewidth=1.2)
        ax_err.annotate(f"limit {limit:g} %", (0.0, limit), xycoords=("axes fraction", "data"),
                        xytext=(4, 0), textcoords="offset points", ha="left", va="center",
                        fontsize=8, bbox=dict(facecolor="white", edgecolor="none", pad=1))
    ax_err.set_yscale("log")
    ax_err.set_xlabel("K (end moment, K = 1: full circle)")
    ax_err.set_ylabel("tip error [% of L]")
    ax_err.set_title("(b) tip error vs exact arc (non-converged omitted)")
    ax_err.grid(True, which="both", alpha=0.25)
    add_legend(ax_err, fontsize=8, ncol=2, loc="lower right")
    fig.suptitle("8.1 End moment: cantilever rolled up by a tip moment")
    fig.tight_layout()
    finish(fig, directory / "fig_8_1_end_moment.png")


# ---------------------------------------------------------------- figure 8.2

def plot_self_weight(directory, tables):
    summary = tables["self_weight.csv"]
    series = group_series(tables["self_weight_series.csv"])
    fig, (ax_z, ax_p) = plt.subplots(1, 2, figsize=(14, 5.5),
                                     gridspec_kw=dict(width_ratios=[3, 1]))
    for model in sorted_models(series):
        data = columns(series[model], "time", "tip_z")
        if data:
            ax_z.plot(*data, linewidth=1.1, **style(model))
    swing = columns(summary, "swing_exact")
    if swing and swing[0]:
        two_w = swing[0][0]
        levels = [(0.0, "0"), (-two_w / 2, "−w_static"), (-two_w, "−2 w_static")]
        for level, _ in levels:
            ax_z.axhline(level, color="black", linestyle=":", linewidth=1.0)
        label_levels(ax_z, levels)
    ax_z.set_xlabel("time [s]")
    ax_z.set_ylabel("tip z displacement [m]")
    ax_z.set_title("(a) tip displacement, self weight applied at t = 0")
    ax_z.grid(True, alpha=0.3)
    bottom, top = ax_z.get_ylim()
    ax_z.set_ylim(bottom - 0.12 * (top - bottom), top)  # room for the legend
    add_legend(ax_z, fontsize=8, ncol=8, loc="lower center")

    models, errors = [], []
    for row in summary:
        if "period_error" in row and finite(row["period_error"]):
            models.append(model_name(row))
            errors.append(100 * row["period_error"])
    order = sorted(range(len(models)), key=lambda i: model_order(models[i]))
    for pos, i in enumerate(order):
        letter, segments = split_model(models[i])
        ax_p.bar(pos, errors[i], color=colour(segments), edgecolor="black", linewidth=0.6,
                 hatch="//" if letter == "T" else None)
        ax_p.annotate(f"{errors[i]:+.2f}", (pos, errors[i]), ha="center", fontsize=7,
                      va="bottom" if errors[i] >= 0 else "top",
                      xytext=(0, 2 if errors[i] >= 0 else -2), textcoords="offset points")
    ax_p.set_xticks(range(len(order)), [models[i] for i in order], rotation=45)
    if not order:
        add_legend(ax_p)
    ax_p.axhline(0, color="black", linewidth=0.8)
    ax_p.set_ylabel("period error [%]")
    ax_p.set_title("(b) first period vs Euler-Bernoulli")
    ax_p.grid(True, axis="y", alpha=0.3)
    ax_p.set_xlabel("model (hatched: Timoshenko)")
    ax_p.margins(y=0.1)
    fig.suptitle("8.1 Self weight: cantilever released under gravity")
    fig.tight_layout()
    finish(fig, directory / "fig_8_2_self_weight.png")


# ---------------------------------------------------------------- figure 8.3

def plot_rotation_torque(directory, tables):
    series = group_series(tables["rotation_torque_series.csv"])
    models = sorted_models(series)
    fig, (ax_d, ax_a, ax_e) = plt.subplots(3, 1, figsize=(12, 11), sharex=True)
    for model in models:
        data = columns(series[model], "time", "tip_deflection")
        if data:
            ax_d.plot(*data, linewidth=0.8, **style(model))
        data = columns(series[model], "time", "chord_angle", "reference_angle")
        if data:
            t, chord, ref = data
            ax_a.plot(t, [c - r for c, r in zip(chord, ref)], linewidth=0.8, **style(model))
    ax_d.set_ylabel("tip deflection [m]")
    ax_d.set_title("(a) tip deflection in the hinge frame")
    ax_a.set_ylabel("chord − rigid angle [rad]")
    ax_a.set_title("(b) chord angle minus rigid-body rotation M t² / (2 I_O)")
    for ax in (ax_d, ax_a):
        ax.axhline(0, color="black", linewidth=0.6)
        add_legend(ax, fontsize=8, ncol=8, loc="lower left")

    ref = reference_model(models)
    data = columns(series[ref], "time", "energy", "torque_work")
    if data:
        t, energy, work = data
        scale, unit = energy_unit(energy + work)
        ax_e.plot(t, [v / scale for v in energy], color="tab:blue", label=f"{ref} energy")
        ax_e.plot(t, [v / scale for v in work], color="black", linestyle="--",
                  label=f"{ref} torque work")
        ax_e.set_ylabel(f"energy, work [{unit}]")
        ax_diff = ax_e.twinx()
        ax_diff.plot(t, [(e - w) / scale for e, w in zip(energy, work)], color="tab:red",
                     linewidth=0.8, label="energy − work (right axis)")
        ax_diff.set_ylabel(f"energy − work [{unit}]", color="tab:red")
        ax_diff.tick_params(axis="y", colors="tab:red")
        lines = ax_e.get_lines() + ax_diff.get_lines()
        ax_e.legend(lines, [ln.get_label() for ln in lines], fontsize=8, loc="upper left")
    else:
        add_legend(ax_e)
    ax_e.set_title(f"(c) work-energy check, {ref}")
    ax_e.set_xlabel("time [s]")
    for ax in (ax_d, ax_a, ax_e):
        ax.grid(True, alpha=0.3)
    fig.suptitle("8.1 Rotation by a constant end torque")
    fig.tight_layout()
    finish(fig, directory / "fig_8_3_rotation_torque.png")


# ---------------------------------------------------------------- figure 8.4

def plot_rotation_angle(directory, tables):
    series = group_series(tables["rotation_angle_series.csv"])
    models = sorted_models(series)
    ref = reference_model(models)
    fig, (ax_h, ax_d) = plt.subplots(2, 1, figsize=(12, 8.5), sharex=True)
    for model in models:
        thick = model == ref
        data = columns(series[model], "time", "hinge_angle")
        if data:
            ax_h.plot(*data, **style(model, linewidth=2.2 if thick else 0.7,
                                     alpha=1.0 if thick else 0.7,
                                     label=f"{model} hinge angle" if thick else model))
        data = columns(series[model], "time", "tip_deflection")
        if data:
            ax_d.plot(*data, linewidth=1.0, **style(model))
    drive = columns(series[ref], "time", "reference_angle")
    if drive:
        ax_h.plot(*drive, color="black", linestyle=":", linewidth=1.6, label="drive (reference)")
    quasi = columns(series[ref], "time", "quasi_static_deflection")
    if quasi:
        ax_d.plot(*quasi, color="black", linestyle="--", linewidth=1.6, label="quasi-static")
    ax_h.set_ylabel("hinge angle [rad]")
    ax_h.set_title(f"(a) hinge angle and prescribed drive ({ref} thick, others thin)")
    add_legend(ax_h, fontsize=8, ncol=5, loc="lower left")
    ax_d.axhline(0, color="black", linewidth=0.6)
    ax_d.set_ylabel("tip deflection [m]")
    ax_d.set_xlabel("time [s]")
    ax_d.set_title("(b) tip deflection in the hinge frame")
    bottom, top = ax_d.get_ylim()
    ax_d.set_ylim(bottom - 0.15 * (top - bottom), top)  # room for the legend
    add_legend(ax_d, fontsize=8, ncol=9, loc="lower center")
    for ax in (ax_h, ax_d):
        ax.grid(True, alpha=0.3)
    fig.suptitle("8.1 Rotation by a prescribed hinge angle")
    fig.tight_layout()
    finish(fig, directory / "fig_8_4_rotation_angle.png")


# ---------------------------------------------------------------- README

SECTIONS = [
    ("End moment", "fig_8_1_end_moment.png", "end_moment.md",
     "Cantilever loaded by a tip moment that rolls it into a circular arc (K = 1: full circle); "
     "static tip position against the exact arc."),
    ("Self weight", "fig_8_2_self_weight.png", "self_weight.md",
     "Cantilever released under its own weight; tip oscillation against the Euler-Bernoulli "
     "first period and static deflection."),
    ("Rotation by an end torque", "fig_8_3_rotation_torque.png", "rotation_torque.md",
     "Hinged beam spun up by a constant torque at the free end; deflection, lag behind the "
     "rigid rotation and the work-energy balance."),
    ("Rotation by a prescribed angle", "fig_8_4_rotation_angle.png", "rotation_angle.md",
     "Hinged beam swung by a prescribed hinge angle; tip deflection against the quasi-static "
     "deflection."),
]


def write_readme(directory):
    lines = [
        "# Cross-validation of the beam elements (thesis 8.1)",
        "",
        "Generated by `scripts/verification-studies.sh`: the C++ studies write the tables, "
        "`scripts/plot_studies.py` draws the figures and this page. "
        "C = cubic spline beam, T = Timoshenko beam, number = segments.",
        "",
    ]
    for title, figure, table, text in SECTIONS:
        lines += [f"## {title}", "", text, "", f"![{title}]({figure})", ""]
        if title.startswith("Rotation by a prescribed") and (directory / "rotation_angle_C10.png").is_file():
            lines += ["The C10 run in ParaView at t = 0, 1, ..., 5 s (seen along the hinge axis; "
                      "`scripts/render.py` on its XDMF):", "", "![C10 in ParaView](rotation_angle_C10.png)", ""]
        path = directory / table
        if path.is_file():
            lines += [path.read_text().rstrip("\n"), ""]
        else:
            print(f"warning: {path} not found, table left out of README.md", file=sys.stderr)
            lines += [f"*(table `{table}` not found)*", ""]
    (directory / "README.md").write_text("\n".join(lines))
    print(f"wrote {directory / 'README.md'}")


# ---------------------------------------------------------------- main

def main(argv):
    if len(argv) != 2:
        print("usage: /usr/bin/python3 scripts/plot_studies.py DIR", file=sys.stderr)
        return 2
    directory = pathlib.Path(argv[1])
    if not directory.is_dir():
        print(f"error: {directory} is not a directory", file=sys.stderr)
        return 1
    missing = [name for name in REQUIRED_CSV if not (directory / name).is_file()]
    if missing:
        for name in missing:
            print(f"error: required file {directory / name} is missing", file=sys.stderr)
        return 1
    try:
        tables = {name: read_csv(directory / name, keys) for name, keys in REQUIRED_CSV.items()}
    except TableError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    for plot in (plot_end_moment, plot_self_weight, plot_rotation_torque, plot_rotation_angle):
        plot(directory, tables)
    write_readme(directory)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
