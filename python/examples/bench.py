"""What Python costs: the environment's step against the Rust loop's whisk, and the vector
environment's scaling over threads — each measured against a baseline of the same run.

    python python/examples/bench.py [--whisks 1000] [--repeats 3]

Prints (best of --repeats, kinematic quickstart, seed 0):
- the Rust loop stepped to its end (``whisker_slam._native.time_loop``: ``whisker run``'s
  loop without set-up or outputs), ms per whisk — the baseline;
- ``RecognitionEnv.step`` with the default policy over the same whisks, ms per whisk and
  its ratio to the baseline (the Python overhead per whisk);
- ``RecognitionVectorEnv`` with 1 and with N environments (default: the CPU count),
  steps per second and the ratio N-envs / 1-env.
"""

import argparse
import os
import time

import numpy as np

import whisker_slam
from whisker_slam import _native

SCENARIO = "scenarios/quickstart.toml"


def env_ms(whisks: int) -> tuple[float, int]:
    env = whisker_slam.RecognitionEnv(SCENARIO, overrides={"explore.max_iterations": whisks})
    obs, _ = env.reset(seed=0)
    n = 0
    t = time.perf_counter()
    while True:
        obs, _, term, trunc, _ = env.step(obs["proposal"])
        n += 1
        if term or trunc:
            break
    return 1e3 * (time.perf_counter() - t) / n, n


def vector_rate(num_envs: int, steps: int) -> float:
    vec = whisker_slam.RecognitionVectorEnv(num_envs, SCENARIO)
    obs, _ = vec.reset(seed=0)
    t = time.perf_counter()
    for _ in range(steps):
        obs, *_ = vec.step(obs["proposal"])
    return num_envs * steps / (time.perf_counter() - t)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--whisks", type=int, default=1000)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--envs", type=int, default=os.cpu_count() or 2)
    a = p.parse_args()
    overrides = [f"explore.max_iterations={a.whisks}"]
    rust = min(_native.time_loop(SCENARIO, overrides, 0)[1] for _ in range(a.repeats))
    rust_ms = 1e3 * rust / a.whisks
    py = min(env_ms(a.whisks)[0] for _ in range(a.repeats))
    print(f"Rust loop (baseline)      {rust_ms:8.3f} ms/whisk")
    print(f"RecognitionEnv.step       {py:8.3f} ms/whisk   ratio {py / rust_ms:.3f}")
    steps = max(50, a.whisks // 4)
    one = max(vector_rate(1, steps) for _ in range(a.repeats))
    many = max(vector_rate(a.envs, steps) for _ in range(a.repeats))
    print(f"vector env, 1 env         {one:8.1f} steps/s")
    print(f"vector env, {a.envs} envs        {many:8.1f} steps/s   ratio {many / one:.2f}")


if __name__ == "__main__":
    np.set_printoptions(precision=3)
    main()
