"""Type stubs of the Rust extension (python/src)."""

from typing import Optional

import numpy as np
import numpy.typing as npt

Array = npt.NDArray[np.float64]

class InputError(ValueError):
    """Bad input: a scenario, dataset or argument (the command line's exit code 2)."""

class RunError(RuntimeError):
    """A run failed while doing valid work (the command line's exit code 1)."""

def run(
    scenario: str, overrides: list[str] = ..., out: Optional[str] = None, seed: Optional[int] = None
) -> str:
    """Runs the scenario as `whisker run` (no recording); returns the output directory."""

def load_dataset(path: str) -> dict:
    """The dataset's manifest (text), streams, contacts and poses as numpy arrays."""

def sense(
    scenario: str, pose: Array, k: int = 0, seed: Optional[int] = None, overrides: list[str] = ...
) -> dict:
    """One whisk with the array held at `pose` [x, y, z, qx, qy, qz, qw]."""

def array_pose(
    scenario: str, joints: Optional[list[float]] = None, overrides: list[str] = ...
) -> Array:
    """The array's pose at the arm's `joints` (rad, m)."""

def step_many(
    episodes: list[Episode], goals: list[Optional[Array]], stay_if_refused: bool = False
) -> list[bool]:
    """One step of each episode in parallel threads, the GIL released."""

class Episode:
    """A closed-loop run of a scenario with `[explore]`, one whisk per `step`."""

    def __init__(
        self, scenario: str, overrides: list[str] = ..., seed: Optional[int] = None
    ) -> None: ...
    def proposal(self) -> Optional[tuple[Array, str]]:
        """The loop's next goal [x, y, z, qx, qy, qz, qw] and its kind, or None."""
    def step(self, goal: Optional[Array] = None, stay_if_refused: bool = False) -> bool:
        """One whisk to `goal` (None: the proposal); False once ended."""
    def ended(self) -> bool: ...
    def observation(self) -> dict[str, Array]:
        """touched, contacts, array_pose, confidence, pose_cell, experiences."""
    def last_step(self) -> Optional[tuple[str, str, Optional[str]]]:
        """(move status, goal kind, object re-localised into) of the last whisk."""
    def objects(self) -> list[str]: ...
    def truth(self) -> str: ...
    def threshold(self) -> Optional[float]: ...
    def identified(self) -> Optional[tuple[str, int]]: ...
    def seed(self) -> int: ...
    def whisks(self) -> int: ...
    def budget(self) -> int: ...
    def finish(self) -> dict[str, str]:
        """explore_csv, contacts_csv and summary_json, as `whisker run` writes them."""

def time_loop(
    scenario: str, overrides: list[str] = ..., seed: Optional[int] = None
) -> tuple[int, float]:
    """(whisks, seconds): the loop stepped to its end in Rust (the bench's baseline)."""
