"""Docstrings with units on every public name, visible through help(); stubs for all."""

import ast
import doctest
import inspect
import pydoc
from pathlib import Path

import pytest

import parasils

METHODS = [
    "from_toml",
    "to_toml",
    "instrument_ik",
    "instrument_fk",
    "instrument_rates",
    "module1_ik",
    "module1_fk",
    "module1_rates",
]


@pytest.mark.parametrize("name", METHODS)
def test_methods_have_docstrings_with_units(name):
    doc = getattr(parasils.Robot, name).__doc__
    assert doc and len(doc) > 40, name
    if name.startswith(("instrument", "module1")):
        assert "mm" in doc and "rad" in doc, name
        assert "shape" in doc and "errors" in doc, name
    text = pydoc.render_doc(getattr(parasils.Robot, name), renderer=pydoc.plaintext)
    assert doc.splitlines()[0] in text


def test_signatures_are_visible():
    sig = inspect.signature(parasils.Robot.instrument_ik)
    assert list(sig.parameters)[1:4] == ["side", "pose", "tip"]
    assert sig.parameters["mode"].default == "A"
    assert sig.parameters["errors"].kind is inspect.Parameter.KEYWORD_ONLY
    sig = inspect.signature(parasils.simulate)
    # Every option is None when not given (not given is not its default).
    for name, default in [
        ("psi_deg", None),
        ("theta_deg", None),
        ("absolute", None),
        ("omega_max_deg_s", None),
        ("eps_max_deg_s2", None),
        ("rate_hz", None),
        ("sync", None),
        ("timing", None),
        ("pose_mm_deg", None),
        ("pose", None),
        ("tip_left_mm", None),
        ("tip_right_mm", None),
        ("out", None),
        ("retarget", None),
        ("stop_at_s", None),
    ]:
        assert sig.parameters[name].default == default, name
        assert sig.parameters[name].kind is inspect.Parameter.KEYWORD_ONLY


def test_simulate_documents_the_library_s_defaults():
    doc = parasils.simulate.__doc__
    paper = parasils._PAPER
    assert f"default {paper['psi_deg']:g}, {paper['theta_deg']:g}" in doc
    assert f"velocity limit, deg/s; default {paper['omega_max_deg_s']:g}" in doc
    assert f"default {paper['rate_hz']:g}" in doc
    assert paper["pose_mm_deg"] == [15.0, 20.0, -500.0, -15.0, 10.0, -60.0]


def test_deprecated_aliases_are_documented():
    for old, new in [("platform_ik", "module1_ik"), ("platform_fk", "module1_fk"), ("platform_rates", "module1_rates")]:
        doc = getattr(parasils.Robot, old).__doc__
        assert "Deprecated" in doc and new in doc, old


def test_help_of_the_package_class_and_simulate():
    text = pydoc.render_doc(parasils, renderer=pydoc.plaintext)
    assert "PARA-SILSROB" in text and "simulate" in text and "KinematicsError" in text
    robot = pydoc.render_doc(parasils.Robot, renderer=pydoc.plaintext)
    assert "mm, rad, s" in robot and "instrument_ik" in robot
    sim = parasils.simulate.__doc__
    for word in ("deg/s", "deg/s^2", "Hz", "mm", "COLUMNS" if False else "column", "MCAP"):
        assert word in sim, word


def test_exceptions_document_their_attributes():
    assert "row" in parasils.KinematicsError.__doc__ and "kind" in parasils.KinematicsError.__doc__
    assert "limit" in parasils.JointLimitError.__doc__
    assert "line" in parasils.RobotFileError.__doc__


def test_the_package_docstring_example_runs():
    failures, tried = doctest.testmod(parasils, verbose=False)
    assert tried > 0 and failures == 0


def test_stubs_cover_every_public_name():
    stub = Path(parasils.__file__).with_name("__init__.pyi")
    assert stub.is_file() and Path(parasils.__file__).with_name("py.typed").is_file()
    tree = ast.parse(stub.read_text())
    names = set()
    classes = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            names.add(node.name)
            classes[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
        elif isinstance(node, ast.FunctionDef):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    assert set(parasils.__all__) <= names
    public = {n for n in dir(parasils) if not n.startswith("_")} | {"__version__"}
    assert public == set(parasils.__all__)
    robot_methods = {n for n in dir(parasils.Robot) if not n.startswith("_")}
    assert robot_methods <= classes["Robot"]
