"""The closed loop of Chapter 6 as a Gymnasium environment (issue #65).

One step is one whisk of the loop of ``whisker run`` with an ``[explore]`` section: the arm
moves to the goal, the array whisks, WhiskerRatSLAM and recognition update, the SPC
decides. The environment is the same loop as ``whisker run``: an agent that returns the
loop's own proposal (``obs["proposal"]``) makes the run ``whisker run`` makes, byte for
byte (python/tests/test_env.py).

Action: ``Box(7,)`` float64, the next whisk's goal, the array's pose in the world:
``[x, y, z, qx, qy, qz, qw]`` (m; a quaternion, scalar last; normalised when not of unit
length), x and y in [-1, 1] m, z in [-0.5, 1.5] m (the UR5's reach round its base). It
replaces the pose of the loop's own proposal; the goal keeps the proposal's kind (a face of
the goal sphere, an SPC correction, a step to an experience) for the log and the strategy's
bookkeeping. A goal the arm cannot reach or that would put the arm into the object is
counted (``summary.json``'s fallbacks) and followed by the strategy's next goals, as in
``whisker run`` — or, with ``stay_if_refused=True``, by a whisk where the array is. When
the loop has no proposal (its strategy has no goal) the action is not used.

Observation (a ``Dict``): ``touched`` (18,) int8 — which whiskers touched in the last whisk;
``contacts`` (18, 5) — per whisker x, y, z of the contact in the array frame (m), whisk
angle at contact (rad) and radial distance (m), zeros where it did not touch;
``array_pose`` (7,) — where the array is (the robot knows its arm); ``confidence``
(objects, 2) — each loaded object's raw confidence RC and integrated confidence IC
(§6.1.2.4), objects in ``env.unwrapped.objects`` order; ``pose_cell`` (6,) — the most
active 6-D pose cell; ``experiences`` (1,) — experiences in the map; ``proposal`` (7,) —
the loop's own next goal (zeros when it has none).

Reward: the change of the true object's IC over the threshold (so a run that recognises
correctly collects about 1), minus ``whisk_cost`` per whisk (default 0.001).
Terminated: the loop stopped (every IC at ``stop_ic``, or recognised with
``stop_on_identity``). Truncated: the budget (``explore.max_iterations``) spent first.
Seeds: ``reset(seed=s)`` runs the scenario with seed ``s`` (every random draw from its
named sub-streams, as ``whisker run --seed s``); ``reset()`` without a seed takes the
scenario's seed first, then the previous seed + 1.
"""

from __future__ import annotations

import os
from typing import Any, Mapping

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.vector import VectorEnv
from gymnasium.vector.utils import batch_space

from . import _native

WHISKERS = 18
LOW = np.array([-1.0, -1.0, -0.5, -1.0, -1.0, -1.0, -1.0])
HIGH = np.array([1.0, 1.0, 1.5, 1.0, 1.0, 1.0, 1.0])


def _overrides(overrides: Mapping[str, Any] | None, sensing: str | None) -> list[str]:
    from . import overrides_list

    o = dict(overrides or {})
    if sensing is not None:
        if sensing not in ("kinematic", "physics"):
            raise _native.InputError(
                f'sensing: expected "kinematic" or "physics", got {sensing!r}'
            )
        o["sensing"] = sensing
    return overrides_list(o)


class _Loop:
    """One episode of the loop and what the environment keeps of it."""

    def __init__(self, scenario: str, overrides: list[str], seed: int | None):
        self.episode = _native.Episode(scenario, overrides, seed)
        self.objects = self.episode.objects()
        self.truth = self.episode.truth()
        self.threshold = self.episode.threshold() or 1.0
        self.seed = seed
        self.ic = self._truth_ic(self.episode.observation())

    def _truth_ic(self, obs: dict) -> float:
        if self.truth in self.objects:
            return float(obs["confidence"][self.objects.index(self.truth), 1])
        return 0.0

    def observe(self) -> dict:
        obs = self.episode.observation()
        p = self.episode.proposal()
        obs["proposal"] = p[0] if p is not None else np.zeros(7)
        return obs

    def goal(self, action: Any) -> np.ndarray | None:
        """The action as a goal, or None when the loop has no proposal to replace."""
        if self.episode.proposal() is None:
            return None
        return np.ascontiguousarray(action, dtype=np.float64).reshape(7)

    def outcome(self, whisk_cost: float) -> tuple[dict, float, bool, bool, dict]:
        e = self.episode
        obs = self.observe()
        ic = self._truth_ic(obs)
        reward = (ic - self.ic) / self.threshold - whisk_cost
        self.ic = ic
        ended = e.ended()
        identified = e.identified()
        truncated = ended and e.whisks() >= e.budget() and identified is None
        last = e.last_step()
        info = {
            "whisks": e.whisks(),
            "identified": identified,
            "status": last[0] if last else None,
            "goal_kind": last[1] if last else None,
            "relocalised_into": last[2] if last else None,
        }
        return obs, reward, ended and not truncated, truncated, info


