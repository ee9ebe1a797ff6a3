"""``parasils.teleop``: the shipped session ``inputs/teleop-demo.csv``
replayed from Python, compared with ``parasils teleop``'s CSV to the last
bit, and its clutch checked with NumPy alone."""

import numpy as np
import pytest

import parasils
from conftest import ROOT
from test_simulate import read_csv

DEMO = ROOT / "inputs" / "teleop-demo.csv"


def test_the_demo_equals_the_cli_csv_to_the_last_bit(run_cli, tmp_path):
    path = tmp_path / "cli.csv"
    run_cli("teleop", "--input", DEMO, "-o", path)
    table = parasils.teleop(DEMO)
    expected = read_csv(path)
    assert list(table)[: len(parasils.COLUMNS)] == list(parasils.COLUMNS)
    assert list(table) == list(expected)
    for name, a in table.items():
        b = expected[name]
        if a.dtype == np.int64:
            # The codes and bit masks, written as integers.
            assert np.array_equal(a.astype(np.float64), b), name
        else:
            assert a.dtype == np.float64 and a.shape == b.shape, name
            assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), name


def test_the_clutch_moves_no_tip():
    table = parasils.teleop(DEMO)
    clutch = (table["left_buttons"] & 2) != 0
    changes = np.flatnonzero(clutch[1:] != clutch[:-1]) + 1
    # Pressed at 2.2 s, released at 2.5 s (rows at 1 kHz).
    assert table["t_s"][changes].tolist() == [2.2, 2.5]
    tips = np.stack(
        [table[f"{side}_tip_{axis}_mm"] for side in ("left", "right") for axis in "xyz"]
    )
    for k in changes:
        # Exactly zero: the same floats before and after.
        assert np.array_equal(tips[:, k], tips[:, k - 1])


def test_a_bad_session_is_a_value_error_naming_its_line(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("t_s,device,tx,ty,tz,rx,ry,rz,buttons,command\n0,middle,0,0,0,0,0,0,0,\n")
    with pytest.raises(ValueError, match="bad.csv: line 2: device: `middle`"):
        parasils.teleop(bad)
