#!/usr/bin/python3
"""Sparse identification of nonlinear dynamics (SINDy; Brunton, Proctor & Kutz, PNAS 113 (2016)
3932) from a latticedyn run: states defined from the probe CSV, their rates by differences,
a library of candidate functions, sequentially thresholded least squares. Writes the identified
model (YAML) and, with --plot, the model's own simulation against the data (PNG).

    latticedyn run examples/minimum_dof/pendulum_swing.yaml
    /usr/bin/python3 scripts/identify.py results/pendulum_swing/pendulum_swing_probes.csv \\
        --state "theta = arctan2(rod.tip.x, -rod.tip.z)" --state "omega = d(theta)" \\
        --library poly:3 --library trig --threshold 0.05 \\
        --out pendulum_model.yaml --plot pendulum_model.png

States are expressions of the probe columns (a column "rod.tip.x [m]" is rod.tip.x; `t` is time),
NumPy's functions (sin, cos, arctan2, sqrt, unwrap, ...), earlier states and d(x), the time
derivative of x by fourth-order central differences. --identify names the states that get an
equation (default: all); --inputs names states that enter the library with their values from the
data but get no equation (SINDy with control, Brunton et al., IFAC-PapersOnLine 49 (2016) 710);
any other state only helps define these (e.g. the slewing angle that turns the load's offset
into the jib's frame).
"""
import argparse
import csv
import itertools
import math
import re
import sys

import numpy as np
import yaml

UNIT = re.compile(r"^(.*?)\s*\[[^\]]*\]$")
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.]*")
SAFE = {name: getattr(np, name) for name in
        ("sin", "cos", "tan", "arcsin", "arccos", "arctan", "arctan2", "sinh", "cosh", "tanh", "exp", "log", "sqrt",
         "abs", "sign", "unwrap", "pi", "hypot")}


class IdentifyError(Exception):
    """Bad input: says what and where."""


