#!/usr/bin/env python3
"""Closed-form buckling loads of the verification cases verification/cases/buckling_*.yaml.

Euler columns (Timoshenko & Gere, Theory of Elastic Stability, 2nd ed. 1961, 2.1-2.3): P_cr =
c EI / L^2 with c = pi^2/4 (fixed-free), pi^2 (pinned-pinned), 20.1907 (fixed-pinned, the root
kL = 4.4934 of tan kL = kL) and 4 pi^2 (fixed-fixed), lowered by shear (Engesser, ibid. 2.16):
P_cr / (1 + P_cr / (kappa G A)), kappa Cowper's 6 (1 + nu) / (7 + 6 nu) of the solid circle.

Lateral-torsional buckling of a cantilever with a point load at the centroid of its free end's
section (ibid. 6.3, eq. 6-24): P_cr = 4.013 sqrt(E I_z G J) / L^2 for a narrow rectangle (warping
rigidity negligible), in-plane prebuckling deflection neglected (I_z / I_y = 0.0025 here: the
correction 1 / sqrt((1 - I_z/I_y)(1 - G J / E I_y)) is +0.3 %).
"""
import math

E, NU, R, L, P = 2.06e11, 0.3, 0.05, 10.0, 1.0e4
A = math.pi * R * R
I = A * R * R / 4
G = E / (2 * (1 + NU))
KAPPA = 6 * (1 + NU) / (7 + 6 * NU)
BETA_FIXED_PINNED = 4.493409457909064  # tan x = x

for name, c in [("fixed_free", math.pi**2 / 4), ("pinned_pinned", math.pi**2),
                ("fixed_pinned", BETA_FIXED_PINNED**2), ("fixed_fixed", 4 * math.pi**2)]:
    pe = c * E * I / L**2
    pcr = pe / (1 + pe / (KAPPA * G * A))
    print(f"{name:14s} P_E = {pe:.6f} N, with shear {pcr:.6f} N, load factor for P = {P:g} N: {pcr / P:.10f}")

# Lateral-torsional: steel blade 0.2 m deep (z) and 0.01 m wide (y), 4 m long, tip load 100 N.
h, b, Lb, Pb = 0.2, 0.01, 4.0, 100.0
Iy, Iz = b * h**3 / 12, h * b**3 / 12
J = h * b**3 / 3 * (1 - 0.63 * b / h)  # Roark, Table 10.1 case 4 (narrow rectangle)
pcr = 4.013 * math.sqrt(E * Iz * G * J) / Lb**2
print(f"lateral-torsional: A = {b*h:.6g}, Iy = {Iy:.6g}, Iz = {Iz:.6g}, J = {J:.6g}; P_cr = {pcr:.6f} N, "
      f"load factor for P = {Pb:g} N: {pcr / Pb:.10f}; with the prebuckling correction "
      f"{pcr / math.sqrt((1 - Iz / Iy) * (1 - G * J / (E * Iy))) / Pb:.10f}")

# The slender lattice of verification/cases/buckling_lattice_column.yaml (scripts/reference/lattice.py):
# a fixed-free column of the chords' parallel-axis EI about y (the weaker plane, chords 2.8 m apart
# in z), lowered by the shear flexibility of its two Warren faces (Engesser: P_E / (1 + P_E / GA_z);
# Timoshenko & Gere 2.17 for laced columns), for a head load of 1 MN.
Ll, order, hz = 60.0, 24, 2.8
Ac, Ad = math.pi * (0.1**2 - 0.08**2), math.pi * (0.05**2 - 0.04**2)
a = Ll / order
EIy = E * Ac * 4 * (hz / 2) ** 2
d = math.hypot(a, hz)
GAz = 2 * E * Ad * hz * hz * a / d**3
pe = math.pi**2 * EIy / (4 * Ll**2)
pcr = pe / (1 + pe / GAz)
print(f"lattice column: EI_y = {EIy:.6g}, GA_z = {GAz:.6g}; P_E = {pe:.6f} N, with shear {pcr:.6f} N, "
      f"load factor for 1 MN: {pcr / 1e6:.10f}")
