"""The Python bindings of the facade (python/latticedyn_module.cpp): NumPy outputs, external drives,
saved states and the exceptions, on the physical pendulum and a rod turned by an external drive.
Run by ctest (python.simulator) with the module's folder on PYTHONPATH."""
import math
import os
import unittest

import numpy as np

import latticedyn

PENDULUM = os.environ["PENDULUM_MODEL"]

TURNED_ROD = os.environ["TURNED_ROD_MODEL"]


class PendulumTest(unittest.TestCase):
    def test_statics_hang_the_pendulum_straight_down(self):
        sim = latticedyn.Simulator(PENDULUM)
        summary = sim.solve_statics()
        self.assertGreater(summary["newton_iterations"], 0)
        tip = sim.joint_position("rod.tip")
        self.assertIsInstance(tip, np.ndarray)
        np.testing.assert_allclose(tip, [0.0, 0.0, -1.0], atol=1e-9)
        # The hinge carries the weight m g (2 kg).
        np.testing.assert_allclose(sim.constraint_reaction("hinge")["force"], [0.0, 0.0, 2.0 * 9.81], atol=1e-6)
        self.assertAlmostEqual(sim.energy()["gravity_potential"], -9.81, places=8)

    def test_half_a_period_swings_it_to_the_other_side(self):
        # Period 2 pi sqrt(I_O / (m g d)) (1 + theta^2 / 16) at 10 degrees (Landau & Lifshitz, section 11).
        sim = latticedyn.Simulator(PENDULUM)
        theta = math.radians(10.0)
        period = 2 * math.pi * math.sqrt((2.0 / 3.0) / (2.0 * 9.81 * 0.5)) * (1 + theta**2 / 16)
        sim.advance(period / 2)
        self.assertAlmostEqual(sim.time, period / 2, places=12)
        np.testing.assert_allclose(sim.joint_position("rod.tip")[[0, 2]], [math.sin(theta), -math.cos(theta)], atol=2e-4)
        probes = sim.probes()
        self.assertEqual(probes.shape, (6,))
        self.assertEqual(sim.joint_orientation("rod.tip").shape, (3, 3))

    def test_overrides_replace_keys(self):
        sim = latticedyn.Simulator(PENDULUM, {"solver.dynamics.time_step": "0.001"})
        self.assertEqual(sim.time_step, 0.001)
        sim.advance(0.01)
        self.assertEqual(sim.steps, 10)


class ExternalDriveTest(unittest.TestCase):
    def test_the_rod_turns_with_the_rate_set_from_python(self):
        sim = latticedyn.Simulator(TURNED_ROD)
        self.assertEqual(sim.external_drive_names, ["turn"])
        sim.solve_statics()
        sim.set_drive_rate("turn", 0.5)
        sim.advance(1.0)
        sim.set_drive_acceleration("turn", 1.0)
        sim.advance(1.0)
        value, rate, acceleration = sim.drive("turn")
        self.assertAlmostEqual(value, 1.5, places=13)
        self.assertAlmostEqual(rate, 1.5, places=13)
        self.assertEqual(acceleration, 1.0)
        np.testing.assert_allclose(sim.joint_position("rod.tip")[:2], [math.cos(1.5), math.sin(1.5)], atol=1e-8)

    def test_a_restored_state_advances_the_same_every_time(self):
        sim = latticedyn.Simulator(TURNED_ROD)
        sim.set_drive_rate("turn", 0.3)
        sim.advance(0.3)
        saved = sim.save_state()
        self.assertAlmostEqual(saved.time, 0.3, places=12)
        runs = []
        for _ in range(2):
            sim.restore_state(saved)
            sim.set_drive_acceleration("turn", 2.0)
            sim.advance(0.3)
            runs.append(sim.coordinates())
        np.testing.assert_array_equal(runs[0], runs[1])


class LinearModelTest(unittest.TestCase):
    def test_the_linear_crane_has_the_frequencies_of_its_modes(self):
        crane = latticedyn.Simulator(os.environ["CRANE_EXTERNAL_MODEL"])
        crane.solve_statics()
        lm = crane.linearize(["slewing", "hoisting"])
        n = 2 * lm["independent"]
        self.assertEqual(lm["A"].shape, (n + 4, n + 4))
        self.assertEqual(lm["B"].shape, (n + 4, 2))
        self.assertEqual(lm["C"].shape, (6, n + 4))
        self.assertEqual(lm["outputs"][0], "load.1.x")
        eigenvalues = np.linalg.eigvals(lm["A"][:n, :n])
        linear = np.sort(np.abs(eigenvalues[eigenvalues.imag > 0])) / (2 * np.pi)
        modes = np.array(crane.natural_frequencies(6))
        # The lowest mode is a mechanism's zero (the hook block turning about its rope): compared
        # where the frequencies are not zero.
        linear, modes = linear[linear > 1e-3], modes[modes > 1e-3]
        np.testing.assert_allclose(linear[:len(modes)], modes, rtol=1e-5)


class ErrorTest(unittest.TestCase):
    def test_errors_are_python_exceptions_that_say_what_is_wrong(self):
        with self.assertRaises(latticedyn.InputError) as bad:
            latticedyn.Simulator.from_string("title: [", "broken.yaml")
        self.assertIn("broken.yaml", str(bad.exception))
        self.assertTrue(issubclass(latticedyn.InputError, ValueError))
        sim = latticedyn.Simulator(TURNED_ROD, {"solver.dynamics.max_steps": "3"})
        with self.assertRaisesRegex(ValueError, "no joint 'rod.nose'"):
            sim.joint_position("rod.nose")
        with self.assertRaisesRegex(latticedyn.SolverError, "max_steps = 3"):
            sim.advance(1.0)
        self.assertAlmostEqual(sim.time, 0.03, places=12)


if __name__ == "__main__":
    unittest.main()
