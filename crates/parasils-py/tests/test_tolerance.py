"""Tolerance studies: parasils.ToleranceStudy and parasils.tolerance, in one
process and on a Dask cluster.

The motion is the paper's reorientation (or the demo procedure) sampled at
10 Hz, so that a robot costs a fraction of a millisecond; the truths are
independent of the library: a robot built exactly replays its own commands
exactly, a port moved by d moves its tip by |d| exactly, whatever the
platform's orientation, and the moments of the distributions the
specification names.
"""

import concurrent.futures
import copy
import pickle

import numpy as np
import pytest

import parasils
from conftest import P0, ROOT

DEMO = ROOT / "procedures" / "sils-demo.toml"
COLUMNS = (
    "sample",
    "left_tip_dev_mm",
    "right_tip_dev_mm",
    "pose_position_err_mm",
    "pose_rotation_err_deg",
    "failed",
)
DEVIATIONS = COLUMNS[1:5]
FAMILIES = {
    "module1": {
        "guides": ["point_mm", "direction_deg", "link_length_mm", "encoder_offset_mm"],
        "legs": ["node_mm"],
    },
    "instruments": ["alpha_deg", "beta_deg", "rcm_mm"],
}
#: Encoder offsets within +-250 mm: many robots whose module 1 cannot be
#: followed from the commanded pose (the forward kinematics fails).
WILD = {"module1": {"guides": {"encoder_offset_mm": {"half_width": 250}}}}


def every_family(entry):
    """A specification giving every family the same entry."""
    return {
        "module1": {
            group: {name: dict(entry) for name in names}
            for group, names in FAMILIES["module1"].items()
        },
        "instruments": {name: dict(entry) for name in FAMILIES["instruments"]},
    }


def assert_same(a, b):
    """Two results equal to the bit, NaN included, failures included."""
    assert set(a) == set(COLUMNS) | {"failures"}
    assert set(b) == set(a)
    for name in COLUMNS:
        x, y = np.asarray(a[name]), np.asarray(b[name])
        assert x.dtype == y.dtype and x.shape == y.shape, name
        if x.dtype == np.float64:
            assert np.array_equal(x.view(np.uint64), y.view(np.uint64)), name
        else:
            assert np.array_equal(x, y), name
    assert a["failures"] == b["failures"]


@pytest.fixture(scope="module")
def study():
    return parasils.ToleranceStudy(None, seed=7, rate_hz=10)


def test_the_columns_and_their_types(study):
    r = study.run(0, 12)
    assert set(r) == set(COLUMNS) | {"failures"}
    assert r["sample"].dtype == np.uint64
    assert np.array_equal(r["sample"], np.arange(12))
    for name in DEVIATIONS:
        assert r[name].dtype == np.float64 and r[name].shape == (12,), name
    assert r["failed"].dtype == np.bool_ and not r["failed"].any()
    assert r["failures"] == []
    # The default tolerances move the tips by tenths of a millimetre.
    assert np.all((r["left_tip_dev_mm"] > 0.01) & (r["left_tip_dev_mm"] < 2.0))
    assert study.seed == 7 and study.rate_hz == 10.0
    # The paper's turn lasts 4.5 s: 46 samples at 10 Hz.
    assert study.n_motion_samples == 46
    assert "point_mm = { sigma = 0.05 }" in study.spec
    assert "seed 7" in repr(study)


@pytest.mark.parametrize("spec", [{}, every_family({"sigma": 0.0}), every_family({"half_width": 0})])
def test_zero_tolerances_replay_the_commands_exactly(spec):
    study = parasils.ToleranceStudy(spec, seed=3, rate_hz=10)
    r = study.run(0, 6)
    assert not r["failed"].any()
    for name in DEVIATIONS:
        assert np.all(r[name] < 1e-9), (name, r[name])
        assert np.all(r[name] >= 0.0), name


