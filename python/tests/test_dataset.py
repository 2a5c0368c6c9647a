"""Datasets read into numpy: the arrays equal the files' values as Python's own csv module
reads them (an independent reader), for a physics closed loop's streams dataset written by
`whisker dataset`; a damaged file is refused with the command line's message."""

import csv
import json

import numpy as np
import pytest

import whisker_slam
from conftest import cli, scenario

FAST = [
    "--set", "explore.max_iterations=4",
    "--set", "array.bending=sweep-plane",
    "--set", "array.segments=8",
    "--set", "array.substeps=2",
]


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    d = tmp_path_factory.mktemp("ds") / "physics"
    cli("dataset", scenario("recognise_box_physics.toml"), "--seed", "1", "--out", str(d), *FAST)
    return d


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_streams_equal_the_whisk_files(dataset):
    data = whisker_slam.load_dataset(dataset)
    m = json.loads((dataset / "dataset.json").read_text())
    assert data["manifest"] == m
    streams = data["streams"]["log/whisks"]
    labels = m["array"]["labels"]
    resolution = m["sensor"]["angle_resolution_rad"]
    assert streams.shape == (4, m["sensor"]["samples_per_whisk"], len(labels), 3)
    for k in range(4):
        table = rows(dataset / "log" / "whisks" / f"whisk_{k:06d}.csv")
        assert len(table) == streams.shape[1]
        header = list(table[0].keys())
        for w in range(len(labels)):
            angle, x, y = header[4 * w], header[4 * w + 1], header[4 * w + 2]
            np.testing.assert_array_equal(
                streams[k, :, w, 0], [int(r[angle]) * resolution for r in table]
            )
            np.testing.assert_array_equal(streams[k, :, w, 1], [float(r[x]) for r in table])
            np.testing.assert_array_equal(streams[k, :, w, 2], [float(r[y]) for r in table])


def test_contacts_and_poses_equal_their_files(dataset):
    data = whisker_slam.load_dataset(dataset)
    for name, c in data["contacts"].items():
        table = rows(dataset / name)
        assert len(c["whisk"]) == len(table)
        np.testing.assert_array_equal(c["whisker"], [int(r["whisker"]) for r in table])
        np.testing.assert_array_equal(c["time_s"], [float(r["time_s"]) for r in table])
        np.testing.assert_array_equal(
            c["point_m"], [[float(r[k]) for k in ("x_m", "y_m", "z_m")] for r in table]
        )
        assert c["label"] == [r["label"] for r in table]
    assert "log/poses.csv" in data["poses"]
    for name, p in data["poses"].items():
        table = rows(dataset / name)
        np.testing.assert_array_equal(p["time_s"], [float(r["time_s"]) for r in table])
        cols = ("x_m", "y_m", "z_m", "qx", "qy", "qz", "qw")
        np.testing.assert_array_equal(p["pose"], [[float(r[k]) for k in cols] for r in table])


def test_a_truncated_whisk_file_is_refused_as_the_cli_refuses_it(dataset, tmp_path):
    import shutil

    bad = tmp_path / "bad"
    shutil.copytree(dataset, bad)
    f = bad / "log" / "whisks" / "whisk_000002.csv"
    lines = f.read_text().splitlines(keepends=True)
    f.write_text("".join(lines[:-10]))
    with pytest.raises(whisker_slam.InputError) as e:
        whisker_slam.load_dataset(bad)
    p = cli("slam", str(bad), check=False)
    assert p.returncode == 2
    assert f"error: {e.value}" in p.stderr
