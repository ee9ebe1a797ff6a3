"""The MCAP output of `parasils simulate`, read back by an independent reader.

Reads the file named by the environment variable ``PARASILS_MCAP`` (written
by ``parasils simulate -o FILE.mcap``) with the Python ``mcap`` package and
checks that:

- the summary has statistics, chunk indexes and message indexes, and the
  reader can seek with them;
- every message validates against its channel's JSON Schema (``jsonschema``);
  ``/tf`` and ``/scene`` also against Foxglove's official schemas, which the
  embedded ones must equal (see *The official schemas* below);
- each data channel has one message per sample: as many as the rows of the
  CSV named by ``PARASILS_CSV`` when set (the same run written as CSV), else
  the ``samples`` of the ``parasils.run`` metadata record;
- log times increase strictly on each channel and equal ``t_s`` in ns;
- with ``PARASILS_CSV``, every field equals its CSV column to the last bit.

The pinned copies of the official schemas are checked even without a file.

Run: ``pip install -r tests/python/requirements.txt``, then
``PARASILS_MCAP=run.mcap PARASILS_CSV=run.csv pytest tests/python``.

The official schemas
--------------------

The repository holds one copy of Foxglove's JSON Schemas for
``foxglove.FrameTransforms`` and ``foxglove.SceneUpdate``, with their licence:
``crates/parasils-sim/schemas`` (inside the crate, so that ``cargo package``
ships the files its MCAP writer embeds; its README names their origin). This
module reads that copy, and only after checking each file's SHA-256 against
``PINNED_SHA256``: the hashes of the copy that was reviewed against
Foxglove's published files. The copy is thus an independent reference even
though the writer embeds the same files: a file that differs from the
reviewed one by a single byte fails the tests, naming the file and both
hashes, and so does a file added to the folder without a pin; a writer that
embeds anything but the file unchanged fails the equality below.

Two more files there, ``CameraCalibration.json`` and ``ImageAnnotations.json``,
are not Foxglove's: they were written for this project from the fields
Foxglove documents for those messages (the crate's schemas README says so).
They are pinned the same way, so that a change to them is a reviewed change,
and every ``/camera/calibration`` and ``/camera/annotations`` message is
validated against them.

To move to a newer release of the schemas: copy the two files and the
licence, unchanged, from ``schemas/jsonschema/`` of a newer commit of
Foxglove's public ``foxglove/foxglove-sdk`` repository into
``crates/parasils-sim/schemas``; update the commit its README names and the
hashes in ``PINNED_SHA256`` (``sha256sum *`` in that folder); then run the
whole test command (``bash scripts/test``), which writes a fresh MCAP file
and reads it back against them.
"""

from __future__ import annotations

import csv
import hashlib
import json
import os
from collections import defaultdict
from pathlib import Path

import jsonschema
import pytest
from mcap.reader import make_reader
from mcap.stream_reader import StreamReader

#: The one copy of Foxglove's official schemas, inside the simulation crate.
OFFICIAL_SCHEMAS = (
    Path(__file__).resolve().parents[2] / "crates" / "parasils-sim" / "schemas"
)

DATA_TOPICS = ["/platform", "/module1", "/left", "/right", "/tips", "/margins", "/camera"]
FOXGLOVE = {"/tf": "foxglove.FrameTransforms", "/scene": "foxglove.SceneUpdate"}
#: The two Foxglove message types whose schemas were written for this
#: project from Foxglove's documented fields (no official file is kept):
#: pinned like the official ones, so that a change is a reviewed change.
WRITTEN = {
    "/camera/calibration": "foxglove.CameraCalibration",
    "/camera/annotations": "foxglove.ImageAnnotations",
}
OFFICIAL_FILES = {
    "foxglove.FrameTransforms": "FrameTransforms.json",
    "foxglove.SceneUpdate": "SceneUpdate.json",
}
WRITTEN_FILES = {
    "foxglove.CameraCalibration": "CameraCalibration.json",
    "foxglove.ImageAnnotations": "ImageAnnotations.json",
}
#: The SHA-256 of each file of ``OFFICIAL_SCHEMAS`` (its README excepted): the
#: files are used only if they are byte for byte the ones that were reviewed
#: (see *The official schemas* above).
PINNED_SHA256 = {
    "FrameTransforms.json": "95a598789fd7e5a588448cd527fce6a90830a64613ed0daa514a954f7c597099",
    "SceneUpdate.json": "d06db9b671fee79f44bade5853a76e4ac3dce1902b6f619a241c802b7d06d138",
    "LICENSE": "da11235665c17d4c1634072dae92b8ba1b38d6fdde2ccf19a6bbede33253f58d",
    "CameraCalibration.json": "155154c314f20153444a0d0b6014946d3d2d92880e015f172e75b1e63abbebcd",
    "ImageAnnotations.json": "2e1920b67803d562eef4931f71e5249154f82f9a4b36cdacce23e9e60a0bf0e8",
}

