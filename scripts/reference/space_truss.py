#!/usr/bin/env python3
"""Hand calculation of the statically determinate space truss of verification/cases/space_truss.yaml.

Member forces by the method of joints (node B first: its three bars are the only unknowns there,
then node A), support reactions from the bars meeting at each support, and the displacement of
the loaded nodes by the unit-load method (virtual work, delta = sum N n L / (E A)).
Linear theory: latticedyn's large-deformation result agrees to the order of the strains (1e-4).
Prints the numbers the verification case checks.
"""
import math

import numpy as np

E = 2.06e11
A = math.pi * (0.03**2 - 0.025**2)
nodes = {
    "s1": np.array([0.0, 0.0, 0.0]),
    "s2": np.array([3.0, 0.0, 0.0]),
    "s3": np.array([1.5, 2.6, 0.0]),
    "s4": np.array([3.5, 5.0, 0.0]),
    "A": np.array([1.5, 0.866, 3.0]),
    "B": np.array([2.0, 4.0, 2.0]),
}
bars = {  # name: (first node, second node) as in the YAML ends
    "bar1": ("s1", "A"), "bar2": ("s2", "A"), "bar3": ("s3", "A"),
    "bar4": ("A", "B"), "bar5": ("s3", "B"), "bar6": ("s4", "B"),
}
loads = {"A": np.array([2000.0, -1000.0, -10000.0]), "B": np.array([0.0, 3000.0, -5000.0])}


def member_forces(load_at):
    """Tension-positive axial forces for nodal loads load_at = {node: force}."""
    def unit(bar, at):  # unit vector from node `at` along the bar, away from it
        a, b = bars[bar]
        other = b if a == at else a
        d = nodes[other] - nodes[at]
        return d / np.linalg.norm(d)
    N = {}
    # Node B: N4 u(B->A) + N5 u(B->s3) + N6 u(B->s4) + P_B = 0 (tension pulls the node along the bar).
    M = np.column_stack([unit("bar4", "B"), unit("bar5", "B"), unit("bar6", "B")])
    N["bar4"], N["bar5"], N["bar6"] = np.linalg.solve(M, -load_at.get("B", np.zeros(3)))
    M = np.column_stack([unit("bar1", "A"), unit("bar2", "A"), unit("bar3", "A")])
    rhs = -load_at.get("A", np.zeros(3)) - N["bar4"] * unit("bar4", "A")
    N["bar1"], N["bar2"], N["bar3"] = np.linalg.solve(M, rhs)
    return N


def length(bar):
    a, b = bars[bar]
    return np.linalg.norm(nodes[b] - nodes[a])


N = member_forces(loads)
for k in sorted(N):
    print(f"{k}: axial force {N[k]:.6f} N")
for node in ("A", "B"):
    for i, c in enumerate("xyz"):
        unit_load = np.zeros(3)
        unit_load[i] = 1.0
        n = member_forces({node: unit_load})
        delta = sum(N[b] * n[b] * length(b) / (E * A) for b in bars)
        print(f"displacement {node}.{c}: {delta:.9e} m")
# Reaction at s3: the two bars there pull the support along themselves.
r3 = sum(N[b] * (nodes["A" if b == "bar3" else "B"] - nodes["s3"]) / length(b) for b in ("bar3", "bar5"))
print("force of the bars on support s3:", r3)
