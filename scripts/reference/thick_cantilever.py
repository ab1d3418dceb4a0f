#!/usr/bin/env python3
"""First bending frequency of a thick cantilever with rotary inertia and no shear (a Rayleigh
beam: what the cubic spline beam models), for verification/cases/spline_thick_cantilever*.yaml.

Euler-Bernoulli: f = (beta L)^2 / (2 pi L^2) sqrt(EI / rho A), beta L = 1.875104 (Meirovitch,
Fundamentals of Vibrations, 7.8). Rotary inertia by Rayleigh's quotient with the Euler-Bernoulli
mode phi (Rayleigh, Theory of Sound, 1877, 186): omega^2 = int EI phi''^2 / (int rho A phi^2 +
int rho I phi'^2), exact to second order in the slenderness r / L.
"""
import math

import numpy as np

E, RHO, R, L = 2.06e11, 7800.0, 0.1, 1.0
A, I = math.pi * R * R, math.pi * R**4 / 4
BL = 1.8751040687119611
s = (math.cosh(BL) + math.cos(BL)) / (math.sinh(BL) + math.sin(BL))
x = np.linspace(0.0, L, 200001)
b = BL / L
phi = np.cosh(b * x) - np.cos(b * x) - s * (np.sinh(b * x) - np.sin(b * x))
dphi = b * (np.sinh(b * x) + np.sin(b * x) - s * (np.cosh(b * x) - np.cos(b * x)))
ddphi = b * b * (np.cosh(b * x) + np.cos(b * x) - s * (np.sinh(b * x) + np.sin(b * x)))
f_eb = BL**2 / (2 * math.pi * L**2) * math.sqrt(E * I / (RHO * A))
w2 = np.trapz(E * I * ddphi**2, x) / (np.trapz(RHO * A * phi**2, x) + np.trapz(RHO * I * dphi**2, x))
print(f"Euler-Bernoulli {f_eb:.6f} Hz; with rotary inertia (Rayleigh quotient) {math.sqrt(w2) / (2 * math.pi):.6f} Hz")
