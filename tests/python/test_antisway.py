"""Closed-loop anti-sway control (python/latticedyn_antisway.py, docs/control.md "Closed loop"):
the regulator's numerics against closed forms, and the 45-degree slew in 15 s on the nonlinear
crane, closed loop against open loop. Run by ctest (python.antisway)."""
import math
import os
import sys
import unittest

import numpy as np

import latticedyn_antisway as antisway

sys.path.insert(0, os.path.join(os.environ["LATTICEDYN_SOURCE_DIR"], "examples", "api"))
import anti_sway  # noqa: E402

MODEL = os.path.join(os.environ["LATTICEDYN_SOURCE_DIR"], "examples", "api", "crane_external.yaml")


class RegulatorNumericsTest(unittest.TestCase):
    def test_continuous_riccati_of_a_double_integrator(self):
        # x'' = v with Q = I, R = 1: K = [1, sqrt(3)] (e.g. Anderson & Moore, Optimal Control).
        a = np.array([[0.0, 1.0], [0.0, 0.0]])
        b = np.array([[0.0], [1.0]])
        np.testing.assert_allclose(antisway.lqr(a, b, np.eye(2), np.eye(1)), [[1.0, math.sqrt(3.0)]], atol=1e-12)

    def test_discrete_gain_tends_to_the_continuous_one_for_short_periods(self):
        omega, r = 0.415, 6.7
        q, rr = np.diag([10.0, 10.0, 10.0, 1.0]), np.eye(1)
        a = np.array([[0, 1, 0, 0], [-omega**2, 0, 0, 0], [0, 0, 0, 1], [0, 0, 0, 0]], dtype=float)
        b = np.array([[0.0], [-r], [0.0], [1.0]])
        continuous = antisway.lqr(a, b, q, rr)
        errors = []
        for h in (1e-2, 1e-3):  # the discrete weights Q h, R h of the sampled cost
            ad, bd = antisway.sampled_model(omega, r, h)
            errors.append(np.max(np.abs(antisway.dlqr(ad, bd, q * h, rr * h) / continuous - 1)))
        self.assertLess(errors[1], 0.02)
        self.assertLess(errors[1], errors[0] / 5)  # first order in h
        # The sampled model in closed form: the oscillator's cosine, the double integrator's h^2 / 2.
        h = 0.1
        ad, bd = antisway.sampled_model(omega, r, h)
        self.assertAlmostEqual(ad[0, 0], math.cos(omega * h), places=14)
        self.assertAlmostEqual(bd[2, 0], h * h / 2, places=14)


class SlewStudyTest(unittest.TestCase):
    def test_the_closed_loop_damps_the_sway_of_a_fast_slew(self):
        regulator, runs, summaries = anti_sway.study(MODEL)
        opened, closed = summaries["open loop"], summaries["closed loop"]
        self.assertGreater(opened["residual_sway"], 1.5)          # about 2 m left swinging
        self.assertLess(closed["residual_sway"], opened["residual_sway"] / 3)
        self.assertTrue(math.isinf(opened["settling_time"]))
        self.assertLess(closed["settling_time"], 40.0)
        self.assertLess(abs(math.degrees(closed["final_angle"]) - 45.0), 1.0)
        self.assertLess(closed["rope_peak"], 1.01 * opened["rope_peak"])
        # Scheduled: the gains differ between the designs at different boom angles.
        self.assertFalse(np.allclose(regulator.gains[0], regulator.gains[-1], rtol=1e-6))


if __name__ == "__main__":
    unittest.main()