def test_a_moved_port_moves_its_tip_by_as_much():
    # Only the ports (rcm_mm, platform frame) are perturbed: module 1 is
    # the nominal one, so the platform goes exactly where commanded and
    # each tip is off by exactly its port's offset, at every sample. Each
    # coordinate is uniform in [-h, h]: |d|^2 has mean h^2 and |d| is at
    # most h sqrt(3).
    h = 0.2
    study = parasils.ToleranceStudy({"instruments": {"rcm_mm": {"half_width": h}}}, rate_hz=10)
    r = study.run(0, 3000)
    assert not r["failed"].any()
    assert np.all(r["pose_position_err_mm"] < 1e-9)
    assert np.all(r["pose_rotation_err_deg"] < 1e-9)
    for side in ("left", "right"):
        d = r[f"{side}_tip_dev_mm"]
        assert d.max() <= h * np.sqrt(3) + 1e-12
        # The standard error of the mean of |d|^2 is 0.009 h^2 here.
        assert abs(np.mean(d**2) / h**2 - 1.0) < 0.04, side
    # The first-order ranking sees the same: one family, the RMS offset
    # of a port (h / sqrt(3) per coordinate, three coordinates): h.
    [only] = study.sensitivity()
    assert only["family"] == "instruments.rcm_mm" and only["share"] == 1.0
    assert abs(only["rms_tip_mm"] - h) < 1e-12


def test_normal_port_offsets_have_the_normal_moments():
    sigma = 0.05
    study = parasils.ToleranceStudy({"instruments": {"rcm_mm": {"sigma": sigma}}}, seed=11, rate_hz=10)
    d = study.run(0, 3000)["right_tip_dev_mm"]
    # |d|^2 / sigma^2 is chi-squared with 3 degrees of freedom: mean 3,
    # variance 6 (standard error of the mean 0.045 over 3000).
    assert abs(np.mean(d**2) / sigma**2 - 3.0) < 0.2
    # Its median is 2.366 (chi2.ppf(0.5, 3)).
    assert abs(np.median(d**2) / sigma**2 - 2.366) < 0.2


def test_the_sensitivity_ranking_adds_up(study):
    ranking = study.sensitivity()
    assert len(ranking) == 8
    keys = {r["family"] for r in ranking}
    assert "module1.guides.point_mm" in keys and "instruments.alpha_deg" in keys
    shares = [r["share"] for r in ranking]
    assert shares == sorted(shares, reverse=True)
    assert abs(sum(shares) - 1.0) < 1e-12
    assert all(r["rms_tip_mm"] > 0 for r in ranking)
    # The ports alone: sigma sqrt(3), as above.
    [rcm] = [r for r in ranking if r["family"] == "instruments.rcm_mm"]
    assert abs(rcm["rms_tip_mm"] - 0.05 * np.sqrt(3)) < 1e-12


def test_a_dict_and_its_toml_file_are_the_same_study(tmp_path):
    spec = {
        "module1": {
            "guides": {"point_mm": {"sigma": 0.08}, "encoder_offset_mm": {"half_width": 0.02}},
            "legs": {"node_mm": {"sigma": 0.03}},
        },
        "instruments": {"beta_deg": {"half_width": 0.05}},
    }
    path = tmp_path / "tol.toml"
    path.write_text(
        "[module1.guides]\n"
        "point_mm = { sigma = 0.08 }\n"
        "encoder_offset_mm = { half_width = 0.02 }\n"
        "[module1.legs]\n"
        "node_mm = { sigma = 0.03 }\n"
        "[instruments]\n"
        "beta_deg = { half_width = 0.05 }\n"
    )
    a = parasils.ToleranceStudy(spec, seed=5, rate_hz=10)
    b = parasils.ToleranceStudy(path, seed=5, rate_hz=10)
    c = parasils.ToleranceStudy(str(path), seed=5, rate_hz=10)
    assert_same(a.run(0, 20), b.run(0, 20))
    assert_same(a.run(0, 20), c.run(0, 20))
    assert a.spec == b.spec
    # The default specification is the one None gives.
    default = tmp_path / "default.toml"
    default.write_text(parasils.ToleranceStudy(None, rate_hz=10).spec)
    assert_same(
        parasils.ToleranceStudy(default, rate_hz=10).run(0, 8),
        parasils.ToleranceStudy(None, rate_hz=10).run(0, 8),
    )
    # Another seed, other robots.
    other = parasils.ToleranceStudy(spec, seed=6, rate_hz=10).run(0, 20)
    assert not np.array_equal(other["left_tip_dev_mm"], a.run(0, 20)["left_tip_dev_mm"])


