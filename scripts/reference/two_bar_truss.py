#!/usr/bin/env python3
"""The two-bar (von Mises) truss of verification/cases/path_two_bar_truss.yaml in closed form.

Bars from (+-a, 0) to the apex at height h, E A, rest length L0 = sqrt(a^2 + h^2), engineering
strain (the strut tie's): with the apex lowered by w, l = sqrt(a^2 + (h - w)^2), N = E A (l / L0 - 1)
and the vertical equilibrium of the apex gives P(w) = 2 E A (1 - l / L0) (h - w) / l (e.g.
Crisfield, Non-linear Finite Element Analysis of Solids and Structures, vol. 1, 1991, 1.2 and 9.1;
Bazant & Cedolin, Stability of Structures, 2.7). Its limit points: dP/dw = 0, i.e.
(h - w)^2 = a^2 ((L0 / a)^(2/3) - 1), symmetric about w = h.
"""
import math

a, h, EA, P = 1.0, 0.2, 1.0e6, 1000.0
L0 = math.hypot(a, h)


def load(w):
    l = math.hypot(a, h - w)
    return 2 * EA * (1 - l / L0) * (h - w) / l


d = a * math.sqrt((L0 / a) ** (2.0 / 3.0) - 1)  # h - w at the limit points
for name, w in (("maximum", h - d), ("minimum", h + d)):
    print(f"{name}: w = {w:.10f} m, P = {load(w):.10f} N, load factor {load(w) / P:.10f}")
