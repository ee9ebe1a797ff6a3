"""A teleoperation run's MCAP file read back by the independent ``mcap`` reader.

Reads the file named by ``PARASILS_TELEOP_MCAP`` and the CSV of the same run
named by ``PARASILS_TELEOP_CSV`` (both written by ``parasils teleop --input
inputs/teleop-demo.csv --rate 100 -o FILE``): ``/teleop`` has one message
per cycle, each valid against its own schema; its numbers are the CSV's
columns of the same name, value for value; its words say what the codes
say (the state's name by the CSV's code, a hold exactly where the CSV has
one); and the other channels are those of every run, in the same order.
"""

import csv
import json
import os
from collections import defaultdict

import pytest
from mcap.reader import make_reader

from test_mcap import validator

PATH = os.environ.get("PARASILS_TELEOP_MCAP")
CSV_PATH = os.environ.get("PARASILS_TELEOP_CSV")

#: The codes of ``teleop_state``, in the order ``crates/parasils-sim/src/teleop.rs`` documents.
STATES = ["DISABLED", "ENABLED", "PAUSED", "FAULT"]


@pytest.fixture(scope="module")
def recording():
    if not PATH or not CSV_PATH:
        pytest.skip("set PARASILS_TELEOP_MCAP and PARASILS_TELEOP_CSV to one teleoperation run's files")
    with open(PATH, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        topics = [c.topic for c in sorted(reader.get_summary().channels.values(), key=lambda c: c.id)]
        messages = defaultdict(list)
        schemas = {}
        for schema, channel, message in reader.iter_messages():
            schemas[channel.topic] = schema
            messages[channel.topic].append(json.loads(message.data))
    with open(CSV_PATH, newline="") as f:
        rows = list(csv.DictReader(f))
    return topics, schemas, messages, rows


def test_the_teleop_channel_comes_last_after_every_run_s_channels(recording):
    topics, _, _, _ = recording
    assert topics[-1] == "/teleop"
    assert topics[:7] == ["/platform", "/module1", "/left", "/right", "/tips", "/margins", "/camera"]
    assert topics.count("/teleop") == 1


def test_one_valid_message_per_cycle_with_the_csv_s_numbers(recording):
    _, schemas, messages, rows = recording
    assert schemas["/teleop"].name == "parasils.Teleop"
    check = validator(json.loads(schemas["/teleop"].data))
    teleop = messages["/teleop"]
    assert len(teleop) == len(rows) == len(messages["/platform"])
    numeric = [k for k in teleop[0] if k not in ("state", "hold", "fault")]
    assert numeric[0] == "t_s" and "teleop_hold" in numeric and "left_tx" in numeric
    for m, row in zip(teleop, rows):
        check.validate(m)
        for k in numeric:
            # Both are shortest round-trip decimals of the same double.
            assert float(m[k]) == float(row[k]), (k, m["t_s"])


def test_the_words_say_what_the_codes_say(recording):
    _, _, messages, _ = recording
    teleop = messages["/teleop"]
    held = 0
    for m in teleop:
        assert m["state"] == STATES[m["teleop_state"]]
        assert (m["hold"] != "") == (m["teleop_hold"] != 0)
        assert (m["fault"] != "") == (m["teleop_fault"] != 0)
        held += m["teleop_hold"] != 0
    # The demo session pushes the right module's qs3 into its stop
    # threshold and holds there for several seconds.
    assert held > 100
    assert any("right.qs3_limits" in m["hold"] for m in teleop)
    assert [s for s in STATES if any(m["state"] == s for m in teleop)] == ["DISABLED", "ENABLED", "PAUSED"]
