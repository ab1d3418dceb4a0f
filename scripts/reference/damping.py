#!/usr/bin/env python3
"""Reference damping ratios of the damping verification cases (prints them; the check files hold them).

Rayleigh damping C = alpha M + beta K gives mode i the ratio zeta_i = alpha / (2 omega_i) +
beta omega_i / 2 (Chopra, Dynamics of Structures, 4th ed., 11.4); a damping ratio given at a
frequency f (`damping: {ratio, frequency}`) means beta = 2 zeta / (2 pi f).

- damping_pendulum: physical pendulum (rod 1 m, 2 kg, hinged at its end) with alpha = 0.4 1/s:
  I_O theta'' + alpha I_O theta' + m g d theta = 0, zeta = alpha / (2 omega_n).
- damping_cantilever: steel tube cantilever (L = 4 m, radii 0.05 / 0.04 m) with a ratio of 0.02
  given at 5.75 Hz; its first frequency from Euler-Bernoulli theory, omega_1 = 1.8751041^2
  sqrt(EI / (rho A L^4)) (slender: L / r_g = 125, shear and rotary inertia change it by ~1e-4).
- damping_rope: a 1000 kg load on a 10 m steel wire (r = 10 mm), ratio 0.05 given at 12.56 Hz.
  The rope is a Kelvin-Voigt bar with its own mass: the first longitudinal mode of a bar with a
  tip mass, x tan x = m_rope / m_load, omega_1 = x c / L, c = sqrt(E / rho); beta K damping is
  proportional to the bar's stiffness, so the mode's ratio is beta omega_1 / 2 exactly.
"""
import math

two_pi = 2 * math.pi

# --- damping_pendulum
m, g, d, I_O, alpha = 2.0, 9.81, 0.5, 2.0 / 3.0, 0.4
omega_n = math.sqrt(m * g * d / I_O)
print(f"damping_pendulum: omega_n = {omega_n:.7f} rad/s, zeta = {alpha / (2 * omega_n):.7f}")

# --- damping_cantilever
E, rho, L, ro, ri = 2.06e11, 7800.0, 4.0, 0.05, 0.04
A = math.pi * (ro**2 - ri**2)
I = math.pi / 4 * (ro**4 - ri**4)
omega_1 = 1.8751040687**2 * math.sqrt(E * I / (rho * A * L**4))
beta = 2 * 0.02 / (two_pi * 5.75)
print(f"damping_cantilever: f_1 = {omega_1 / two_pi:.6f} Hz, beta = {beta:.6e} s, zeta = {beta * omega_1 / 2:.7f}")

# --- damping_rope
E, rho, r, L, m_load = 2.0e11, 7850.0, 0.01, 10.0, 1000.0
A = math.pi * r**2
mu = rho * A * L / m_load
x = math.sqrt(mu)  # x tan x = mu by Newton from the small-mu root
for _ in range(50):
    x -= (x * math.tan(x) - mu) / (math.tan(x) + x / math.cos(x)**2)
omega_1 = x * math.sqrt(E / rho) / L
beta = 2 * 0.05 / (two_pi * 12.56)
print(f"damping_rope: f_1 = {omega_1 / two_pi:.6f} Hz, beta = {beta:.6e} s, zeta = {beta * omega_1 / 2:.7f}")