def read_probes(path):
    """Columns of a probe CSV by name (units dropped), as float arrays."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise IdentifyError(f"{path}: {e.strerror}") from e
    if len(rows) < 6:
        raise IdentifyError(f"{path}: needs a header and at least 5 rows of data, has {len(rows)} lines")
    names = []
    for h in rows[0]:
        m = UNIT.match(h.strip())
        names.append((m.group(1) if m else h).strip())
    if names[0] != "time":
        raise IdentifyError(f"{path}: the first column must be time (a latticedyn probe CSV), found '{names[0]}'")
    try:
        data = np.array([[float(x) for x in r] for r in rows[1:] if r], dtype=float)
    except ValueError as e:
        raise IdentifyError(f"{path}: {e}") from e
    return {n: data[:, i] for i, n in enumerate(names)}


def derivative(x, t):
    """dx/dt on a uniform grid: fourth-order central differences inside, second order at the ends."""
    h = np.diff(t)
    if np.max(np.abs(h - h.mean())) > 1e-6 * h.mean():
        raise IdentifyError("d(): the samples must be equally spaced in time (output.interval with fixed steps)")
    h = h.mean()
    d = np.gradient(x, h, edge_order=2)
    d[2:-2] = (-x[4:] + 8 * x[3:-1] - 8 * x[1:-3] + x[:-4]) / (12 * h)
    return d


def evaluate_states(columns, definitions):
    """name = expression, in order; returns the states as arrays."""
    t = columns["time"]
    env = dict(SAFE)
    env["t"] = t
    env["d"] = lambda x: derivative(np.asarray(x, dtype=float), t)
    # Probe names contain dots: rename every known column to an identifier in the expression.
    aliases = {n: "_c%d" % i for i, n in enumerate(columns)}
    for n, a in aliases.items():
        env[a] = columns[n]
    states = {}
    for text in definitions:
        if "=" not in text:
            raise IdentifyError(f"--state '{text}': expected name = expression")
        name, expr = (s.strip() for s in text.split("=", 1))
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
            raise IdentifyError(f"--state '{text}': '{name}' is not a name")

        def rename(m):
            token = m.group(0)
            if token in aliases:
                return aliases[token]
            if token in env or token in states:
                return token
            raise IdentifyError(f"--state '{text}': '{token}' is neither a probe column ({', '.join(columns)}), "
                                f"a state defined before, nor a function")
        code = NAME.sub(rename, expr)
        try:
            value = eval(code, {"__builtins__": {}}, env)  # noqa: S307 - names checked above, no builtins
        except Exception as e:  # the expression's own error, shown with it
            raise IdentifyError(f"--state '{text}': {e}") from e
        value = np.broadcast_to(np.asarray(value, dtype=float), t.shape).copy()
        if not np.all(np.isfinite(value)):
            raise IdentifyError(f"--state '{text}': not finite everywhere")
        states[name] = value
        env[name] = value
    return states


def build_library(names, specs):
    """Candidate functions as (label, f(dict of arrays) -> array)."""
    terms = []
    for spec in specs:
        kind, _, arg = spec.partition(":")
        if kind == "poly":
            try:
                degree = int(arg or "2")
            except ValueError:
                raise IdentifyError(f"--library {spec}: expected poly:DEGREE") from None
            if not 1 <= degree <= 5:
                raise IdentifyError(f"--library {spec}: degree 1 to 5")
            terms.append(("1", lambda s: np.ones_like(next(iter(s.values())))))
            for k in range(1, degree + 1):
                for combo in itertools.combinations_with_replacement(names, k):
                    label = "*".join(combo)
                    terms.append((label, lambda s, c=combo: np.prod([s[n] for n in c], axis=0)))
        elif kind == "trig":
            for n in names:
                terms.append((f"sin({n})", lambda s, n=n: np.sin(s[n])))
                terms.append((f"cos({n})", lambda s, n=n: np.cos(s[n])))
        else:
            raise IdentifyError(f"--library {spec}: expected poly:DEGREE or trig")
    unique = {}
    for label, f in terms:
        unique.setdefault(label, f)
    return list(unique.items())


def ridge(theta, y, alpha):
    """argmin |theta xi - y|^2 + alpha |xi|^2 on columns scaled to unit RMS (so that alpha weighs
    every candidate alike), in the unscaled coefficients."""
    scale = np.sqrt(np.mean(theta ** 2, axis=0))
    scale[scale == 0] = 1.0
    a = theta / scale
    n = a.shape[1]
    xi = np.linalg.solve(a.T @ a + alpha * len(a) * np.eye(n), a.T @ y)
    return xi / scale


def fit(theta, y, alpha):
    """Least squares where the candidates are well conditioned, ridge where they are (nearly)
    dependent."""
    if np.linalg.cond(theta) < 1e8:
        return np.linalg.lstsq(theta, y, rcond=None)[0]
    return ridge(theta, y, alpha)


def stlsq(theta, rates, threshold, alpha=1e-5, iterations=20):
    """Sequentially thresholded least squares (STLSQ): fit, coefficients below `threshold` set to
    zero, the rest refitted, until the support stops changing. Where the candidates are linearly
    dependent on the data (a pendulum's conserved energy ties 1, omega^2 and cos(theta)) the fit
    is ridge regression, whose minimum-norm solution carries nothing along such a dependency."""
    xi = np.column_stack([fit(theta, rates[:, k], alpha) for k in range(rates.shape[1])])
    for _ in range(iterations):
        changed = False
        for k in range(rates.shape[1]):
            big = np.abs(xi[:, k]) >= threshold
            new = np.zeros(theta.shape[1])
            if big.any():
                new[big] = fit(theta[:, big], rates[:, k], alpha)
            changed |= not np.array_equal(new != 0, xi[:, k] != 0)
            xi[:, k] = new
        if not changed:
            break
    return xi


def simulate(xi, library, identified, inputs, t, x0):
    """The identified model's own trajectory (RK4 on the data's grid, inputs interpolated)."""
    def rhs(tt, x):
        s = {n: np.array([x[i]]) for i, n in enumerate(identified)}
        for n, u in inputs.items():
            s[n] = np.array([np.interp(tt, t, u)])
        theta = np.array([f(s)[0] for _, f in library])
        return theta @ xi
    out = np.zeros((len(t), len(identified)))
    out[0] = x0
    for k in range(len(t) - 1):
        h = t[k + 1] - t[k]
        x = out[k]
        k1 = rhs(t[k], x)
        k2 = rhs(t[k] + h / 2, x + h / 2 * k1)
        k3 = rhs(t[k] + h / 2, x + h / 2 * k2)
        k4 = rhs(t[k] + h, x + h * k3)
        out[k + 1] = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        if not np.all(np.isfinite(out[k + 1])):
            out[k + 1:] = np.nan
            break
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("probes", help="a latticedyn probe CSV (<name>_probes.csv)")
    ap.add_argument("--state", action="append", required=True, help="name = expression (repeatable, in order)")
    ap.add_argument("--identify", help="comma-separated states that get an equation (default: all)")
    ap.add_argument("--inputs", default="", help="comma-separated states in the library without an equation")
    ap.add_argument("--library", action="append", default=None, help="poly:DEGREE or trig (repeatable; default poly:3)")
    ap.add_argument("--threshold", type=float, default=0.05, help="STLSQ threshold on the coefficients")
    ap.add_argument("--ridge", type=float, default=1e-5, help="ridge weight on unit-RMS candidates (default 1e-5)")
    ap.add_argument("--from", dest="t_from", type=float, default=-math.inf, help="first time used, s")
    ap.add_argument("--until", type=float, default=math.inf, help="last time used, s")
    ap.add_argument("--out", help="YAML file for the identified model")
    ap.add_argument("--plot", help="PNG: the identified model's simulation against the data")
    args = ap.parse_args(argv)
    try:
        columns = read_probes(args.probes)
        states = evaluate_states(columns, args.state)
        t_all = columns["time"]
        keep = (t_all >= args.t_from) & (t_all <= args.until)
        if keep.sum() < 10:
            raise IdentifyError(f"--from/--until leave {keep.sum()} samples: need at least 10")
        identified = args.identify.split(",") if args.identify else list(states)
        for n in identified:
            if n not in states:
                raise IdentifyError(f"--identify: no state '{n}' (states: {', '.join(states)})")
        input_names = [n for n in args.inputs.split(",") if n]
        for n in input_names:
            if n not in states or n in identified:
                raise IdentifyError(f"--inputs: '{n}' is not a state, or is identified as well")
        names = identified + input_names
        inputs = {n: states[n] for n in input_names}
        library = build_library(names, args.library or ["poly:3"])
        # Rates of the identified states over the whole record (differences need neighbours),
        # then the window. Four samples at each end of the record are left out: there the
        # differences are one-sided and second order, and a state that is itself a derivative
        # (omega = d(theta)) passes its end error on to its rate.
        rates_all = np.column_stack([derivative(states[n], t_all) for n in identified])
        inner = np.zeros_like(keep)
        inner[4:-4] = True
        idx = np.flatnonzero(keep & inner)
        if len(idx) < 10:
            raise IdentifyError(f"--from/--until leave {len(idx)} samples away from the record's ends: need at least 10")
        s = {n: states[n][idx] for n in names}
        theta = np.column_stack([f(s) for _, f in library])
        rates = rates_all[idx]
        xi = stlsq(theta, rates, args.threshold, args.ridge)
    except IdentifyError as e:
        print(f"identify.py: error: {e}", file=sys.stderr)
        return 2

    fit = theta @ xi
    model = {"source": args.probes, "method": "SINDy, sequentially thresholded least squares",
             "threshold": args.threshold, "ridge": args.ridge, "time_span": [float(t_all[idx[0]]), float(t_all[idx[-1]])],
             "samples": int(len(idx)), "states": {n: d.split("=", 1)[1].strip() for n, d in
                                                  ((x.split("=", 1)[0].strip(), x) for x in args.state)},
             "inputs": input_names, "library": [label for label, _ in library],
             "equations": {}}
    for k, n in enumerate(identified):
        terms = {label: float(c) for (label, _), c in zip(library, xi[:, k]) if c != 0}
        residual = rates[:, k] - fit[:, k]
        scale = np.linalg.norm(rates[:, k] - rates[:, k].mean())
        r2 = 1.0 - (np.linalg.norm(residual) / scale) ** 2 if scale > 0 else float("nan")
        model["equations"][f"d{n}/dt"] = {"terms": terms, "rms_residual": float(np.sqrt(np.mean(residual ** 2))),
                                         "r_squared": float(r2)}
        rhs = " ".join(f"{c:+.6g}*{label}" if label != "1" else f"{c:+.6g}" for label, c in terms.items()) or "0"
        print(f"d{n}/dt = {rhs}    (R^2 {r2:.6f}, rms residual {model['equations'][f'd{n}/dt']['rms_residual']:.3g})")
    if args.out:
        with open(args.out, "w") as f:
            f.write("# identified by scripts/identify.py\n")
            yaml.safe_dump(model, f, sort_keys=False)
        print(f"wrote {args.out}")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        t = t_all[idx]
        x0 = np.array([states[n][idx[0]] for n in identified])
        sim = simulate(xi, library, identified, {n: states[n][idx] for n in inputs}, t, x0)
        fig, axes = plt.subplots(len(identified), 1, figsize=(8, 2.4 * len(identified)), sharex=True, squeeze=False)
        for k, n in enumerate(identified):
            ax = axes[k, 0]
            ax.plot(t, states[n][idx], "k", lw=2.5, alpha=0.35, label="latticedyn")
            ax.plot(t, sim[:, k], "C1", lw=1.2, label="identified model")
            ax.set_ylabel(n)
            ax.grid(alpha=0.3)
        axes[0, 0].legend(loc="upper right")
        axes[-1, 0].set_xlabel("time [s]")
        fig.suptitle(f"SINDy: {args.probes}", fontsize=9)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
