"""scripts/identify.py (SINDy): recovers a physical pendulum's equation from latticedyn's own
results (theta_ddot = -(3 g / 2 L) sin(theta) for a uniform rod: I_O = m L^2 / 3, d = L / 2), a
Duffing oscillator's coefficients from data written here, and refuses bad input by name."""
import csv
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import yaml

SOURCE = os.environ["LATTICEDYN_SOURCE_DIR"]
sys.path.insert(0, os.path.join(SOURCE, "scripts"))
import identify  # noqa: E402


def identify_to_yaml(args, out):
    code = identify.main(args + ["--out", out])
    assert code == 0, code
    with open(out) as f:
        return yaml.safe_load(f)["equations"]


class Identify(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.tmp = self.dir.name

    def tearDown(self):
        self.dir.cleanup()

    def test_recovers_the_pendulum_from_a_latticedyn_run(self):
        model = os.path.join(SOURCE, "examples", "minimum_dof", "pendulum_swing.yaml")
        run = subprocess.run([os.environ["LATTICEDYN_EXE"], "run", model, "--output", self.tmp],
                             capture_output=True, text=True)
        self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
        probes = os.path.join(self.tmp, "pendulum_swing_probes.csv")
        eq = identify_to_yaml([probes, "--state", "theta = arctan2(rod.tip.x, -rod.tip.z)", "--state",
                               "omega = d(theta)", "--library", "poly:3", "--library", "trig", "--threshold", "0.05",
                               "--plot", os.path.join(self.tmp, "p.png")], os.path.join(self.tmp, "p.yaml"))
        self.assertEqual(list(eq["dtheta/dt"]["terms"]), ["omega"])
        self.assertAlmostEqual(eq["dtheta/dt"]["terms"]["omega"], 1.0, delta=1e-6)
        # Of 14 candidates (polynomials to degree 3, sines and cosines) only sin(theta) remains.
        self.assertEqual(list(eq["domega/dt"]["terms"]), ["sin(theta)"])
        exact = -3 * 9.81 / (2 * 1.0)
        self.assertAlmostEqual(eq["domega/dt"]["terms"]["sin(theta)"], exact, delta=1e-4 * abs(exact))
        self.assertTrue(os.path.getsize(os.path.join(self.tmp, "p.png")) > 10000)

    def test_recovers_a_duffing_oscillator(self):
        # x'' = -x - 0.1 x' - 0.5 x^3, sampled every 0.01 s (RK4 at 1e-3 s) and written as a probe CSV.
        def f(s):
            return np.array([s[1], -s[0] - 0.1 * s[1] - 0.5 * s[0] ** 3])
        h, s, rows = 1e-3, np.array([2.0, 0.0]), []
        for k in range(20001):
            if k % 10 == 0:
                rows.append([k * h, s[0], s[1]])
            k1 = f(s); k2 = f(s + h / 2 * k1); k3 = f(s + h / 2 * k2); k4 = f(s + h * k3)
            s = s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        path = os.path.join(self.tmp, "duffing.csv")
        with open(path, "w", newline="") as out:
            w = csv.writer(out)
            w.writerow(["time [s]", "mass.x [m]", "mass.vx [m/s]"])
            w.writerows(rows)
        eq = identify_to_yaml([path, "--state", "x = mass.x", "--state", "v = mass.vx", "--library", "poly:3",
                               "--threshold", "0.02"], os.path.join(self.tmp, "d.yaml"))
        self.assertEqual(sorted(eq["dv/dt"]["terms"]), ["v", "x", "x*x*x"])
        for term, value in {"x": -1.0, "v": -0.1, "x*x*x": -0.5}.items():
            self.assertAlmostEqual(eq["dv/dt"]["terms"][term], value, delta=1e-4)
        self.assertEqual(list(eq["dx/dt"]["terms"]), ["v"])

    def test_bad_input_is_named(self):
        path = os.path.join(self.tmp, "p.csv")
        with open(path, "w") as out:
            out.write("time [s],a.x [m]\n" + "".join(f"{0.1 * k},{math.sin(k)}\n" for k in range(20)))
        script = os.path.join(SOURCE, "scripts", "identify.py")
        for state, says in [("y = b.x", "'b.x' is neither"), ("y a.x", "expected name = expression"),
                            ("y = log(a.x - 5)", "not finite")]:
            r = subprocess.run([sys.executable, script, path, "--state", state], capture_output=True, text=True)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn(says, r.stderr)


if __name__ == "__main__":
    unittest.main()