def test_any_split_gives_the_same_rows(study):
    n = 50
    whole = study.run(0, n)
    for threads in (1, 2, 3):
        assert_same(study.run(0, n, threads=threads), whole)
    pieces = [study.run(0, 7), study.run(7, 1), study.run(8, 30, threads=2), study.run(38, 12)]
    joined = {name: np.concatenate([p[name] for p in pieces]) for name in COLUMNS}
    joined["failures"] = []
    assert_same(joined, whole)
    order = np.random.default_rng(0).permutation(n)
    shuffled = study.run_indices(order, threads=2)
    assert np.array_equal(shuffled["sample"], order)
    back = np.argsort(order)
    for name in COLUMNS:
        assert np.array_equal(shuffled[name][back], whole[name]), name
    # Repeats, and a sample far away computed alone.
    again = study.run_indices([3, 3, 10**12])
    assert np.array_equal(again["left_tip_dev_mm"][:2], whole["left_tip_dev_mm"][[3, 3]])
    assert_same(
        study.run_indices([10**12]),
        {k: v[2:] for k, v in again.items() if k != "failures"} | {"failures": []},
    )
    assert_same(study.run(10**12, 1), study.run_indices(np.array([10**12], dtype=np.uint64)))


def test_the_library_entry_point_is_a_study_run():
    r = parasils.tolerance({"module1": {"legs": {"node_mm": {"sigma": 0.05}}}}, 16, seed=2, rate_hz=10)
    s = parasils.ToleranceStudy({"module1": {"legs": {"node_mm": {"sigma": 0.05}}}}, seed=2, rate_hz=10)
    assert_same(r, s.run(0, 16))
    empty = parasils.tolerance(None, 0, rate_hz=10)
    assert all(len(empty[name]) == 0 for name in COLUMNS) and empty["failures"] == []
    with pytest.raises(ValueError, match="n must be >= 0"):
        parasils.tolerance(None, -1, rate_hz=10)
    with pytest.raises(ValueError, match="chunks must be at least 1"):
        parasils.tolerance(None, 4, rate_hz=10, chunks=0)
    with pytest.raises(TypeError):
        parasils.tolerance(None, 2.5, rate_hz=10)


def test_read_only_and_other_index_arrays(study):
    whole = study.run(0, 10)
    for dtype in (np.int64, np.uint64, np.int32, np.uint8):
        indices = np.arange(10)[::-1].astype(dtype)
        indices.flags.writeable = False
        r = study.run_indices(indices)
        assert np.array_equal(r["left_tip_dev_mm"], whole["left_tip_dev_mm"][::-1]), dtype
    # A read-only view with a stride, as an object store may hand out.
    base = np.arange(20, dtype=np.int64)
    view = base[::2]
    view.flags.writeable = False
    assert np.array_equal(study.run_indices(view)["sample"], np.arange(0, 20, 2))
    assert np.array_equal(study.run_indices(range(3))["sample"], [0, 1, 2])
    assert len(study.run_indices([])["sample"]) == 0
    with pytest.raises(ValueError, match=r"indices\[1\] is -4"):
        study.run_indices([1, -4])
    with pytest.raises(TypeError, match="integers"):
        study.run_indices([0.5, 1.0])
    with pytest.raises(ValueError, match="1-D"):
        study.run_indices(np.zeros((2, 2), dtype=np.int64))
    with pytest.raises(ValueError, match="threads must be at least 1"):
        study.run(0, 2, threads=0)


