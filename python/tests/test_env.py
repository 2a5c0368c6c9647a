"""The Gymnasium environment: Gymnasium's own checker, and the loop's faithfulness — an
agent that returns the loop's own proposal reproduces the command line's run byte for byte
(explore.csv, contacts.csv, summary.json), which fails if a goal, a seed, a sub-stream or a
step is lost on the way through Python."""

import pathlib

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import whisker_slam
from conftest import cli, scenario

QUICK = scenario("quickstart.toml")
SHORT = {"explore.max_iterations": 150}


def test_check_env_passes():
    env = whisker_slam.RecognitionEnv(QUICK, overrides={"explore.max_iterations": 30})
    check_env(env, skip_render_check=True)


def test_registered_and_spaces_hold_observations():
    env = gymnasium.make("whisker_slam/Recognition-v0", scenario=QUICK, overrides=SHORT)
    obs, info = env.reset(seed=2)
    assert info == {"seed": 2, "truth": "box"}
    assert env.observation_space.contains(obs)
    assert env.unwrapped.objects == ["box", "box_stack"]
    # Before the first whisk nothing was touched and no confidence exists.
    assert obs["touched"].sum() == 0 and np.all(obs["confidence"] == 0)


def default_run(tmp_path: pathlib.Path, seed: int, overrides: dict, name: str) -> dict:
    """The environment stepped with the loop's own proposals to its end."""
    env = whisker_slam.RecognitionEnv(QUICK if name is None else name, overrides=overrides)
    obs, _ = env.reset(seed=seed)
    steps, touched = 0, 0
    while True:
        obs, reward, terminated, truncated, info = env.step(obs["proposal"])
        steps += 1
        touched += int(obs["touched"].sum())
        if terminated or truncated:
            break
    assert steps == info["whisks"]
    out = env.finish()
    out["touched"] = touched
    return out


@pytest.mark.parametrize(
    "name,seed,overrides",
    [
        ("quickstart.toml", 0, SHORT),
        ("recognise_box_feh.toml", 4, SHORT),
        ("recognise_box_stack.toml", 7, SHORT),
    ],
)
def test_default_policy_reproduces_whisker_run_byte_for_byte(tmp_path, name, seed, overrides):
    out = tmp_path / "cli"
    sets = [a for k, v in overrides.items() for a in ("--set", f"{k}={v}")]
    cli("run", scenario(name), "--seed", str(seed), "--out", str(out), "--no-rrd", *sets)
    got = default_run(tmp_path, seed, overrides, scenario(name))
    assert got["explore_csv"] == (out / "explore.csv").read_text()
    assert got["contacts_csv"] == (out / "contacts.csv").read_text()
    assert got["summary_json"] == (out / "summary.json").read_text()
    # The observations carried the contacts the run logged (one row per contact).
    assert got["touched"] == len((out / "contacts.csv").read_text().splitlines()) - 1


def test_a_different_goal_changes_the_run_and_stay_whisks_in_place():
    env = whisker_slam.RecognitionEnv(QUICK, overrides=SHORT, stay_if_refused=True)
    obs, _ = env.reset(seed=0)
    start = obs["array_pose"].copy()
    # A goal far out of the UR5's reach: refused, so the array whisks where it was.
    far = np.array([0.99, 0.99, 1.4, 0.0, 0.0, 0.0, 1.0])
    obs, _, _, _, info = env.step(far)
    assert info["status"] == "unreachable"
    np.testing.assert_array_equal(obs["array_pose"], start)
    # The loop's proposal is reachable and moves the array there.
    obs, _, _, _, info = env.step(obs["proposal"])
    assert info["status"] == "reached"
    assert not np.array_equal(obs["array_pose"], start)


def test_reward_sums_to_the_true_objects_ic_over_the_threshold():
    cost = 0.01
    env = whisker_slam.RecognitionEnv(QUICK, overrides=SHORT, whisk_cost=cost)
    obs, _ = env.reset(seed=0)
    total, steps = 0.0, 0
    while True:
        obs, r, term, trunc, _ = env.step(obs["proposal"])
        total += r
        steps += 1
        if term or trunc:
            break
    ic_box = obs["confidence"][0, 1]
    assert total == pytest.approx(ic_box / env.episode.threshold() - cost * steps)


def test_vector_env_steps_every_copy_as_alone():
    vec = whisker_slam.RecognitionVectorEnv(2, QUICK, overrides={"explore.max_iterations": 20})
    obs, _ = vec.reset(seed=10)
    assert vec.observation_space.contains(obs)
    single = [whisker_slam.RecognitionEnv(QUICK, overrides={"explore.max_iterations": 20}) for _ in range(2)]
    alone = [e.reset(seed=10 + i)[0] for i, e in enumerate(single)]
    for _ in range(5):
        obs, rewards, term, trunc, _ = vec.step(obs["proposal"])
        alone = [e.step(a["proposal"])[0] for e, a in zip(single, alone)]
        for i in range(2):
            for k in obs:
                np.testing.assert_array_equal(obs[k][i], alone[i][k])


def test_reset_without_a_seed_takes_the_scenarios_then_the_next():
    env = whisker_slam.RecognitionEnv(QUICK, overrides={"seed": 7, "explore.max_iterations": 5})
    assert env.reset()[1]["seed"] == 7
    assert env.reset()[1]["seed"] == 8
    assert env.reset(seed=3)[1]["seed"] == 3
    assert env.reset()[1]["seed"] == 4
    # The same as whisker run --seed 7: the first proposal is the same goal.
    a = whisker_slam.Episode(QUICK, ["explore.max_iterations=5"], 7).proposal()
    b = whisker_slam.RecognitionEnv(QUICK, overrides={"seed": 7}).reset()[0]["proposal"]
    np.testing.assert_array_equal(a[0], b)


def test_physics_sensing_reproduces_whisker_run_too(tmp_path):
    fast = {
        "explore.max_iterations": 4,
        "array.bending": "sweep-plane",
        "array.segments": 8,
        "array.substeps": 2,
    }
    name = scenario("recognise_box_physics.toml")
    out = tmp_path / "cli"
    sets = [a for k, v in fast.items() for a in ("--set", f"{k}={v}")]
    cli("run", name, "--seed", "3", "--out", str(out), "--no-rrd", *sets)
    env = whisker_slam.RecognitionEnv(name, overrides=fast)
    obs, _ = env.reset(seed=3)
    while True:
        obs, _, term, trunc, _ = env.step(obs["proposal"])
        assert env.observation_space.contains(obs)
        if term or trunc:
            break
    got = env.finish()
    assert got["explore_csv"] == (out / "explore.csv").read_text()
    assert got["contacts_csv"] == (out / "contacts.csv").read_text()
