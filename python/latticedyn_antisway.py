"""Closed-loop anti-sway control of the crane's slewing (docs/control.md, "Closed loop"): a linear
quadratic regulator on the load's tangential sway mode, taken from the linearised crane
(Simulator.linearize), scheduled over the boom angle (the luffing rope's length), acting on the
slewing drive's acceleration around an open-loop reference motion.

The reduced model, per design point: the tangential pendulum mode of the linear model (frequency
omega, the eigenvalue whose mode moves the load most in the tangential direction) and its
excitation by the slewing acceleration, identified from the linear model's frequency response:

    s'' + omega^2 s = -r (u''_ref + v),    e'' = v,

with s the load's tangential sway (m) in the slewed frame, e = u - u_ref the slewing angle's
deviation from the reference, v the feedback acceleration. The gains minimise the integral of
x^T Q x + R v^2 (x = [s, s', e, e']), for the model sampled at the controller's period (zero-order hold, in closed form), from the
discrete Riccati equation; care()/lqr() give the continuous design for comparison.
"""
import math

import numpy as np


def care(a, b, q, r):
    """The stabilising solution P of A^T P + P A - P B R^-1 B^T P + Q = 0 (small, dense)."""
    n = a.shape[0]
    rinv = np.linalg.inv(r)
    h = np.block([[a, -b @ rinv @ b.T], [-q, -a.T]])
    w, v = np.linalg.eig(h)
    stable = v[:, w.real < 0]
    if stable.shape[1] != n:
        raise ValueError(f"care: {stable.shape[1]} stable eigenvalues of the Hamiltonian, expected {n}")
    p = np.real(stable[n:, :] @ np.linalg.inv(stable[:n, :]))
    return 0.5 * (p + p.T)


def lqr(a, b, q, r):
    """The gain K of v = -K x."""
    p = care(a, b, q, r)
    return np.linalg.inv(r) @ b.T @ p


def dlqr(a, b, q, r, tolerance=1e-12, iterations=100000):
    """The gain K of v_k = -K x_k for x_{k+1} = A x_k + B v_k, from the discrete Riccati equation
    iterated to its fixed point (small, dense)."""
    p = q.copy()
    for _ in range(iterations):
        k = np.linalg.solve(r + b.T @ p @ b, b.T @ p @ a)
        p_next = q + a.T @ p @ (a - b @ k)
        if np.max(np.abs(p_next - p)) <= tolerance * max(1.0, np.max(np.abs(p))):
            return np.linalg.solve(r + b.T @ p_next @ b, b.T @ p_next @ a)
        p = p_next
    raise ValueError("dlqr: the Riccati iteration did not converge")


def sampled_model(omega, r, period):
    """The reduced model held over each sampling period (zero-order hold), in closed form: the
    pendulum mode and the drive's double integrator."""
    c, s = math.cos(omega * period), math.sin(omega * period)
    a = np.array([[c, s / omega, 0, 0], [-omega * s, c, 0, 0], [0, 0, 1, period], [0, 0, 0, 1]])
    b = np.array([[-r * (1 - c) / omega**2], [-r * s / omega], [period**2 / 2], [period]])
    return a, b