def test_bad_specifications_are_clear_errors(tmp_path):
    def error(spec):
        with pytest.raises(ValueError) as info:
            parasils.ToleranceStudy(spec, rate_hz=10)
        return str(info.value)

    text = error({"instruments": {"gamma_deg": {"sigma": 1}}})
    assert "unknown key `instruments.gamma_deg`" in text and "instruments.alpha_deg" in text
    text = error({"module2": {}})
    assert "unknown key `module2`" in text
    text = error({"module1": {"guides": {"point_mm": {"sigma": -0.1}}}})
    assert "`module1.guides.point_mm.sigma` must be finite and >= 0, got -0.1" in text
    text = error({"module1": {"guides": {"point_mm": {"spread": 0.1}}}})
    assert "unknown key `module1.guides.point_mm.spread`" in text
    text = error({"module1": {"guides": {"point_mm": {"sigma": 0.1, "half_width": 0.1}}}})
    assert "exactly one of sigma and half_width" in text
    # Legs' nodes 40 mm off (240 mm at six sigma): a link cannot reach.
    text = error({"module1": {"legs": {"node_mm": {"sigma": 40}}}})
    assert "module1.legs.node_mm" in text and "unable to reach its node" in text
    assert "too wide" in text
    text = error({"instruments": {"beta_deg": {"half_width": 95}}})
    assert "instruments.beta_deg" in text and "invalid" in text
    # A file names itself, its line for bad TOML.
    path = tmp_path / "bad.toml"
    path.write_text("[instruments]\nalpha_deg = { sigma = -1.0 }\n")
    text = error(path)
    assert str(path) in text and "got -1" in text
    path.write_text("[instruments\n")
    assert "line 1" in error(path)
    with pytest.raises(FileNotFoundError):
        parasils.ToleranceStudy(tmp_path / "missing.toml")
    with pytest.raises(TypeError, match="spec must be"):
        parasils.ToleranceStudy(42)
    with pytest.raises(ValueError, match="rate_hz must be a positive"):
        parasils.ToleranceStudy(None, rate_hz=0)
    with pytest.raises(TypeError, match="procedure"):
        parasils.ToleranceStudy(None, procedure=DEMO, robot=parasils.Robot())


def test_failed_robots_are_counted_never_dropped():
    study = parasils.ToleranceStudy(WILD, seed=1, rate_hz=10)
    n = 40
    r = study.run(0, n)
    assert np.array_equal(r["sample"], np.arange(n))
    failed = r["failed"]
    assert 0 < failed.sum() < n
    for name in DEVIATIONS:
        assert np.all(np.isnan(r[name][failed])), name
        assert np.all(np.isfinite(r[name][~failed])), name
    assert [s for s, _ in r["failures"]] == list(np.flatnonzero(failed))
    for _, message in r["failures"]:
        assert "module 1" in message and "t = " in message, message
    # The same rows again, split and shuffled.
    order = np.random.default_rng(2).permutation(n)
    again = study.run_indices(order, threads=2)
    assert np.array_equal(again["failed"][np.argsort(order)], failed)
    assert sorted(again["failures"]) == r["failures"]


def test_a_procedure_is_followed():
    study = parasils.ToleranceStudy(None, procedure=DEMO, rate_hz=10)
    motion = parasils.simulate(procedure=DEMO, rate_hz=10)
    assert study.n_motion_samples == len(motion["t_s"])
    r = study.run(0, 8)
    assert not r["failed"].any()
    assert np.all((r["left_tip_dev_mm"] > 0.01) & (r["left_tip_dev_mm"] < 2.0))
    # Its motion is not the paper's turn: other deviations.
    paper = parasils.ToleranceStudy(None, rate_hz=10).run(0, 8)
    assert not np.array_equal(paper["left_tip_dev_mm"], r["left_tip_dev_mm"])
    # A dict of the same structure, its robot path relative to the working
    # directory.
    as_dict = {
        "robot": str(ROOT / "robots" / "default.toml"),
        "pose": [15, 20, -500, -15, 10, -60],
        "motion": [{"type": "reorient", "psi_deg": 15, "theta_deg": 25}],
    }
    d = parasils.ToleranceStudy(None, procedure=as_dict, rate_hz=10)
    assert d.n_motion_samples > 1
    assert not d.run(0, 4)["failed"].any()
    with pytest.raises(ValueError, match="motion 0"):
        parasils.ToleranceStudy(None, procedure={"motion": [{"type": "jump"}]}, rate_hz=10)


