"""Shared helpers: the repository's root (scenarios are named from it) and the `whisker`
command line of the same build (target/release/whisker, or $CARGO_TARGET_DIR's, or
$WHISKER_BIN), which the tests compare the package against."""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def scenario(name: str) -> str:
    return str(REPO / "scenarios" / name)


def whisker_bin() -> str:
    if "WHISKER_BIN" in os.environ:
        return os.environ["WHISKER_BIN"]
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    path = target / "release" / "whisker"
    if not path.exists():
        pytest.fail(f"{path} is missing: build it first (cargo build --release)")
    return str(path)


def cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Runs `whisker ARGS` from the repository's root."""
    p = subprocess.run(
        [whisker_bin(), *args], cwd=REPO, capture_output=True, text=True, check=False
    )
    if check and p.returncode != 0:
        raise AssertionError(f"whisker {' '.join(args)} failed ({p.returncode}):\n{p.stderr}")
    return p
