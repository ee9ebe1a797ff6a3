"""The README's Python example runs as written, and says what it computes."""

import os
import re
from pathlib import Path

import numpy as np

README = Path(__file__).resolve().parents[3] / "README.md"


def python_blocks():
    text = README.read_text(encoding="utf-8")
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def test_the_readme_python_example_runs(tmp_path):
    blocks = python_blocks()
    assert len(blocks) == 1, "one Python example in the README"
    cwd = os.getcwd()
    os.chdir(tmp_path)  # the example writes paper.mcap
    try:
        ns = {}
        exec(compile(blocks[0], str(README), "exec"), ns)
    finally:
        os.chdir(cwd)
    # What its comments say.
    np.testing.assert_allclose(ns["tip"], [50, -50, -620], atol=1e-9)
    assert ns["q"].shape == (6,)
    np.testing.assert_allclose(ns["pose"], ns["p0"], atol=1e-9)
    assert ns["qs"].shape == (1_000_000, 3)
    assert ns["ok"].shape == (1_000_000,)
    assert ns["df"].shape == (4501, 74)
    assert (tmp_path / "paper.mcap").stat().st_size > 0
