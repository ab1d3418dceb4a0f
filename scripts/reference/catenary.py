#!/usr/bin/env python3
"""Elastic catenary (Irvine, Cable Structures, MIT Press 1981, section 2.2): an extensible rope of
unstretched length L0, weight w per unstretched length and axial stiffness EA hanging between two
supports at the same height, span l. Lagrangian coordinate s along the unstretched rope, support
forces H (horizontal) and V = w L0 / 2 (vertical):

  dx/ds = H / T + H / EA,   dz/ds = -(V - w s) / T - (V - w s) / EA,   T = sqrt(H^2 + (V - w s)^2)

H follows from x(L0) = l (bisection); the sag is -z(L0 / 2), the end tension T(0).
Prints the reference numbers of verification/cases/rope_catenary_*.check.yaml. Standard library only.
"""
import math


def integrate(H, w, L0, EA, s_end, n=20000):
    V = 0.5 * w * L0
    x = z = 0.0
    h = s_end / n
    def f(s):
        v = V - w * s
        T = math.hypot(H, v)
        return H / T + H / EA, -v / T - v / EA
    # Simpson's rule on both integrands.
    for i in range(n + 1):
        c = 1 if i in (0, n) else (4 if i % 2 else 2)
        fx, fz = f(i * h)
        x += c * fx
        z += c * fz
    return x * h / 3, z * h / 3


def elastic_catenary(span, L0, w, EA):
    lo, hi = 1e-6 * w * L0, 1e6 * w * L0
    for _ in range(200):
        H = math.sqrt(lo * hi)
        x, _ = integrate(H, w, L0, EA, L0, 2000)
        if x > span:
            hi = H
        else:
            lo = H
    H = math.sqrt(lo * hi)
    _, z_mid = integrate(H, w, L0, EA, 0.5 * L0)
    V = 0.5 * w * L0
    return {"H": H, "V": V, "T_end": math.hypot(H, V), "sag": -z_mid}


def main():
    rho, E, r, g = 7850.0, 1.0e11, 0.01, 9.81
    A = math.pi * r * r
    w, EA = rho * A * g, E * A
    for name, span, L0 in (("sagging", 100.0, 102.0), ("taut", 100.0, 99.9)):
        c = elastic_catenary(span, L0, w, EA)
        print(f"{name}: span {span} m, L0 {L0} m, w {w:.10g} N/m, EA {EA:.10g} N")
        print(f"  H = {c['H']:.10g} N, V = {c['V']:.10g} N, end tension {c['T_end']:.10g} N, sag {c['sag']:.10g} m")


if __name__ == "__main__":
    main()
