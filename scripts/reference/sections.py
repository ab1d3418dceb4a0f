#!/usr/bin/env python3
"""Closed forms behind the section verification cases (verification/cases/section_*.yaml).

frame cantilever: Timoshenko tip deflection of a clamped beam under a tip force,
    delta = P L^3 / (3 E I) + P L / (kappa G A)   (Timoshenko & Gere, Mechanics of Materials, 9.11),
    rectangular hollow section (height h along z, width b along y, wall t) with kappa the web
    area over the area in the weaker direction, min(2 h t, 2 b t) / A, as elements/section.cpp.
frame cantilever, stresses: the root section carries My = Pz L, Mz = Py L, Qz = -Pz, Qy = Py (statics of
    the cantilever); the largest normal stress is at a corner, sigma = |My| h / (2 Iy) + |Mz| b / (2 Iz)
    (Navier), and with no torque it is the largest von Mises stress; utilization sigma / f_y with
    f_y = 355 MPa (S355).
custom cantilever: Euler-Bernoulli tip deflection P L^3 / (3 E I) and the first two bending
    frequencies f = lambda^2 / (2 pi) sqrt(E I / (mu L^4)), lambda = 1.8751040687 (Blevins,
    Formulas for Natural Frequency and Mode Shape, Table 8-1), with mu the section's own mass per
    length (not rho A).
"""
import math

E, NU = 2.1e11, 0.3
G = E / (2 * (1 + NU))

# frame: h = 0.3, b = 0.2, t = 0.01, L = 5, P = (0, Py, Pz) = (0, 4e3, -1e4)
h, b, t, L = 0.3, 0.2, 0.01, 5.0
hi, bi = h - 2 * t, b - 2 * t
A = b * h - bi * hi
Iy = (b * h**3 - bi * hi**3) / 12
Iz = (h * b**3 - hi * bi**3) / 12
kappa = min(2 * h * t, 2 * b * t) / A
for name, P, I in (("frame uz", -1e4, Iy), ("frame uy", 4e3, Iz)):
    print(f"{name}: {P * L**3 / (3 * E * I) + P * L / (kappa * G * A):.10e}"
          f"  (bending {P * L**3 / (3 * E * I):.6e}, shear {P * L / (kappa * G * A):.6e})")

My, Mz = 1e4 * L, 4e3 * L
sigma = My * h / (2 * Iy) + Mz * b / (2 * Iz)
print(f"frame root: My = {My:.6e} N m, Mz = {Mz:.6e} N m, corner sigma = {sigma:.10e} Pa, utilization {sigma / 355e6:.10f}")

# custom: A = 0.01, Iy = 2e-4, Iz = 5e-5, mass 150 kg/m, L = 8, P = (0, 2e3, 5e3)
L, Iy, Iz, mu = 8.0, 2e-4, 5e-5, 150.0
print(f"custom uz: {5e3 * L**3 / (3 * E * Iy):.10e}")
print(f"custom uy: {2e3 * L**3 / (3 * E * Iz):.10e}")
lam = 1.8751040687
for I in (Iz, Iy):
    print(f"custom f: {lam**2 / (2 * math.pi) * math.sqrt(E * I / (mu * L**4)):.10f} Hz")
