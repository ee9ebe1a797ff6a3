"""simulate(anatomy=): the no-go column last, equal to the CLI's table to
the bit, and a
run into a region refused naming the region and the body."""

import numpy as np
import pytest

import parasils
from conftest import ROOT
from test_simulate import read_csv

DEMO = ROOT / "procedures" / "sils-demo.toml"
ANATOMY = ROOT / "procedures" / "anatomy" / "demo.toml"


def test_the_column_comes_last_and_equals_the_cli_s(run_cli, tmp_path):
    path = tmp_path / "cli.csv"
    run_cli("simulate", "--procedure", DEMO, "--anatomy", ANATOMY, "--rate", "50", "-o", path)
    table = parasils.simulate(procedure=str(DEMO), anatomy=str(ANATOMY), rate_hz=50.0)
    plain = parasils.simulate(procedure=str(DEMO), rate_hz=50.0)
    assert list(table) == list(plain) + ["no_go_clearance_mm"]
    cli = read_csv(path)
    assert list(cli) == list(table)
    for name in table:
        ours = np.asarray(table[name], dtype=np.float64)  # motion, motion_type: int64
        assert np.array_equal(ours.view(np.uint64), cli[name].view(np.uint64)), name
    # The demo clears every region of the example anatomy.
    assert table["no_go_clearance_mm"].min() > 10.0


def test_a_run_into_a_region_raises_naming_it(tmp_path):
    anatomy = tmp_path / "ball.toml"
    # The paper's left tip is (50, -50, -620): a ball 10 mm below it with a
    # radius of 8 mm leaves 2 mm to the tip, -0.5 mm to the 5 mm shaft.
    anatomy.write_text(
        '[[region]]\nname = "ball"\nshape = "sphere"\ncentre_mm = [50, -50, -630]\nradius_mm = 8\n'
    )
    with pytest.raises(ValueError, match=r'left shaft is -0\.500 mm from the forbidden region "ball"'):
        parasils.simulate(anatomy=str(anatomy), rate_hz=50.0)


def test_a_bad_or_missing_anatomy_file_names_itself(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[[region]]\nname = "k"\nshape = "sphere"\ncentre_mm = [0, 0]\nradius_mm = 1\n')
    with pytest.raises(ValueError, match="region k: centre_mm"):
        parasils.simulate(anatomy=str(bad))
    with pytest.raises(OSError, match="missing.toml"):
        parasils.simulate(anatomy=str(tmp_path / "missing.toml"))
