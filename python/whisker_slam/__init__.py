"""whisker-slam from Python: runs, datasets, one whisk, and the Chapter 6 closed loop as a
Gymnasium environment.

    import whisker_slam
    summary, out = whisker_slam.run("scenarios/quickstart.toml", out="out/q")
    data = whisker_slam.load_dataset("out/dataset")
    whisk = whisker_slam.sense("scenarios/quickstart.toml", pose)
    env = gymnasium.make("whisker_slam/Recognition-v0", scenario="scenarios/quickstart.toml")

Errors raise ``InputError`` (a ``ValueError``: a bad scenario, dataset or argument, with the
message the command line prints after ``error:``) or ``RunError`` (a ``RuntimeError``).
Documented in python/README.md.
"""

from __future__ import annotations

import json
import os
from typing import Any, Mapping

import numpy as np

from . import _native
from ._native import Episode, InputError, RunError, array_pose, step_many
from .env import RecognitionEnv, RecognitionVectorEnv

__all__ = [
    "Episode",
    "InputError",
    "RunError",
    "RecognitionEnv",
    "RecognitionVectorEnv",
    "array_pose",
    "load_dataset",
    "overrides_list",
    "run",
    "sense",
    "step_many",
]


def overrides_list(overrides: Mapping[str, Any] | None) -> list[str]:
    """``{"explore.strategy": "feh"}`` as ``whisker run --set`` arguments: each value
    written as TOML (strings quoted, numbers, booleans, lists of them)."""
    out = []
    for path, value in (overrides or {}).items():
        if value is None:
            raise InputError(f"overrides: {path}: None has no TOML value")
        out.append(f"{path}={json.dumps(value)}")
    return out


def run(
    scenario: str | os.PathLike,
    overrides: Mapping[str, Any] | None = None,
    out: str | os.PathLike | None = None,
    seed: int | None = None,
) -> tuple[dict, str]:
    """Runs a scenario as ``whisker run`` does (no Rerun recording) and returns its
    ``summary.json`` as a dict and its output directory (default: the scenario's
    ``output.dir``)."""
    dir = _native.run(
        os.fspath(scenario),
        overrides_list(overrides),
        None if out is None else os.fspath(out),
        seed,
    )
    path = os.path.join(dir, "summary.json")
    summary = {}
    if os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            summary = json.load(f)
    return summary, dir


def load_dataset(path: str | os.PathLike) -> dict:
    """A dataset (docs/dataset.md) as numpy arrays, read and checked by the Rust readers of
    ``whisker slam``: ``manifest`` (dict), ``streams`` ({folder: (whisks, samples, whiskers, 3)
    array: whisk angle in rad, x and y deflection in Hall counts}), ``contacts`` ({file:
    {column: array}}), ``poses`` ({file: {"time_s", "pose" (n, 7), "whisk"}})."""
    d = _native.load_dataset(os.fspath(path))
    d["manifest"] = json.loads(d["manifest"])
    return d


def sense(
    scenario: str | os.PathLike,
    pose: Any,
    k: int = 0,
    seed: int | None = None,
    overrides: Mapping[str, Any] | None = None,
) -> dict:
    """One whisk with the array held at ``pose`` ([x, y, z, qx, qy, qz, qw], world), sensed
    as the scenario says (kinematic or physics): ``contacts`` ({column: array}),
    ``streams`` ((18, samples, 3) for physics, else None), ``period_s``."""
    return _native.sense(
        os.fspath(scenario),
        np.ascontiguousarray(pose, dtype=np.float64),
        k,
        seed,
        overrides_list(overrides),
    )


def _register() -> None:
    import gymnasium

    if "whisker_slam/Recognition-v0" not in gymnasium.envs.registry:
        gymnasium.register(
            id="whisker_slam/Recognition-v0",
            entry_point="whisker_slam.env:RecognitionEnv",
        )


_register()
