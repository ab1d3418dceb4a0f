"""The learning environment (python/latticedyn_envs.py): Gymnasium's API conventions, seeding,
and rewards that favour damping the sway. Run by ctest (python.envs)."""
import unittest

import numpy as np

import latticedyn_envs


class CraneSwayEnvTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.env = latticedyn_envs.CraneSwayEnv(duration=20.0)

    def test_reset_and_step_follow_the_gymnasium_conventions(self):
        env = self.env
        obs, info = env.reset(seed=3)
        self.assertEqual(obs.shape, env.observation_space.shape)
        self.assertTrue(env.observation_space.contains(obs))
        self.assertIn(info["start"], range(3))
        self.assertEqual(env.action_space.shape, (1,))
        self.assertTrue(env.action_space.contains(env.action_space.sample()))
        steps = 0
        while True:
            obs, reward, terminated, truncated, info = env.step(np.array([0.0]))
            steps += 1
            self.assertIsInstance(reward, float)
            self.assertFalse(terminated)
            if truncated:
                break
        self.assertEqual(steps, 40)  # 20 s of 0.5 s
        start = env.starts[env.reset(seed=3)[1]["start"]]
        self.assertAlmostEqual(info["time"], start.time + 20.0, places=9)

    def test_a_seed_gives_the_same_episode(self):
        env = self.env
        runs = []
        for _ in range(2):
            obs, info = env.reset(seed=7)
            trajectory = [obs]
            for k in range(6):
                obs, *_ = env.step([0.01 * (-1) ** k])
                trajectory.append(obs)
            runs.append(np.array(trajectory))
        np.testing.assert_array_equal(runs[0], runs[1])

    def test_the_load_swings_after_the_slew_and_damping_it_pays(self):
        env = self.env
        obs, info = env.reset(options={"start": 1})  # the 15 s slew
        self.assertGreater(abs(obs[0]), 1.0)  # about 2 m of tangential sway
        self.assertLess(abs(obs[4]), 1e-9)    # at the target angle

        def ret(policy):
            obs, _ = env.reset(options={"start": 1})
            total = 0.0
            while True:
                obs, reward, terminated, truncated, _ = env.step(policy(obs))
                total += reward
                if terminated or truncated:
                    return total

        # Slewing against the sway's rate damps it (a pendulum on a cart): a better return than none.
        self.assertGreater(ret(lambda o: [0.005 * o[2]]), ret(lambda o: [0.0]) + 10.0)
        # Actions beyond the bound are clipped to it.
        env.reset(options={"start": 1})
        env.step([1.0])
        self.assertAlmostEqual(env.sim.drive("slewing")[2], env.max_acceleration)


if __name__ == "__main__":
    unittest.main()
