"""Learns to damp the crane's load sway after a fast slew (latticedyn_envs.CraneSwayEnv) with a
linear policy in PyTorch trained by the cross-entropy method, and plots the learning curve and the
sway with and without the learned control (docs/learning.md).

    PYTHONPATH=build/python /usr/bin/python3 examples/api/learn_sway.py --out docs/learning
"""
import argparse
import os
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import torch  # noqa: E402

import latticedyn_envs  # noqa: E402


def episode(env, policy, start):
    """Return and tangential sway history of one episode from start state `start`."""
    obs, _ = env.reset(options={"start": start})
    total, sway, times = 0.0, [], []
    while True:
        with torch.no_grad():
            action = policy(torch.as_tensor(obs, dtype=torch.float64)).numpy()
        obs, reward, terminated, truncated, info = env.step(action)
        total += reward
        sway.append(info["tangential_sway"])
        times.append(info["time"])
        if terminated or truncated:
            return total, np.array(times), np.array(sway)


def score(env, policy):
    """Mean return over every start state."""
    return float(np.mean([episode(env, policy, s)[0] for s in range(len(env.starts))]))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="results/learn_sway", help="folder for the PNGs")
    p.add_argument("--iterations", type=int, default=10)
    p.add_argument("--population", type=int, default=10)
    p.add_argument("--elite", type=int, default=3)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    torch.manual_seed(args.seed)

    env = latticedyn_envs.CraneSwayEnv()
    scale = env.max_acceleration
    # a = max_acceleration * tanh(w . observation + b): bounded, smooth in the parameters.
    policy = torch.nn.Sequential(torch.nn.Linear(6, 1, dtype=torch.float64), torch.nn.Tanh())
    with torch.no_grad():
        policy[0].weight.zero_()
        policy[0].bias.zero_()

    def act(obs):
        return scale * policy(obs)

    parameters = torch.nn.utils.parameters_to_vector(policy.parameters()).detach()
    baseline = score(env, lambda obs: torch.zeros(1, dtype=torch.float64))
    mean, std = parameters.clone(), torch.full_like(parameters, 0.5)
    curve, started = [], time.perf_counter()
    steps0 = 0
    for it in range(args.iterations):
        samples = mean + std * torch.randn(args.population, mean.numel(), dtype=torch.float64)
        returns = []
        for candidate in samples:
            torch.nn.utils.vector_to_parameters(candidate, policy.parameters())
            returns.append(score(env, act))
        order = np.argsort(returns)[::-1][: args.elite]
        elite = samples[order.copy()]
        mean, std = elite.mean(dim=0), elite.std(dim=0) + 0.02
        torch.nn.utils.vector_to_parameters(mean, policy.parameters())
        curve.append(score(env, act))
        steps0 += (args.population + 1) * len(env.starts) * env.max_steps
        print(f"iteration {it + 1}: mean policy return {curve[-1]:.1f} (no control {baseline:.1f}), "
              f"best sample {max(returns):.1f}", flush=True)
    wall = time.perf_counter() - started
    print(f"{steps0} environment steps in {wall:.0f} s: {steps0 / wall:.0f} steps/s "
          f"({steps0 * env.control_period / wall:.0f} x real time)")

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(range(1, len(curve) + 1), curve, "o-", label="learned policy (mean of the elite)")
    ax.axhline(baseline, color="grey", ls="--", label="no control")
    ax.set_xlabel("cross-entropy iteration")
    ax.set_ylabel("return (mean over the 3 start states)")
    ax.set_title("Learning to damp the load's sway after a 45° slew")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "learning_curve.png"), dpi=120)

    fig, axes = plt.subplots(len(env.starts), 1, figsize=(7, 2.2 * len(env.starts)), sharex=True)
    for s, ax in enumerate(np.atleast_1d(axes)):
        for label, pol, style in (("no control", lambda obs: torch.zeros(1, dtype=torch.float64), "--"),
                                  ("learned", act, "-")):
            total, t, sway = episode(env, pol, s)
            ax.plot(t, sway, style, label=f"{label} (return {total:.0f})")
        ax.set_ylabel("tangential sway [m]")
        ax.set_title(f"start: slew of {[12, 15, 18][s] if len(env.starts) == 3 else s} s", fontsize=9)
        ax.legend(fontsize=8, loc="upper right")
    np.atleast_1d(axes)[-1].set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "sway.png"), dpi=120)
    print(f"learned return {curve[-1]:.1f} against {baseline:.1f} without control; "
          f"weights {mean.numpy().round(4).tolist()}")
    print(f"wrote {args.out}/learning_curve.png, {args.out}/sway.png")


if __name__ == "__main__":
    main()