MCAP_PATH = os.environ.get("PARASILS_MCAP")
CSV_PATH = os.environ.get("PARASILS_CSV")


def pinned(name: str) -> bytes:
    """The bytes of ``OFFICIAL_SCHEMAS/<name>``, after checking its SHA-256 pin."""
    path = OFFICIAL_SCHEMAS / name
    if not path.is_file():
        pytest.fail(f"{path} is missing: the official schemas live in the repository")
    data = path.read_bytes()
    got = hashlib.sha256(data).hexdigest()
    want = PINNED_SHA256[name]
    if got != want:
        pytest.fail(
            f"{path} has SHA-256 {got}, but {want} is pinned: it is not the "
            "reviewed copy of Foxglove's file. Restore it, or update it as "
            "the docstring of tests/python/test_mcap.py says (pin included)."
        )
    return data


def official_schema(name: str) -> dict:
    """Foxglove's official schema of a message type (``foxglove.SceneUpdate``, ...)."""
    return json.loads(pinned(OFFICIAL_FILES[name]))


def validator(schema: dict) -> jsonschema.protocols.Validator:
    """A validator of the schema's own draft (2020-12 when it names none)."""
    cls = jsonschema.validators.validator_for(
        schema, default=jsonschema.Draft202012Validator
    )
    cls.check_schema(schema)
    return cls(schema)


