"""parasils.calibrate: module 1's geometry fitted to readings at measured poses."""

import re

import numpy as np
import pytest

import parasils


def perturbed_robot(tmp_path):
    """The paper's robot with module 1's links 0.3 to 1.5 mm off, its
    nodes moved and an encoder offset on every guide, via its robot file."""
    text = parasils.Robot().to_toml().replace("assumed = true", "assumed = false")
    links = iter([350.3, 349.2, 351.5, 350.8, 349.6, 350.4])
    offsets = iter([0.7, -1.2, 0.4, 1.9, -0.3, 0.0])
    text = re.sub(
        r"link_length_mm = 350\.0",
        lambda _: f"link_length_mm = {next(links)}\nencoder_offset_mm = {next(offsets)}",
        text,
    )
    text = text.replace("node_mm = [0.0, -150.0, 100.0]", "node_mm = [0.8, -150.6, 99.5]")
    path = tmp_path / "real.toml"
    path.write_text(text)
    return parasils.Robot.from_toml(path)


def random_poses(robot, n, seed):
    """Poses about (0, 0, -540 mm, 0, 0, -60 deg) that the robot reaches."""
    rng = np.random.default_rng(seed)
    centre = np.array([0.0, 0.0, -540.0, 0.0, 0.0, np.radians(-60.0)])
    half = np.array([80.0, 80.0, 60.0, *np.radians([20.0, 20.0, 25.0])])
    poses = centre + rng.uniform(-1, 1, size=(4 * n, 6)) * half
    _, ok = robot.module1_ik(poses, errors="nan")
    return poses[ok][:n]


def test_a_perturbed_robot_is_recovered_from_its_readings(tmp_path):
    nominal = parasils.Robot()
    real = perturbed_robot(tmp_path)
    poses = random_poses(nominal, 60, 1)
    q = real.module1_ik(poses)
    fitted, report = parasils.calibrate(nominal, q, poses)
    assert report["poses"] == 60 and report["equations"] == 360
    assert report["rms_before_mm"] > 0.3
    assert report["rms_after_mm"] < 1e-9
    fixed = [p["name"] for p in report["fixed"]]
    assert fixed == [f"guides[{j}].point_mm.z" for j in range(6)]
    names = {p["name"]: p for p in report["identified"]}
    # The link lengths are identified exactly; an encoder offset is seen
    # together with its guide point along the (vertical) guide, which stays
    # at its nominal height: the offset comes out as set.
    assert abs(names["guides[2].link_length_mm"]["fitted"] - 351.5) < 1e-8
    assert abs(names["guides[3].encoder_offset_mm"]["fitted"] - 1.9) < 1e-8
    assert abs(names["legs[1].node_mm.y"]["fitted"] + 150.6) < 1e-8
    assert report["observability"]["condition_number"] > 1
    assert not fitted.module1_assumed
    assert "[module1.calibration]" in fitted.to_toml()
    # Held-out poses: the fitted robot predicts the real readings.
    held_out = random_poses(nominal, 20, 2)
    np.testing.assert_allclose(fitted.module1_ik(held_out), real.module1_ik(held_out), atol=1e-8)


def test_pandas_frames_and_noise_weights_are_accepted(tmp_path):
    pd = pytest.importorskip("pandas")
    nominal = parasils.Robot()
    real = perturbed_robot(tmp_path)
    poses = random_poses(nominal, 60, 3)
    rng = np.random.default_rng(4)
    q = real.module1_ik(poses) + rng.normal(0, 0.01, size=(60, 6))
    pose_sigma = np.array([0.02, 0.02, 0.02, *np.radians([0.01, 0.01, 0.01])])
    noisy = poses + rng.normal(0, 1, size=(60, 6)) * pose_sigma
    frame = pd.DataFrame(q, columns=[f"q{j}_mm" for j in range(1, 7)])
    fitted, report = parasils.calibrate(nominal, frame, noisy, sigma=[0.01, 0.02, np.radians(0.01)])
    assert "covariance" in report["weighting"]
    assert 0.3 < report["variance_factor"] < 3.0
    for p in report["identified"]:
        assert p["std_dev"] > 0
    held_out = random_poses(nominal, 20, 5)
    err = fitted.module1_ik(held_out) - real.module1_ik(held_out)
    assert np.sqrt(np.mean(err**2)) < 0.04


def test_bad_input_names_the_row_or_the_problem():
    nominal = parasils.Robot()
    poses = random_poses(nominal, 12, 6)
    q = nominal.module1_ik(poses)
    bad = q.copy()
    bad[2, 4] = np.nan
    with pytest.raises(ValueError, match=r"row 3, `q5_mm` = NaN"):
        parasils.calibrate(nominal, bad, poses)
    with pytest.raises(ValueError, match="at least 8 poses"):
        parasils.calibrate(nominal, q[:5], poses[:5])
    with pytest.raises(ValueError, match=r"shape \(N, 6\)"):
        parasils.calibrate(nominal, q[:, :5], poses)
    with pytest.raises(ValueError, match="one reading row per pose"):
        parasils.calibrate(nominal, q[:10], poses)
