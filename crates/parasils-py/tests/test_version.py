"""One version everywhere: the workspace's Cargo.toml, the installed Python
package (its module attribute and its distribution metadata) and the
`parasils` command."""

import subprocess
from importlib import metadata
from pathlib import Path

import pytest

import parasils

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")

WORKSPACE_MANIFEST = Path(__file__).resolve().parents[3] / "Cargo.toml"


def workspace_version():
    with WORKSPACE_MANIFEST.open("rb") as f:
        manifest = tomllib.load(f)
    return manifest["workspace"]["package"]["version"]


def test_the_workspace_states_one_version():
    version = workspace_version()
    parts = version.split(".")
    assert len(parts) == 3 and all(p.isdigit() for p in parts), version


def test_the_module_reports_the_workspace_version():
    assert parasils.__version__ == workspace_version()


def test_the_installed_distribution_has_the_workspace_version():
    # maturin's `dynamic = ["version"]`: the wheel's metadata from Cargo.
    assert metadata.version("parasils") == workspace_version()


def test_the_command_prints_the_workspace_version(cli):
    out = subprocess.run([cli, "--version"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == f"parasils {workspace_version()}"
