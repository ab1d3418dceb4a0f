#!/usr/bin/env python3
"""Equivalent beam of a rectangular lattice boom (four chords, Warren faces, no verticals), for
the closed-form checks of the full lattice model (verification/cases/lattice_*.check.yaml).

  EA    = E * 4 A_chord                         (chords parallel to the axis)
  EI_y  = E * A_chord * 4 (h/2)^2,  EI_z = E * A_chord * 4 (w/2)^2   (parallel-axis sums)
  GA_z  = 2 E A_d h^2 a / d^3 over the two faces of height h (one diagonal per bay of length a,
          d = sqrt(a^2 + h^2): the diagonal's stretch under the bay's shear), GA_y likewise
  tip deflections of a cantilever: F L / EA; F L^3 / (3 EI) + F L / GA (Timoshenko beam theory)
Standard library only; prints the numbers the check files hold.
"""
import math


def tube_area(ro, ri):
    return math.pi * (ro * ro - ri * ri)


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


if __name__ == "__main__":
    main()
