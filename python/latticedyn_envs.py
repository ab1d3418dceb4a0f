"""Learning environments on latticedyn's Python module, following the Gymnasium API conventions
(reset(seed) -> observation, info; step(action) -> observation, reward, terminated, truncated,
info; observation_space and action_space as boxes) without depending on the gymnasium package.

CraneSwayEnv: the reduced crane of Appendix D has just slewed 45 degrees open-loop and its load
swings; the agent damps the sway with the slewing drive's acceleration (docs/learning.md).
"""
import math
import os

import numpy as np

import latticedyn
import latticedyn_antisway


class Box:
    """A box of real vectors, as gymnasium.spaces.Box: shape, low, high, dtype, sample(), contains()."""

    def __init__(self, low, high, dtype=np.float64):
        self.low = np.asarray(low, dtype=dtype)
        self.high = np.asarray(high, dtype=dtype)
        self.shape = self.low.shape
        self.dtype = np.dtype(dtype)
        self._rng = np.random.default_rng()

    def seed(self, seed=None):
        self._rng = np.random.default_rng(seed)

    def sample(self):
        low = np.where(np.isfinite(self.low), self.low, -1.0)
        high = np.where(np.isfinite(self.high), self.high, 1.0)
        return self._rng.uniform(low, high).astype(self.dtype)

    def contains(self, x):
        x = np.asarray(x)
        return x.shape == self.shape and bool(np.all(x >= self.low) and np.all(x <= self.high))

    def __repr__(self):
        return f"Box({self.low.tolist()}, {self.high.tolist()})"


# Where the build put this file from: its source tree (CMake fills it in).
SOURCE_DIR = "@PROJECT_SOURCE_DIR@"


def default_model():
    """LATTICEDYN_CRANE_MODEL, else examples/api/crane_external.yaml of the source tree this module
    was built from, else of the installed examples (<prefix>/share/latticedyn/examples)."""
    here = os.path.dirname(os.path.abspath(__file__))
    for candidate in (os.environ.get("LATTICEDYN_CRANE_MODEL"),
                      os.path.join(SOURCE_DIR, "examples", "api", "crane_external.yaml"),
                      os.path.join(here, "..", "..", "..", "share", "latticedyn", "examples", "api",
                                   "crane_external.yaml")):
        if candidate and os.path.exists(candidate):
            return candidate
    raise FileNotFoundError("CraneSwayEnv: give model= or set LATTICEDYN_CRANE_MODEL to examples/api/crane_external.yaml")


class CraneSwayEnv:
    """Damp the load's sway after a fast slew.

    Start: the crane at rest, slewed by 45 degrees in `slew_times` seconds (one of them, drawn at
    reset) with a bang-bang acceleration; the load then swings about 2 m. Every `control_period`
    seconds the agent sets the slewing acceleration (rad/s^2, within +-max_acceleration); an
    episode lasts `duration` seconds.

    Observation (6, in the slewed frame, relative to the load's quasi-static position there):
    tangential and radial sway (m), their rates (m/s), the slewing angle's error from 45 degrees
    (rad x 10) and the slewing rate (rad/s x 10).

    Reward per step: -(s_t^2 + 0.5 v_t^2 + 10 e^2), with the tangential sway s_t (m), its rate v_t
    (m/s) and the slewing angle's error e (rad): the sway the slewing drive can act on and the
    angle it must keep. The radial sway (which slewing cannot reach to
    first order) is in `info`. A failed solve ends the episode (terminated, info["error"]).
    """

    metadata = {"render_modes": []}
    target = math.pi / 4

    def __init__(self, model=None, slew_times=(12.0, 15.0, 18.0), control_period=0.5, duration=40.0,
                 max_acceleration=0.02):
        self.control_period = control_period
        self.max_steps = int(round(duration / control_period))
        self.max_acceleration = max_acceleration
        self.observation_space = Box(np.full(6, -np.inf), np.full(6, np.inf))
        self.action_space = Box([-max_acceleration], [max_acceleration])
        self.np_random = np.random.default_rng()
        self.sim = latticedyn.Simulator(model or default_model())
        self.sim.solve_statics()
        self.rest = self.sim.joint_position("load.1")
        rest_state = self.sim.save_state()
        # The start states: the open-loop slew of each duration, computed once.
        self.starts = []
        for seconds in slew_times:
            self.sim.restore_state(rest_state)
            a = self.target / (seconds / 2) ** 2
            self.sim.set_drive_acceleration("slewing", a)
            self.sim.advance(seconds / 2)
            self.sim.set_drive_acceleration("slewing", -a)
            self.sim.advance(seconds / 2)
            self.sim.set_drive_rate("slewing", 0.0)
            self.starts.append(self.sim.save_state())
        self.steps = 0

    def _sway(self):
        angle, rate, _ = self.sim.drive("slewing")
        return (*latticedyn_antisway.slewed_sway(self.sim, self.rest), angle - self.target, rate)

    def _observation(self):
        st, sr, vt, vr, error, rate = self._sway()
        return np.array([st, sr, vt, vr, 10.0 * error, 10.0 * rate])

    def reset(self, seed=None, options=None):
        if seed is not None:
            self.np_random = np.random.default_rng(seed)
            self.action_space.seed(seed)
        start = int(self.np_random.integers(len(self.starts)))
        if options and "start" in options:
            start = int(options["start"])
        self.sim.restore_state(self.starts[start])
        self.sim.set_drive_rate("slewing", 0.0)
        self.steps = 0
        return self._observation(), {"start": start, "time": self.sim.time}

    def step(self, action):
        a = float(np.clip(np.asarray(action, dtype=float).reshape(-1)[0], -self.max_acceleration, self.max_acceleration))
        self.sim.set_drive_acceleration("slewing", a)
        info = {}
        terminated = False
        try:
            self.sim.advance(self.control_period)
        except latticedyn.SolverError as e:
            terminated = True
            info["error"] = str(e)
        self.steps += 1
        obs = self._observation()
        st, sr, vt, vr, error, rate = self._sway()
        reward = -(st**2 + 0.5 * vt**2 + 10.0 * error**2) - (100.0 if terminated else 0.0)
        info.update({"radial_sway": sr, "tangential_sway": st, "angle_error": error, "time": self.sim.time})
        truncated = self.steps >= self.max_steps and not terminated
        return obs, reward, terminated, truncated, info

    def render(self):
        return None

    def close(self):
        pass
