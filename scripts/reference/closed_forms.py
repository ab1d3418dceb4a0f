#!/usr/bin/env python3
"""Closed-form reference numbers of the verification cases (prints them; the check files hold them).

- pendulum: exact period of a physical pendulum, T = 4 K(k) / omega0 with k = sin(theta0 / 2),
  omega0^2 = m g d / I_O (e.g. Landau & Lifshitz, Mechanics, section 11, problem 1); K by the
  arithmetic-geometric mean.
- conical pendulum: steady precession of a rod + bob at cone angle theta,
  Omega^2 = (m_r L / 2 + m_b L) g / (I_O cos theta), I_O = m_r L^2 / 3 + rho I_m L + m_b L^2
  (Lagrange's equations for T = I_O/2 (theta_dot^2 + sin^2 theta psi_dot^2)).
- block on an incline: s(t) = g sin(alpha) t^2 / 2 along the incline, normal force m g cos(alpha).
- elastica: a cantilever under a transverse tip load, EI theta'' + P cos(theta) = 0 with
  theta(0) = 0, theta'(L) = 0, solved by shooting on theta'(0) (fourth-order Runge-Kutta, 20,000
  steps); it reproduces Mattiasson's elliptic-integral table (Int. J. Numer. Meth. Engng 17 (1981)
  145-153) at P L^2 / EI = 1, 3, 10.
"""
import math


def agm(a, b):
    while abs(a - b) > 1e-15 * a:
        a, b = (a + b) / 2, math.sqrt(a * b)
    return a


g = 9.81
# --- physical pendulum (examples/pendulum.yaml): rod 1 m, 2 kg, released at 10 degrees
m, L, theta0 = 2.0, 1.0, math.radians(10)
I_O = m * L**2 / 3
omega0 = math.sqrt(m * g * (L / 2) / I_O)
k = math.sin(theta0 / 2)
K = math.pi / (2 * agm(1.0, math.sqrt(1 - k * k)))
print(f"pendulum: small-amplitude period {2 * math.pi / omega0:.10f} s, at 10 deg {4 * K / omega0:.10f} s")

# --- conical pendulum (verification/cases/conical_pendulum.yaml)
rho, r, Lr, mb, theta = 7800.0, 0.01, 1.0, 5.0, math.radians(30)
mr = rho * math.pi * r**2 * Lr
I_m = math.pi * r**4 / 4  # (Iy + Iz) / 2 of a solid round section
I_O = mr * Lr**2 / 3 + rho * I_m * Lr + mb * Lr**2
Omega = math.sqrt((mr * Lr / 2 + mb * Lr) * g / (I_O * math.cos(theta)))
print(f"conical pendulum: rod mass {mr:.10f} kg, Omega {Omega:.10f} rad/s, period {2 * math.pi / Omega:.10f} s")
print(f"  bob at ({Lr * math.sin(theta):.10f}, 0, {-Lr * math.cos(theta):.10f}), speed {Omega * Lr * math.sin(theta):.10f} m/s")

# --- block on an incline (verification/cases/incline.yaml): alpha = 30 deg, m = 5 kg
alpha, mblk = math.radians(30), 5.0
for t in (0.5, 1.0, 1.5):
    s = 0.5 * g * math.sin(alpha) * t * t
    print(f"incline: t = {t}: s = {s:.10f}, x = {s * math.cos(alpha):.10f}, z = {-s * math.sin(alpha):.10f}")
print(f"incline: normal force {mblk * g * math.cos(alpha):.10f} N")

# --- elastica (verification/cases/elastica.yaml): tip displacements for P L^2 / EI = alpha


def elastica_tip(alpha, steps=20000):
    """(u/L, w/L, tip rotation) of the inextensible cantilever elastica, arc length s in [0, 1]."""

    def integrate(k0, n):
        h = 1.0 / n
        state = [0.0, k0, 0.0, 0.0]  # theta, theta', x, z

        def rate(st):
            return [st[1], -alpha * math.cos(st[0]), math.cos(st[0]), math.sin(st[0])]

        for _ in range(n):
            k1 = rate(state)
            k2 = rate([a + h / 2 * b for a, b in zip(state, k1)])
            k3 = rate([a + h / 2 * b for a, b in zip(state, k2)])
            k4 = rate([a + h * b for a, b in zip(state, k3)])
            state = [a + h / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(state, k1, k2, k3, k4)]
        return state

    lo, hi = 0.0, alpha  # theta'(0) = curvature at the clamp, between 0 and P L^2 / EI
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if integrate(mid, 2000)[1] > 0:
            hi = mid
        else:
            lo = mid
    theta, _, x, z = integrate(0.5 * (lo + hi), steps)
    return 1.0 - x, z, theta


for a in (1.0, 3.0, 10.0):
    u, w, th = elastica_tip(a)
    print(f"elastica: P L^2 / EI = {a:g}: u/L = {u:.5f}, w/L = {w:.5f}, tip rotation {th:.5f} rad")


# --- relief valve steady pressure (verification/cases/hydraulic_relief_valve.yaml,
# hydraulic_end_stop.yaml): the orifice equation with the valve's opening law, Q = C_d x(dp) A
# sqrt(2 / rho) dp / (dp^2 + p_t^2)^(1/4), x the smoothstep from cracking to full-open pressure
# (Merritt, Hydraulic Control Systems, 1967, 3.2), solved for dp by bisection.
def relief_pressure(flow, area, cracking, full_open, cd=0.62, rho=870.0, pt=1e4):
    def passed(dp):
        y = min(max((dp - cracking) / (full_open - cracking), 0.0), 1.0)
        return cd * y * y * (3 - 2 * y) * area * math.sqrt(2 / rho) * dp / (dp * dp + pt * pt) ** 0.25
    lo, hi = cracking, 10 * full_open
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if passed(mid) < flow else (lo, mid)
    return 0.5 * (lo + hi)


print(f"relief valve: 0.1 l/s through 10 mm^2 (200/220 bar): {relief_pressure(1e-4, 1e-5, 2e7, 2.2e7):.9f} Pa")
# End stop: a pump (0.5 l/s) drives a cylinder (piston 100 mm) to full stroke; the relief valve
# then passes the whole flow, and the stop (k = 1e8 N/m, C1 over w = 0.1 mm) carries p_1 A_1:
# travel past the stop d = p_1 A_1 / k + w / 2 (the spring's force k (d - w / 2) past w).
p1 = relief_pressure(5e-4, 1e-5, 2e7, 2.2e7)
A1 = math.pi / 4 * 0.1**2
print(f"end stop: cap pressure {p1:.9f} Pa, rod end at x = {0.5 + 0.2 + p1 * A1 / 1e8 + 0.5e-4:.12f} m")
