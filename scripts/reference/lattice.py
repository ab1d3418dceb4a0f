#!/usr/bin/env python3
"""Equivalent beam of a rectangular lattice boom (four chords, Warren faces, no verticals), for
the closed-form checks of the full lattice model (verification/cases/lattice_*.check.yaml).

  EA    = E * 4 A_chord                         (chords parallel to the axis)
  EI_y  = E * A_chord * 4 (h/2)^2,  EI_z = E * A_chord * 4 (w/2)^2   (parallel-axis sums)
  GA_z  = 2 E A_d h^2 a / d^3 over the two faces of height h (one diagonal per bay of length a,
          d = sqrt(a^2 + h^2): the diagonal's stretch under the bay's shear), GA_y likewise
  tip deflections of a cantilever: F L / EA; F L^3 / (3 EI) + F L / GA (Timoshenko beam theory)
  first bending frequencies: Euler-Bernoulli cantilever with mass per length mu (chords and
          diagonals) and a tip mass M_t (the tip's cross-section beams), lambda the root of
          1 + cos l cosh l + (M_t / (mu L)) l (cos l sinh l - sin l cosh l) = 0 (Blevins,
          Formulas for Natural Frequency and Mode Shape, Table 8-8); f = l^2 / (2 pi) sqrt(EI / (mu L^4))
Standard library only; prints the numbers the check files hold.
"""
import math


def tube_area(ro, ri):
    return math.pi * (ro * ro - ri * ri)


def cantilever_lambda(tip_ratio):
    """First root of the cantilever-with-tip-mass frequency equation, by bisection."""
    def f(x):
        return (1 + math.cos(x) * math.cosh(x)
                + tip_ratio * x * (math.cos(x) * math.sinh(x) - math.sin(x) * math.cosh(x)))
    lo, hi = 0.5, 1.8751040687
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(lo) * f(mid) <= 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def main():
    E = 2.06e11
    L, order = 60.0, 24
    w, h = 3.0, 2.8            # chord spacing along y and z
    A = tube_area(0.1, 0.08)   # chords
    Ad = tube_area(0.05, 0.04)  # diagonals
    a = L / order
    EA = 4 * E * A
    EIy = E * A * 4 * (h / 2) ** 2
    EIz = E * A * 4 * (w / 2) ** 2
    dz, dy = math.hypot(a, h), math.hypot(a, w)
    GAz = 2 * E * Ad * h * h * a / dz ** 3
    GAy = 2 * E * Ad * w * w * a / dy ** 3
    Fx, Fy, Fz = 1.0e5, 1.0e4, 1.0e4
    ux = Fx * L / EA
    uz_bend, uz_shear = Fz * L ** 3 / (3 * EIy), Fz * L / GAz
    uy_bend, uy_shear = Fy * L ** 3 / (3 * EIz), Fy * L / GAy
    print(f"L = {L} m, order {order}: EA = {EA:.6g} N, EIy = {EIy:.6g}, EIz = {EIz:.6g} N m^2, "
          f"GAz = {GAz:.6g}, GAy = {GAy:.6g} N")
    print(f"axial: F = {Fx:g} N -> u_x = {ux:.10g} m")
    print(f"z: F = {Fz:g} N -> bending {uz_bend:.10g} + shear {uz_shear:.10g} = {uz_bend + uz_shear:.10g} m")
    print(f"y: F = {Fy:g} N -> bending {uy_bend:.10g} + shear {uy_shear:.10g} = {uy_bend + uy_shear:.10g} m")
    rho = 7800.0
    mu = rho * (4 * A * L + order * 2 * (dz + dy) * Ad) / L   # one diagonal per bay in each of 4 faces
    tip = rho * A * 2 * (w + h)                           # the four cross-section beams of end 2
    lam = cantilever_lambda(tip / (mu * L))
    for name, EI in (("vertical (about y)", EIy), ("lateral (about z)", EIz)):
        f = lam ** 2 / (2 * math.pi) * math.sqrt(EI / (mu * L ** 4))
        print(f"first {name} bending frequency: mu = {mu:.6g} kg/m, M_t = {tip:.6g} kg, "
              f"lambda = {lam:.8g}: f = {f:.10g} Hz")


if __name__ == "__main__":
    main()