def test_the_nominal_robot_is_the_one_given(tmp_path):
    text = parasils.Robot().to_toml().replace("alpha_deg = 10.0", "alpha_deg = 12.5", 1)
    path = tmp_path / "robot.toml"
    path.write_text(text)
    robot = parasils.Robot.from_toml(path)
    by_object = parasils.ToleranceStudy(None, rate_hz=10, robot=robot).run(0, 6)
    by_path = parasils.ToleranceStudy(None, rate_hz=10, robot=path).run(0, 6)
    assert_same(by_object, by_path)
    paper = parasils.ToleranceStudy(None, rate_hz=10, robot=parasils.Robot()).run(0, 6)
    assert_same(paper, parasils.ToleranceStudy(None, rate_hz=10).run(0, 6))
    assert not np.array_equal(paper["left_tip_dev_mm"], by_object["left_tip_dev_mm"])
    with pytest.raises(TypeError, match="robot must be"):
        parasils.ToleranceStudy(None, robot=3)


def unusual_robot(tmp_path):
    """A robot whose numbers are far from round, in degrees and mm."""
    text = parasils.Robot().to_toml()
    text = text.replace("alpha_deg = 10.0", "alpha_deg = 10.123456789012345", 1)
    text = text.replace("beta_deg = 10.0", "beta_deg = 9.87654321", 1)
    text = text.replace("link_length_mm = 350.0", "link_length_mm = 350.1234567890123", 1)
    text = text.replace("node_mm = [0.0, -150.0, 100.0]", "node_mm = [0.3, -150.7, 99.9]")
    text = text.replace("direction = [0.0, 0.0, -1.0]", "direction = [0.01, 0.02, -1.0]", 1)
    path = tmp_path / "unusual.toml"
    path.write_text(text)
    return parasils.Robot.from_toml(path)


def test_a_robot_pickles_to_the_same_bits(tmp_path):
    rng = np.random.default_rng(4)
    poses = P0 + rng.normal(0, 1, (64, 6)) * np.array([10, 10, 10, 0.1, 0.1, 0.1])
    for robot in (parasils.Robot(), unusual_robot(tmp_path)):
        for again in (pickle.loads(pickle.dumps(robot)), copy.deepcopy(robot), copy.copy(robot)):
            assert isinstance(again, parasils.Robot)
            assert again.to_toml() == robot.to_toml()
            assert again.module1_assumed == robot.module1_assumed
            q, ok = robot.module1_ik(poses, errors="nan")
            q2, ok2 = again.module1_ik(poses, errors="nan")
            assert np.array_equal(ok, ok2) and ok.sum() > 40
            assert np.array_equal(q.view(np.uint64), q2.view(np.uint64))
            qs = np.array([0.2, -0.3, 120.0])
            a = robot.instrument_fk("left", poses, qs)
            b = again.instrument_fk("left", poses, qs)
            assert np.array_equal(a.view(np.uint64), b.view(np.uint64))
    unusual = unusual_robot(tmp_path)
    assert pickle.loads(pickle.dumps(unusual)).to_toml() != parasils.Robot().to_toml()
    assert parasils.Robot.from_toml_str(unusual.to_toml()).to_toml() == unusual.to_toml()
    with pytest.raises(parasils.RobotFileError):
        parasils.Robot.from_toml_str("[module1]\nassumed = 3\n")


