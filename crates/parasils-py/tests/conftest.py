"""Shared fixtures of the parasils Python tests.

The tests run against the installed package (``scripts/python-tests`` builds
the wheel into a fresh virtual environment). The comparison with the CLI
needs its binary: ``PARASILS_CLI=/path/to/parasils``.
"""

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import parasils

#: The repository's root (tests/ is crates/parasils-py/tests).
ROOT = Path(__file__).resolve().parents[3]

#: The paper's start pose P0 = (15, 20, -500 mm, -15, 10, -60 deg), in mm and rad.
P0 = np.array([15.0, 20.0, -500.0, *np.radians([-15.0, 10.0, -60.0])])
#: The paper's left tip, mm, fixed frame.
LEFT_TIP = np.array([50.0, -50.0, -620.0])


def rotation(psi, theta, phi):
    """R = R_X(psi) R_Y(theta) R_Z(phi), written here independently of the crate."""
    cx, sx = np.cos(psi), np.sin(psi)
    cy, sy = np.cos(theta), np.sin(theta)
    cz, sz = np.cos(phi), np.sin(phi)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rx @ ry @ rz


def to_fixed(pose, c):
    """A platform-frame point (mm) in the fixed frame at `pose` (mm, rad)."""
    return rotation(*pose[3:]) @ np.asarray(c, dtype=float) + pose[:3]


def mirror_tip(pose, tip):
    """The mirror image of a fixed-frame point across the platform's Y'Z' plane."""
    r = rotation(*pose[3:])
    c = r.T @ (np.asarray(tip) - pose[:3])
    c[0] = -c[0]
    return r @ c + pose[:3]


@pytest.fixture(scope="session")
def robot():
    return parasils.Robot()


def default_right_tip(pose, tip):
    """The simulation's default right tip: the mirror image of `tip` moved
    35 mm along X' and 100 mm along Y' (docs/model.md, *The paper's
    scenario*), so that the shafts do not meet."""
    return mirror_tip(pose, tip) + rotation(*pose[3:]) @ np.array([35.0, 100.0, 0.0])


@pytest.fixture(scope="session")
def right_tip():
    """The paper's mirror image of the left tip at P0 (its check values)."""
    return mirror_tip(P0, LEFT_TIP)


@pytest.fixture(scope="session")
def default_right():
    """The right tip `simulate` holds by default."""
    return default_right_tip(P0, LEFT_TIP)


@pytest.fixture(scope="session")
def cli():
    """The `parasils` binary: $PARASILS_CLI, else one on PATH."""
    path = os.environ.get("PARASILS_CLI") or shutil.which("parasils")
    if not path:
        pytest.skip("set PARASILS_CLI to the parasils binary (scripts/python-tests does)")
    return path


@pytest.fixture(scope="session")
def run_cli(cli):
    def run(*args):
        proc = subprocess.run(
            [cli, *map(str, args)], capture_output=True, text=True, check=False
        )
        assert proc.returncode == 0, proc.stderr
        return proc

    return run
