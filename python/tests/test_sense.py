"""One whisk from Python: at the pose of the closed loop's whisk k, `sense` gives the
contacts the loop logged for that whisk (contacts.csv, written by the command line; the
kinematic contact noise off, as its per-whisker streams are drawn in sequence over a run); a physics whisk's angle stream follows the scenario's whisking pattern
(40° to 140°, §2.2) and the array's pose follows the arm's forward kinematics."""

import csv
import math

import numpy as np

import whisker_slam
from conftest import cli, scenario

Q = scenario("quickstart.toml")


def test_kinematic_whisk_equals_the_loops_logged_whisk(tmp_path):
    out = tmp_path / "run"
    noise = "kinematic.noise=false"
    cli("run", Q, "--out", str(out), "--no-rrd", "--set", "explore.max_iterations=40", "--set", noise)
    explore = list(csv.DictReader(open(out / "explore.csv")))
    contacts = list(csv.DictReader(open(out / "contacts.csv")))
    checked = 0
    for row in explore:
        k = int(row["iteration"])
        logged = [c for c in contacts if int(c["cycle"]) == k]
        if not logged:
            continue
        pose = np.array([float(row[c]) for c in ("x_m", "y_m", "z_m", "qx", "qy", "qz", "qw")])
        got = whisker_slam.sense(Q, pose, k=k, overrides={"kinematic.noise": False})
        assert got["streams"] is None
        c = got["contacts"]
        assert list(c["whisker"]) == [int(r["whisker"]) for r in logged]
        # contacts.csv writes shortest round-trip decimals: equal to the bit.
        np.testing.assert_array_equal(
            c["radial_distance_m"], [float(r["radial_distance_m"]) for r in logged]
        )
        np.testing.assert_array_equal(
            c["point_m"], [[float(r[a]) for a in ("x_m", "y_m", "z_m")] for r in logged]
        )
        checked += 1
    assert checked >= 10


def test_physics_whisk_streams_follow_the_whisking_pattern():
    far = np.array([0.0, -0.6, 0.5, 0.0, 0.0, 0.0, 1.0])  # nothing within reach
    got = whisker_slam.sense(
        scenario("recognise_box_physics.toml"),
        far,
        overrides={"array.bending": "sweep-plane", "array.segments": 8, "array.substeps": 2},
    )
    s = got["streams"]
    assert s.shape[0] == 18 and s.shape[2] == 3
    assert s.shape[1] == round(got["period_s"] * 2000)
    angle = np.degrees(s[:, :, 0])
    assert abs(angle.min() - 40) < 1.0 and abs(angle.max() - 140) < 1.0
    assert len(got["contacts"]["whisker"]) == 0


def test_array_pose_is_the_arms_forward_kinematics():
    start = whisker_slam.array_pose(Q)
    # The quickstart's comment: the array level at (0.33, 0.11, 0.23) m, along +x.
    np.testing.assert_allclose(start[:3], [0.3251, 0.1092, 0.2296], atol=1e-4)
    assert math.isclose(np.linalg.norm(start[3:]), 1.0, rel_tol=1e-12)
    # Turning the base joint by 90° turns the array's position about z by 90°.
    q = np.radians([90.0, -115.0, 137.5, -22.5, 90.0, 0.0])
    turned = whisker_slam.array_pose(Q, list(q))
    np.testing.assert_allclose(turned[:2], [-start[1], start[0]], atol=1e-12)
    assert math.isclose(turned[2], start[2], abs_tol=1e-12)