def test_a_study_pickles_to_the_same_rows(tmp_path):
    robot = unusual_robot(tmp_path)
    studies = [
        parasils.ToleranceStudy(None, seed=9, rate_hz=10),
        parasils.ToleranceStudy(WILD, seed=9, rate_hz=10, robot=robot),
        parasils.ToleranceStudy(
            {"instruments": {"alpha_deg": {"sigma": 0.02}}}, seed=2**64 - 1, procedure=DEMO, rate_hz=5
        ),
        parasils.ToleranceStudy(
            None,
            procedure={"motion": [{"type": "insert", "instrument": "endoscope", "depth_mm": 40}]},
            rate_hz=10,
        ),
    ]
    for study in studies:
        before = study.run(0, 24)
        for again in (pickle.loads(pickle.dumps(study, protocol=p)) for p in (2, 5)):
            assert isinstance(again, parasils.ToleranceStudy)
            assert again.seed == study.seed and again.spec == study.spec
            assert again.n_motion_samples == study.n_motion_samples
            assert_same(again.run(0, 24), before)
            assert again.sensitivity() == study.sensitivity()
        assert_same(copy.deepcopy(study).run(0, 24), before)
    assert studies[1].run(0, 24)["failed"].any()


def test_a_pickled_procedure_reads_its_robot_where_it_was_given(tmp_path, monkeypatch):
    # Relative paths are resolved where the study is built: a worker
    # elsewhere (another working directory) builds the same study.
    monkeypatch.chdir(ROOT / "procedures")
    by_file = parasils.ToleranceStudy(None, procedure="sils-demo.toml", rate_hz=5)
    by_dict = parasils.ToleranceStudy(
        None,
        procedure={"robot": "../robots/default.toml", "motion": [{"type": "reorient", "psi_deg": 5, "theta_deg": 0}]},
        rate_hz=10,
    )
    pickles = [pickle.dumps(s) for s in (by_file, by_dict)]
    before = [s.run(0, 6) for s in (by_file, by_dict)]
    monkeypatch.chdir(tmp_path)
    for data, rows in zip(pickles, before):
        assert_same(pickle.loads(data).run(0, 6), rows)
    with pytest.raises(FileNotFoundError):
        parasils.ToleranceStudy(None, procedure="sils-demo.toml", rate_hz=5)


def test_a_pickle_from_another_version_is_refused():
    study = parasils.ToleranceStudy(None, rate_hz=10)
    constructor, args = study.__reduce__()
    with pytest.raises(ValueError, match="same version everywhere"):
        constructor("0.0.0-other", *args[1:])


def test_a_worker_chunk_runs_on_one_thread_unless_told(monkeypatch, study):
    # parasils._tolerance_chunk is what the workers run: one thread, unless
    # PARASILS_NUM_THREADS is set, which it then obeys (here: a bad value,
    # which the batch's rule refuses).
    monkeypatch.delenv("PARASILS_NUM_THREADS", raising=False)
    assert_same(parasils._tolerance_chunk(3, 5, study), study.run(3, 5))
    monkeypatch.setenv("PARASILS_NUM_THREADS", "none")
    with pytest.raises(ValueError, match="PARASILS_NUM_THREADS"):
        parasils._tolerance_chunk(3, 5, study)
    with pytest.raises(ValueError, match="PARASILS_NUM_THREADS"):
        study.run(0, 2)


def test_a_local_dask_cluster_gives_the_same_rows():
    import distributed
    n = 45
    kwargs = dict(seed=4, rate_hz=10)
    local = parasils.tolerance(WILD, n, **kwargs)
    assert local["failed"].any() and not local["failed"].all()
    with distributed.LocalCluster(
        n_workers=2,
        processes=True,
        threads_per_worker=1,
        dashboard_address=None,
        silence_logs=40,
    ) as cluster, distributed.Client(cluster, timeout="60s") as client:
        assert len(client.nthreads()) == 2
        with concurrent.futures.ThreadPoolExecutor(1) as pool:
            # Bounded in time: a hung cluster fails the test.
            for chunks in (4, None, 1000):
                job = pool.submit(parasils.tolerance, WILD, n, client=client, chunks=chunks, **kwargs)
                assert_same(job.result(timeout=120), local)
            job = pool.submit(parasils.tolerance, None, 0, client=client, rate_hz=10)
            assert len(job.result(timeout=120)["sample"]) == 0
        # Both workers took chunks.
        ran = client.run(lambda dask_worker: len(dask_worker.data) + dask_worker.state.executed_count)
        assert len(ran) == 2 and all(v > 0 for v in ran.values())
