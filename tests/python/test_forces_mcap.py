"""The forces in the MCAP output, read back by an independent reader.

Reads the file named by ``PARASILS_FORCES_MCAP``, written by
``parasils simulate --robot robots/dynamics.toml --tip-load-left 2,-3,-5
--tip-load-right -1.5,2,-4 -o FILE.mcap``, and the same run as CSV named by
``PARASILS_FORCES_CSV``, with the Python ``mcap`` package, and checks that:

- the file has the paper's channels and one more, ``/forces``;
- every ``/forces`` message validates against its embedded schema and equals
  the CSV's fourteen force columns to the last bit;
- every ``/scene`` message validates against Foxglove's official schema
  (pinned, see ``test_mcap.py``), and the ``forces`` entity draws each
  slider's force along its guide (the default robot's guides point down,
  ``u = -Z``) and each tip's load, 2 mm per newton.

Run: ``PARASILS_FORCES_MCAP=forces.mcap PARASILS_FORCES_CSV=forces.csv pytest tests/python``.
"""

from __future__ import annotations

import csv
import json
import math
import os
from collections import defaultdict

import pytest
from mcap.reader import make_reader

from test_mcap import DATA_TOPICS, FOXGLOVE, WRITTEN, official_schema, validator

MCAP_PATH = os.environ.get("PARASILS_FORCES_MCAP")
CSV_PATH = os.environ.get("PARASILS_FORCES_CSV")

FORCES = (
    [f"q{j}_force_n" for j in range(1, 7)]
    + [
        f"{side}_{name}"
        for side in ("left", "right")
        for name in ("qs1_torque_nmm", "qs2_torque_nmm", "qs3_force_n")
    ]
    + ["left_tip_deflection_mm", "right_tip_deflection_mm"]
)
#: The loads the run is written with, N (see the module docs).
LOADS = [(2.0, -3.0, -5.0), (-1.5, 2.0, -4.0)]
MM_PER_N = 2.0


@pytest.fixture(scope="module")
def recording():
    if not (MCAP_PATH and CSV_PATH):
        pytest.skip("set PARASILS_FORCES_MCAP and PARASILS_FORCES_CSV (see the module docs)")
    with open(MCAP_PATH, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        messages = defaultdict(list)
        schemas = {}
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            schemas[channel.topic] = schema
            messages[channel.topic].append(message)
    with open(CSV_PATH, newline="") as f:
        rows = list(csv.DictReader(f))
    return summary, schemas, messages, rows


def test_forces_is_one_more_channel(recording):
    summary, _, _, _ = recording
    topics = {c.topic for c in summary.channels.values()}
    assert topics == set(DATA_TOPICS) | set(FOXGLOVE) | set(WRITTEN) | {"/forces"}
    ids = {c.topic: c.id for c in summary.channels.values()}
    assert ids["/forces"] == max(ids.values()), "after every other channel"


def test_the_forces_are_the_csv_s_to_the_bit(recording):
    _, schemas, messages, rows = recording
    schema = schemas["/forces"]
    assert schema.name == "parasils.Forces"
    embedded = json.loads(schema.data)
    assert embedded["required"] == ["t_s", *FORCES]
    check = validator(embedded)
    assert len(messages["/forces"]) == len(rows)
    for message, row in zip(messages["/forces"], rows, strict=True):
        value = json.loads(message.data)
        check.validate(value)
        for name in ["t_s", *FORCES]:
            assert value[name] == float(row[name]), (name, row["t_s"])


def test_the_arrows_draw_the_forces(recording):
    _, _, messages, rows = recording
    official = validator(official_schema("foxglove.SceneUpdate"))
    by_time = {round(float(r["t_s"]) * 1e9): r for r in rows}
    drawn = 0
    for message in messages["/scene"]:
        scene = json.loads(message.data)
        official.validate(scene)
        entity = scene["entities"][0]
        if entity["id"] != "forces":
            continue
        row = by_time[message.log_time]
        assert entity["metadata"] == [{"key": "mm_per_n", "value": "2.0"}]
        arrows = entity["arrows"]
        assert len(arrows) == 8
        expected = [(0.0, 0.0, -float(row[f"q{j}_force_n"])) for j in range(1, 7)] + LOADS
        for arrow, force in zip(arrows, expected, strict=True):
            length_mm = (arrow["shaft_length"] + arrow["head_length"]) * 1e3
            x, y, z, w = (arrow["pose"]["orientation"][k] for k in "xyzw")
            # The arrow's own x axis: the first column of its rotation.
            axis = (1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y))
            drawn_n = [a * length_mm / MM_PER_N for a in axis]
            norm = math.sqrt(sum(f * f for f in force))
            assert all(abs(d - f) <= 1e-9 * max(norm, 1.0) for d, f in zip(drawn_n, force)), (
                drawn_n,
                force,
            )
        drawn += 1
    assert drawn > 100
