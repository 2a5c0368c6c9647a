"""A random and the default policy side by side in the Chapter 6 loop: each object's
integrated confidence (IC) whisk by whisk, plotted with matplotlib.

    python python/examples/policies.py [--seed 0] [--whisks 600] [--out confidence.png]

The default policy returns the loop's own proposal (``obs["proposal"]``), i.e. the
thesis' default trajectory with the surface placement controller; the random one draws
goals from the action space, each a pose anywhere in the UR5's workspace with any
orientation (refused goals make the array whisk where it is: ``stay_if_refused``). Run
from the repository's root (the scenario's paths are relative to it).
"""

import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import whisker_slam  # noqa: E402


def episode(policy: str, seed: int, whisks: int) -> tuple[np.ndarray, list[str], dict]:
    env = whisker_slam.RecognitionEnv(
        "scenarios/quickstart.toml",
        overrides={"explore.max_iterations": whisks},
        # The default policy is the loop of `whisker run` (a refused goal: the strategy's
        # next); a random goal refused leaves the array where it is.
        stay_if_refused=policy == "random",
    )
    env.action_space.seed(seed)
    obs, info = env.reset(seed=seed)
    ics = []
    while True:
        action = obs["proposal"] if policy == "default" else env.action_space.sample()
        obs, reward, terminated, truncated, info = env.step(action)
        ics.append(obs["confidence"][:, 1].copy())
        if terminated or truncated:
            return np.array(ics), env.objects, info


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--whisks", type=int, default=600)
    p.add_argument("--out", default="confidence.png")
    a = p.parse_args()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    for ax, policy in zip(axes, ("default", "random")):
        ics, objects, info = episode(policy, a.seed, a.whisks)
        for k, name in enumerate(objects):
            ax.plot(ics[:, k], label=name)
        ax.axhline(300, color="grey", linestyle=":", label="threshold (300)")
        ax.set_title(f"{policy} policy: identified {info['identified']}")
        ax.set_xlabel("whisk")
        print(f"{policy:8s} {len(ics)} whisks, identified {info['identified']}, "
              f"final IC {dict(zip(objects, ics[-1].round(1)))}")
    axes[0].set_ylabel("integrated confidence IC")
    axes[0].legend()
    fig.suptitle(f"The Box, seed {a.seed}: the loop's default goals against random goals")
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
