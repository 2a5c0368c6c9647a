"""Bad input raises the package's exceptions with the command line's own messages (the
CLI prints `error: MESSAGE` and exits 2); the interpreter never crashes."""

import numpy as np
import pytest

import whisker_slam
from conftest import REPO, cli, scenario


def cli_error(*args):
    p = cli(*args, check=False)
    assert p.returncode == 2, p.stderr
    return p.stderr


def test_a_missing_scenario(tmp_path):
    missing = str(tmp_path / "nope.toml")
    with pytest.raises(whisker_slam.InputError) as e:
        whisker_slam.run(missing, out=tmp_path / "o")
    assert f"error: {e.value}" in cli_error("run", missing, "--out", str(tmp_path / "o"))
    with pytest.raises(ValueError):  # InputError is a ValueError
        whisker_slam.Episode(missing)


def test_a_bad_field_names_the_file_and_field(tmp_path):
    bad = tmp_path / "bad.toml"
    text = (REPO / "scenarios" / "quickstart.toml").read_text()
    bad.write_text(
        text.replace('strategy = "default"', 'strategy = "sideways"').replace(
            '"../assets', f'"{REPO}/assets'
        )
    )
    with pytest.raises(whisker_slam.InputError) as e:
        whisker_slam.RecognitionEnv(str(bad))
    assert str(bad) in str(e.value) and "line 37" in str(e.value)
    assert "unknown variant `sideways`, expected one of `default`, `feh`, `lsr`" in str(e.value)
    assert f"error: {e.value}" in cli_error("run", str(bad), "--out", str(tmp_path / "o"))


def test_a_bad_override_is_the_clis_message(tmp_path):
    q = scenario("quickstart.toml")
    with pytest.raises(whisker_slam.InputError) as e:
        whisker_slam.run(q, overrides={"explore.max_iterations": "many"}, out=tmp_path / "o")
    stderr = cli_error(
        "run", q, "--set", 'explore.max_iterations="many"', "--out", str(tmp_path / "o")
    )
    assert f"error: {e.value}" in stderr


def test_bad_arguments_of_the_loop():
    q = scenario("quickstart.toml")
    with pytest.raises(whisker_slam.InputError, match="no \\[explore\\] section"):
        whisker_slam.Episode(scenario("maze.toml"))
    e = whisker_slam.Episode(q, ["explore.max_iterations=3"])
    with pytest.raises(whisker_slam.InputError, match="expected 7 finite numbers"):
        e.step(np.zeros(6))
    with pytest.raises(whisker_slam.InputError, match="no direction"):
        e.step(np.array([0.5, 0.0, 0.3, 0.0, 0.0, 0.0, 0.0]))
    with pytest.raises(whisker_slam.InputError, match="sensing"):
        whisker_slam.RecognitionEnv(q, sensing="telepathy")
    e.finish()
    with pytest.raises(whisker_slam.RunError, match="finished"):
        e.step()
    with pytest.raises(TypeError):
        whisker_slam.Episode(q, seed="zero")