def _observation_space(objects: int) -> spaces.Dict:
    inf = np.inf
    return spaces.Dict(
        {
            "touched": spaces.MultiBinary(WHISKERS),
            "contacts": spaces.Box(-inf, inf, (WHISKERS, 5), np.float64),
            "array_pose": spaces.Box(-inf, inf, (7,), np.float64),
            "confidence": spaces.Box(-inf, inf, (objects, 2), np.float64),
            "pose_cell": spaces.Box(-inf, inf, (6,), np.float64),
            "experiences": spaces.Box(0.0, inf, (1,), np.float64),
            "proposal": spaces.Box(-inf, inf, (7,), np.float64),
        }
    )


class RecognitionEnv(gymnasium.Env):
    """The Chapter 6 loop of ``scenario`` (a scenario with ``[explore]``), one whisk a step
    (module documentation). ``sensing`` ("kinematic" or "physics") overrides the
    scenario's; ``overrides`` are ``whisker run --set`` fields as a dict."""

    metadata = {"render_modes": []}

    def __init__(
        self,
        scenario: str | os.PathLike = "scenarios/quickstart.toml",
        overrides: Mapping[str, Any] | None = None,
        sensing: str | None = None,
        whisk_cost: float = 0.001,
        stay_if_refused: bool = False,
    ):
        self.scenario = os.fspath(scenario)
        self._overrides = _overrides(overrides, sensing)
        self.whisk_cost = whisk_cost
        self.stay_if_refused = stay_if_refused
        self._loop = _Loop(self.scenario, self._overrides, None)
        self.objects = self._loop.objects
        self._next_seed: int | None = None
        self.observation_space = _observation_space(len(self.objects))
        self.action_space = spaces.Box(LOW, HIGH, (7,), np.float64)

    @property
    def episode(self) -> _native.Episode:
        """The native episode (its proposal, identification, ``finish()``…)."""
        return self._loop.episode

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        if seed is None and self._next_seed is not None:
            seed = self._next_seed
        self._loop = _Loop(self.scenario, self._overrides, seed)
        used = self._loop.episode.seed()
        self._next_seed = used + 1
        return self._loop.observe(), {"seed": used, "truth": self._loop.truth}

    def step(self, action):
        goal = self._loop.goal(action)
        self._loop.episode.step(goal, self.stay_if_refused)
        return self._loop.outcome(self.whisk_cost)

    def finish(self) -> dict:
        """Ends the episode: ``explore_csv``, ``contacts_csv`` and ``summary_json``, the
        texts ``whisker run`` writes."""
        return self._loop.episode.finish()


class RecognitionVectorEnv(VectorEnv):
    """``num_envs`` copies of :class:`RecognitionEnv` stepped together in Rust threads with
    the GIL released (``whisker_slam.step_many``). An episode that ends is reset in the same
    step (``autoreset_mode`` SAME_STEP) with its seed + ``num_envs``; its last observation
    is in ``infos["final_obs"]``. ``reset(seed=s)`` seeds environment i with s + i (without a
    seed, s is the scenario's)."""

    metadata = {"render_modes": [], "autoreset_mode": gymnasium.vector.AutoresetMode.SAME_STEP}

    def __init__(
        self,
        num_envs: int,
        scenario: str | os.PathLike = "scenarios/quickstart.toml",
        overrides: Mapping[str, Any] | None = None,
        sensing: str | None = None,
        whisk_cost: float = 0.001,
        stay_if_refused: bool = False,
    ):
        self.num_envs = num_envs
        self.scenario = os.fspath(scenario)
        self._overrides = _overrides(overrides, sensing)
        self.whisk_cost = whisk_cost
        self.stay_if_refused = stay_if_refused
        self._loops = [_Loop(self.scenario, self._overrides, None)]
        objects = len(self._loops[0].objects)
        self.single_observation_space = _observation_space(objects)
        self.single_action_space = spaces.Box(LOW, HIGH, (7,), np.float64)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)

    def _batch(self, observations: list[dict]) -> dict:
        return {k: np.stack([o[k] for o in observations]) for k in observations[0]}

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        # Without a seed: the scenario's (as --set seed=… gives it) for the first copy.
        base = self._loops[0].episode.seed() if seed is None else seed
        self._loops = [
            _Loop(self.scenario, self._overrides, base + i) for i in range(self.num_envs)
        ]
        return self._batch([l.observe() for l in self._loops]), {}

    def step(self, actions):
        actions = np.asarray(actions, dtype=np.float64)
        goals = [l.goal(a) for l, a in zip(self._loops, actions)]
        _native.step_many([l.episode for l in self._loops], goals, self.stay_if_refused)
        obs, rewards, terms, truncs, finals = [], [], [], [], []
        for i, l in enumerate(self._loops):
            o, r, term, trunc, _ = l.outcome(self.whisk_cost)
            if term or trunc:
                finals.append(o)
                self._loops[i] = _Loop(self.scenario, self._overrides, l.seed + self.num_envs)
                o = self._loops[i].observe()
            else:
                finals.append(None)
            obs.append(o)
            rewards.append(r)
            terms.append(term)
            truncs.append(trunc)
        infos = {"final_obs": np.array(finals, dtype=object)}
        return (
            self._batch(obs),
            np.array(rewards),
            np.array(terms),
            np.array(truncs),
            infos,
        )
