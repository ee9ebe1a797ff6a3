"""A procedure's MCAP file read back by the independent ``mcap`` reader.

Reads the file named by ``PARASILS_PROCEDURE_MCAP`` (written by ``parasils
simulate --procedure procedures/sils-demo.toml -o FILE.mcap``): ``/motion``
validates against its own schema and names the motions in order, ``/scene``
against Foxglove's official ``SceneUpdate``, the endoscope is drawn to its
tip at the simulated depth (a cylinder from its tip to its port, then one
outside), and the tips' paths are sent piece by piece.
"""

import json
import os
from collections import defaultdict

import pytest
from mcap.reader import make_reader

from test_mcap import cylinder_ends, official_schema, validator

PATH = os.environ.get("PARASILS_PROCEDURE_MCAP")


@pytest.fixture(scope="module")
def recording():
    if not PATH:
        pytest.skip("set PARASILS_PROCEDURE_MCAP to a procedure's MCAP file")
    with open(PATH, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
        messages = defaultdict(list)
        schemas = {}
        for schema, channel, message in reader.iter_messages():
            schemas[channel.topic] = schema
            messages[channel.topic].append((message.log_time, json.loads(message.data)))
    return metadata, schemas, messages


def test_motion_messages_validate_and_name_the_motions_in_order(recording):
    metadata, schemas, messages = recording
    schema = json.loads(schemas["/motion"].data)
    assert schemas["/motion"].name == "parasils.ProcedureMotion"
    check = validator(schema)
    motions = messages["/motion"]
    assert len(motions) == len(messages["/platform"])
    seen = []
    for _, m in motions:
        check.validate(m)
        if not seen or seen[-1][0] != m["motion"]:
            seen.append((m["motion"], m["motion_type"], m["type_name"], m["name"]))
    planned = json.loads(metadata["parasils.scenario"]["scenario"])["motions"]
    assert [s[0] for s in seen] == list(range(len(planned)))
    assert [s[2] for s in seen] == [p["type"] for p in planned]
    assert [s[3] for s in seen] == [p.get("name") for p in planned]
    assert {s[2]: s[1] for s in seen} == {"position": 1, "insert": 2, "manipulate": 3, "reorient": 4}


def test_the_scene_is_foxglove_s_and_draws_the_procedure(recording):
    _, schemas, messages = recording
    official = validator(official_schema("foxglove.SceneUpdate"))
    depth_at = {t: m for t, m in messages["/motion"]}
    pieces = []
    for t, scene in messages["/scene"]:
        official.validate(scene)
        entities = {e["id"]: e for e in scene["entities"]}
        assert "tip_targets" not in entities
        # The endoscope from its tip at the simulated depth up to its port,
        # then on outside: the first cylinder that long, the second
        # starting where it ends.
        inside, outside = entities["endoscope"]["cylinders"]
        start, port, _ = cylinder_ends(inside)
        after, _, _ = cylinder_ends(outside)
        m = depth_at[t]
        tip = [m[f"endoscope_tip_{a}_mm"] / 1000.0 for a in "xyz"]
        assert all(abs(p - q) < 1e-12 for p, q in zip(start, tip))
        assert all(abs(p - q) < 1e-12 for p, q in zip(after, port))
        length = sum((p - q) ** 2 for p, q in zip(port, start)) ** 0.5
        assert abs(length - m["endoscope_depth_mm"] / 1000.0) < 1e-12
        paths = [k for k in entities if k.startswith("tip_paths_")]
        assert len(paths) == 1
        pieces.append(int(paths[0].rsplit("_", 1)[1]))
        # Kept (no lifetime): the paths build up from the pieces.
        assert entities[paths[0]]["lifetime"] == {"sec": 0, "nsec": 0}
    assert pieces == list(range(len(pieces)))
    depths = [m["endoscope_depth_mm"] for _, m in messages["/motion"]]
    assert max(depths) == 60.0 and depths[0] == depths[-1] == 0.0
