"""simulate(out=...) checks the output's size before it writes, like the CLI."""

import pytest

import parasils


def test_above_the_cap_needs_force(tmp_path, monkeypatch):
    # A small cap (the variable exists for tests): the paper's CSV is about 4 MB.
    monkeypatch.setenv("PARASILS_OUTPUT_CAP_BYTES", "100000")
    out = tmp_path / "paper.csv"
    with pytest.raises(ValueError, match="force=True"):
        parasils.simulate(out=out)
    assert list(tmp_path.iterdir()) == []  # nothing written, no temporary file
    table = parasils.simulate(out=out, force=True)
    assert out.stat().st_size > 100000
    assert len(table["t_s"]) == 4501
    assert list(tmp_path.iterdir()) == [out]


def test_more_than_the_free_space_is_refused(tmp_path):
    # 1e9 samples per second for 4.5 s: terabytes, more than any test disk holds.
    out = tmp_path / "huge.csv"
    with pytest.raises(OSError) as err:
        parasils.simulate(rate_hz=1e9, out=out, force=True)
    assert err.value.errno == 28  # ENOSPC
    assert list(tmp_path.iterdir()) == []