def sway_model(crane, probe_index=0):
    """(omega, r) of the tangential sway mode at the crane's current equilibrium, from its linear
    model with the slewing drive as input (docs/api.md#linear-models). The tangential direction is
    the horizontal normal to the load's radius."""
    lm = crane.linearize(["slewing"])
    n = 2 * lm["independent"]
    a, b, c = lm["A"], lm["B"], lm["C"]
    load = crane.joint_position(lm["outputs"][6 * probe_index][:-2])
    radial = load[:2] / np.linalg.norm(load[:2])
    tangential = np.array([-radial[1], radial[0]])
    row = tangential @ c[6 * probe_index:6 * probe_index + 2, :]  # tangential position output
    eigenvalues, vectors = np.linalg.eig(a[:n, :n])
    # The pendulum modes: below 0.2 Hz; the one that moves the load most tangentially.
    candidates = [i for i in range(n) if eigenvalues[i].imag > 1e-6 and abs(eigenvalues[i]) < 2 * math.pi * 0.2]
    if not candidates:
        raise ValueError("sway_model: no pendulum mode below 0.2 Hz")
    i = max(candidates, key=lambda k: abs(row[:n] @ vectors[:, k]) / np.linalg.norm(vectors[:n // 2, k]))
    omega = abs(eigenvalues[i])
    # Frequency response of the tangential position to the slewing acceleration at Omega = omega / 2:
    # G = r_load / (i Omega)^2 - r / (omega^2 - Omega^2) for the reduced model (rigid rotation plus
    # the pendulum), so r follows from G and the load's radius.
    big_omega = 0.5 * omega
    g = row @ np.linalg.solve(1j * big_omega * np.eye(a.shape[0]) - a, b[:, 0])
    r_load = np.linalg.norm(load[:2])
    r = float(np.real(-(g + r_load / big_omega**2) * (omega**2 - big_omega**2)))
    return float(omega), r


class SwayRegulator:
    """Discrete LQR gains for the sampling period, designed at several luffing rope lengths (boom
    angles) and interpolated linearly in the current length: gain scheduling over the boom angle."""

    def __init__(self, designs, period=0.1, q=(10.0, 10.0, 10.0, 1.0), r=1.0):
        # designs: [(luffing length, omega, r), ...]
        self.points = sorted(designs)
        self.period = period
        self.q = np.diag(q)
        self.r = np.array([[r]])
        self.gains = []
        for _, omega, gain in self.points:
            a, b = sampled_model(omega, gain, period)
            self.gains.append(dlqr(a, b, self.q, self.r)[0])

    @classmethod
    def design(cls, model, luffing_lengths, **settings):
        """Linearises the crane `model` (its drives external) at rest at each luffing rope length."""
        import latticedyn

        designs = []
        for length in luffing_lengths:
            crane = latticedyn.Simulator(model, {"drives.luffing": f"{{type: external, initial: {length!r}}}"})
            crane.solve_statics()
            omega, r = sway_model(crane)
            designs.append((float(length), omega, r))
        return cls(designs, **settings)

    def gain(self, luffing_length):
        lengths = [p[0] for p in self.points]
        if len(lengths) == 1:
            return self.gains[0]
        return np.array([np.interp(luffing_length, lengths, [k[j] for k in self.gains]) for j in range(4)])

    def feedback(self, luffing_length, x):
        return float(-self.gain(luffing_length) @ x)


def bang_bang(angle, duration):
    """Reference slew: accelerate for half the time, decelerate for the other half."""
    a = angle / (duration / 2) ** 2

    def reference(t):
        if t < duration / 2:
            return 0.5 * a * t * t, a * t, a
        if t < duration:
            tau = duration - t
            return angle - 0.5 * a * tau * tau, a * tau, -a
        return angle, 0.0, 0.0

    return reference


def slewed_sway(crane, rest):
    """The load's sway in the slewed frame, relative to its quasi-static position `rest` there:
    tangential and radial sway (m), their rates (m/s); the velocity less the frame's own rotation."""
    angle, rate, _ = crane.drive("slewing")
    c, s = math.cos(angle), math.sin(angle)
    to_slewed = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    p = to_slewed @ crane.joint_position("load.1")
    v = to_slewed @ crane.joint_velocity("load.1") - rate * np.array([-p[1], p[0], 0.0])
    d = p - rest
    radial = rest[:2] / np.linalg.norm(rest[:2])
    tangential = np.array([-radial[1], radial[0]])
    return d[:2] @ tangential, d[:2] @ radial, v[:2] @ tangential, v[:2] @ radial


def tangential_sway(crane, rest):
    """Tangential sway (m) and its rate (m/s) in the slewed frame, and the radial sway."""
    st, sr, vt, _ = slewed_sway(crane, rest)
    return st, vt, sr


def slew(crane, reference, duration, regulator=None, period=0.1, max_acceleration=0.05):
    """Runs the slew on the nonlinear crane (at rest at its equilibrium) for `duration` seconds,
    open loop (regulator None: the reference acceleration) or closed loop, sampled every `period`.
    Returns a dict of arrays: time, tangential and radial sway, slewing angle, acceleration applied,
    the hoisting rope's largest tension."""
    rest = crane.joint_position("load.1")
    t0 = crane.time
    out = {k: [] for k in ("time", "sway", "radial", "angle", "acceleration", "rope")}
    steps = int(round(duration / period))
    for k in range(steps):
        t = k * period
        u_ref, rate_ref, accel_ref = reference(t)
        s, s_rate, _ = tangential_sway(crane, rest)
        angle, rate, _ = crane.drive("slewing")
        w = accel_ref
        if regulator is not None:
            luffing = crane.drive("luffing")[0]
            w += regulator.feedback(luffing, np.array([s, s_rate, angle - u_ref, rate - rate_ref]))
        w = float(np.clip(w, -max_acceleration, max_acceleration))
        crane.set_drive_acceleration("slewing", w)
        crane.advance(period)
        s, _, radial = tangential_sway(crane, rest)
        out["time"].append(crane.time - t0)
        out["sway"].append(s)
        out["radial"].append(radial)
        out["angle"].append(crane.drive("slewing")[0])
        out["acceleration"].append(w)
        out["rope"].append(float(np.max(crane.axial_forces("hoisting_rope"))))
    return {k: np.array(v) for k, v in out.items()}


def summary(run, slew_time, threshold=0.1):
    """Residual sway amplitude after the slew, settling time (from the slew's start until the sway
    stays within `threshold` m), the rope's peak tension."""
    after = run["time"] >= slew_time
    residual = float(np.max(np.abs(run["sway"][after])))
    outside = np.nonzero(np.abs(run["sway"]) > threshold)[0]
    settled = float(run["time"][outside[-1]]) if outside.size else 0.0
    if outside.size and outside[-1] == len(run["time"]) - 1:
        settled = math.inf
    return {"residual_sway": residual, "settling_time": settled, "rope_peak": float(np.max(run["rope"])),
            "final_angle": float(run["angle"][-1])}