@pytest.fixture(scope="module")
def recording():
    """Everything in the file, read once: summary, metadata, channels, messages."""
    if not MCAP_PATH:
        pytest.skip(
            "set PARASILS_MCAP to a file written by `parasils simulate -o FILE.mcap`"
        )
    with open(MCAP_PATH, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
        messages = defaultdict(list)
        schemas = {}
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            schemas[channel.topic] = (schema, channel)
            messages[channel.topic].append(message)
    return summary, metadata, schemas, messages


@pytest.fixture(scope="module")
def sample_count(recording) -> int:
    """N: the CSV's rows when given, else the run metadata's sample count."""
    _, metadata, _, _ = recording
    n_meta = int(metadata["parasils.run"]["samples"])
    if CSV_PATH:
        with open(CSV_PATH, newline="") as f:
            n_csv = sum(1 for _ in f) - 1
        assert n_csv == n_meta, (
            "the CSV and the MCAP metadata disagree on the sample count"
        )
        return n_csv
    return n_meta


def test_the_official_schemas_are_the_pinned_copies():
    assert set(PINNED_SHA256) == {
        p.name for p in OFFICIAL_SCHEMAS.iterdir() if p.name != "README.md"
    }, f"every file of {OFFICIAL_SCHEMAS} (but its README) is pinned, and only those"
    for name in PINNED_SHA256:
        pinned(name)
    for name, file in {**OFFICIAL_FILES, **WRITTEN_FILES}.items():
        schema = json.loads(pinned(file))
        assert schema["title"] == name, file
        validator(schema)


def test_summary_has_statistics_and_indexes(recording):
    summary, _, _, messages = recording
    assert summary is not None, "no summary section"
    stats = summary.statistics
    assert stats is not None
    assert stats.message_count == sum(len(v) for v in messages.values())
    assert stats.metadata_count == 2
    assert summary.chunk_indexes, "no chunk indexes"
    for ci in summary.chunk_indexes:
        assert ci.compression == "zstd"
        assert ci.message_index_offsets, "a chunk without message indexes"
    topics = {c.topic for c in summary.channels.values()}
    assert topics == set(DATA_TOPICS) | set(FOXGLOVE) | set(WRITTEN)
    for c in summary.channels.values():
        assert c.message_encoding == "json"
        assert summary.schemas[c.schema_id].encoding == "jsonschema"
        assert stats.channel_message_counts[c.id] == len(messages[c.topic])


def test_the_reader_can_seek(recording):
    _, _, _, messages = recording
    times = [m.log_time for m in messages["/platform"]]
    mid = times[len(times) // 2]
    with open(MCAP_PATH, "rb") as f:
        reader = make_reader(f)
        got = [
            m.log_time
            for _, _, m in reader.iter_messages(
                topics=["/platform"], starting_at=mid, ending_before=mid + 1
            )
        ]
        assert got == [mid]
        last = next(reader.iter_messages(topics=["/left"], reverse=True))[2]
        assert last.log_time == times[-1]


def test_a_linear_read_agrees(recording):
    """A record-by-record read with CRC checks finds the same messages."""
    _, _, _, messages = recording
    counts = defaultdict(int)
    channels = {}
    with open(MCAP_PATH, "rb") as f:
        for record in StreamReader(f, validate_crcs=True).records:
            kind = type(record).__name__
            if kind == "Channel":
                channels[record.id] = record.topic
            elif kind == "Message":
                counts[channels[record.channel_id]] += 1
    assert dict(counts) == {t: len(v) for t, v in messages.items()}


def test_every_message_validates_against_its_schema(recording):
    _, _, schemas, messages = recording
    for topic, (schema, channel) in schemas.items():
        assert schema.encoding == "jsonschema"
        embedded = json.loads(schema.data)
        validators = [validator(embedded)]
        if topic in FOXGLOVE:
            assert schema.name == FOXGLOVE[topic]
            official = official_schema(schema.name)
            assert embedded == official, (
                f"{topic}: the embedded schema is not the official one"
            )
            validators.append(validator(official))
        elif topic in WRITTEN:
            assert schema.name == WRITTEN[topic]
            written = json.loads(pinned(WRITTEN_FILES[schema.name]))
            assert embedded == written, f"{topic}: not the repository's schema"
        else:
            assert embedded["type"] == "object"
            assert embedded["additionalProperties"] is False
            assert set(embedded["required"]) == set(embedded["properties"])
            assert all(p["type"] == "number" for p in embedded["properties"].values())
            assert "t_s" in embedded["required"]
        for message in messages[topic]:
            value = json.loads(message.data)
            for v in validators:
                v.validate(value)


def test_one_message_per_sample_with_sim_time_log_times(recording, sample_count):
    _, _, _, messages = recording
    first = last = None
    for topic in DATA_TOPICS:
        msgs = messages[topic]
        assert len(msgs) == sample_count, topic
        previous = -1
        for m in msgs:
            t = json.loads(m.data)["t_s"]
            assert abs(m.log_time - t * 1e9) <= 0.5, (topic, t, m.log_time)
            assert m.publish_time == m.log_time
            assert m.log_time > previous, (
                f"{topic}: log times do not increase at t = {t} s"
            )
            previous = m.log_time
        if first is None:
            first, last = msgs[0].log_time, msgs[-1].log_time
        assert (msgs[0].log_time, msgs[-1].log_time) == (first, last), topic
    for topic in [*FOXGLOVE, *WRITTEN]:
        msgs = messages[topic]
        assert msgs, topic
        times = [m.log_time for m in msgs]
        assert times == sorted(set(times)), f"{topic}: log times do not increase"
        assert (times[0], times[-1]) == (first, last), topic


def test_transforms_and_scene_are_in_metres(recording):
    _, _, _, messages = recording
    tf = json.loads(messages["/tf"][0].data)["transforms"]
    platform = next(t for t in tf if t["child_frame_id"] == "platform")
    assert platform["parent_frame_id"] == "world"
    p = platform["translation"]
    # The paper's platform is half a metre below the base, not 500 "metres".
    assert 0.05 < (p["x"] ** 2 + p["y"] ** 2 + p["z"] ** 2) ** 0.5 < 5.0
    q = platform["rotation"]
    assert abs(sum(q[k] ** 2 for k in "xyzw") - 1.0) < 1e-9
    scene = json.loads(messages["/scene"][0].data)
    ids = {e["id"] for e in scene["entities"]}
    assert {"module1_legs", "platform", "left_instrument", "right_instrument"} <= ids
    for e in scene["entities"]:
        for line in e["lines"]:
            for pt in line["points"]:
                assert max(abs(pt["x"]), abs(pt["y"]), abs(pt["z"])) < 5.0, e["id"]


def test_metadata_holds_the_scenario_and_geometry(recording, sample_count):
    _, metadata, _, _ = recording
    scenario = metadata["parasils.scenario"]
    s = json.loads(scenario["scenario"])
    assert {"start", "psi", "theta", "rate_hz", "robot"} <= set(s)
    g = json.loads(scenario["geometry"])
    assert len(g["guide_points_mm"]) == 6 and len(g["nodes_mm"]) == 3
    assert scenario["module1_geometry"]
    assert int(metadata["parasils.run"]["samples"]) == sample_count


def cylinder_ends(c: dict) -> tuple[list[float], list[float], float]:
    """The two ends of a ``foxglove.CylinderPrimitive`` (its centre minus and
    plus half its height along its own z, the quaternion's third column) and
    its diameter."""
    p, q, size = c["pose"]["position"], c["pose"]["orientation"], c["size"]
    x, y, z, w = q["x"], q["y"], q["z"], q["w"]
    axis = [2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)]
    assert size["x"] == size["y"], "a round cylinder"
    h = size["z"] / 2
    centre = [p["x"], p["y"], p["z"]]
    return (
        [c_ - h * a for c_, a in zip(centre, axis)],
        [c_ + h * a for c_, a in zip(centre, axis)],
        size["x"],
    )


def test_the_shafts_are_cylinders_from_tip_to_port_and_on(recording):
    """Each instrument shaft is two translucent cylinders of its diameter:
    from its tip to its port (the ``/tips`` fields at the same time), then
    on outside, its length in all (the ``bodies_mm`` metadata: the robot
    file's ``[bodies]``)."""
    _, metadata, _, messages = recording
    bodies = json.loads(metadata["parasils.scenario"]["bodies_mm"])
    length_m = bodies["instrument_length"] / 1000
    diameter_m = bodies["instrument_diameter"] / 1000
    tips = {m.log_time: json.loads(m.data) for m in messages["/tips"]}
    checked = 0
    for m in messages["/scene"]:
        entities = {e["id"]: e for e in json.loads(m.data)["entities"]}
        if "left_instrument" not in entities:
            continue  # the forbidden regions' scene
        t = tips[m.log_time]
        for side in ("left", "right"):
            inside, outside = entities[f"{side}_instrument"]["cylinders"]
            tip, port, d_in = cylinder_ends(inside)
            start, end, d_out = cylinder_ends(outside)
            want_tip = [t[f"{side}_tip_{a}_mm"] / 1000 for a in "xyz"]
            want_port = [t[f"{side}_port_{a}_mm"] / 1000 for a in "xyz"]
            assert max(abs(a - b) for a, b in zip(tip, want_tip)) < 1e-12
            assert max(abs(a - b) for a, b in zip(port, want_port)) < 1e-12
            assert max(abs(a - b) for a, b in zip(start, port)) < 1e-12
            assert d_in == d_out and abs(d_in - diameter_m) < 1e-15
            assert inside["color"]["a"] < 1 and outside["color"]["a"] < 1
            length = sum((a - b) ** 2 for a, b in zip(end, tip)) ** 0.5
            assert abs(length - length_m) < 1e-12
        checked += 1
    assert checked > 0


@pytest.mark.skipif(
    not CSV_PATH, reason="set PARASILS_CSV to the same run written as CSV"
)
def test_fields_equal_the_csv_to_the_last_bit(recording):
    _, _, _, messages = recording
    with open(CSV_PATH, newline="") as f:
        rows = list(csv.DictReader(f))
    for topic in DATA_TOPICS:
        for row, m in zip(rows, messages[topic], strict=True):
            for name, value in json.loads(m.data).items():
                if name in row:
                    assert value == float(row[name]), (topic, name, row["t_s"])
