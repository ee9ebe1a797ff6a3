"""``parasils serve`` driven by the Python client helper (``parasils.live``):
commands acknowledged with CRTK's states, a bad command refused, a hand's
input moving the setpoint it drives, and the session ended by SIGINT with
its recording complete, read back by the ``mcap`` package and validated
against each channel's JSON Schema."""

import importlib
import json
import signal
import subprocess
import sys

import pytest


@pytest.fixture
def live():
    """``parasils.live``, imported for the test and forgotten after it:
    the package imports it only on demand, and the other tests see the
    package as a user who never imported it does (``test_docs`` checks
    its public names)."""
    pytest.importorskip("websockets", reason="parasils.live needs the websockets package")
    module = importlib.import_module("parasils.live")
    yield module
    sys.modules.pop("parasils.live", None)
    parent = sys.modules.get("parasils")
    if parent is not None and hasattr(parent, "live"):
        delattr(parent, "live")


@pytest.fixture
def server(cli, tmp_path):
    """``parasils serve`` on a free port for at most 20 s, recording to
    ``live.mcap``; yields (url, process, recording)."""
    recording = tmp_path / "live.mcap"
    proc = subprocess.Popen(
        [cli, "serve", "--port", "0", "--duration-s", "20", "-o", str(recording)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        line = proc.stdout.readline().strip()
        prefix = "parasils: serving on "
        assert line.startswith(prefix), line
        yield line[len(prefix):], proc, recording
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait()


def test_commands_inputs_and_a_complete_recording(server, live):
    url, proc, recording = server
    with live.LiveClient(url) as c:
        assert "/left/setpoint_cp" in c.channels and "/diagnostics" in c.channels
        # CRTK's table: pause is invalid in DISABLED, then enable, pause,
        # resume (the state each led to, from the acknowledgement).
        refused = c.command("pause")
        assert (refused["accepted"], refused["state"]) == (False, "DISABLED")
        assert "not valid in DISABLED" in refused["reason"]
        assert c.command("enable")["state"] == "ENABLED"
        assert c.command("pause")["state"] == "PAUSED"
        assert c.command("resume")["state"] == "ENABLED"
        with pytest.raises(live.LiveError, match="unknown command `jump`"):
            c.command("jump")
        # The left hand engaged at rest, then pushed along its first axis:
        # one of the two instrument tips moves (the hand drives the tip on
        # its side of the image), the other stays.
        c.subscribe(["/left/setpoint_cp", "/right/setpoint_cp"])
        c.publish_input("left", [0, 0, 0, 0, 0, 0], buttons=1, id=1)
        before = c.receive(duration_s=0.3)
        c.publish_input("left", [1, 0, 0, 0, 0, 0], buttons=1, id=2)
        c.wait_for("/diagnostics", lambda d: (d["last_input"] or {}).get("id") == 2)
        after = c.receive(duration_s=0.5)

        def moved(topic):
            first = [m["position"] for t, _, m in before if t == topic][-1]
            last = [m["position"] for t, _, m in after if t == topic][-1]
            return max(abs(first[k] - last[k]) for k in "xyz")

        moves = sorted([moved("/left/setpoint_cp"), moved("/right/setpoint_cp")])
        print("tip moves, mm:", moves)
        assert moves[0] == 0.0 and moves[1] > 1e-3
        # The planned moves and the stop, with their goals: accepted in
        # ENABLED; the port itself is a point no view aims at.
        assert c.command("stop")["accepted"]
        assert c.command("look_at", point_mm=[20, 30, -600])["accepted"]
        refused = c.command("look_at", point_mm=[15, 20, -500])
        assert not refused["accepted"] and "camera:" in refused["reason"]
        assert c.command("move_to", psi_deg=-13, theta_deg=10)["accepted"]
        assert c.command("look_at_tips")["state"] == "ENABLED"
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 0, err
    assert "signal 2: ending the session" in err
    check_recording(recording)


def check_recording(path):
    """The recording read back by the ``mcap`` package (summary, CRCs) and
    every message validated against its channel's JSON Schema."""
    mcap_reader = pytest.importorskip("mcap.reader")
    jsonschema = pytest.importorskip("jsonschema")
    validators = {}
    counts = {}
    with open(path, "rb") as f:
        reader = mcap_reader.make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        assert summary is not None and summary.statistics.message_count > 0
        for schema, channel, message in reader.iter_messages():
            assert schema.encoding == "jsonschema" and channel.message_encoding == "json"
            if channel.id not in validators:
                validators[channel.id] = jsonschema.validators.validator_for(
                    json.loads(schema.data), default=jsonschema.Draft202012Validator
                )(json.loads(schema.data))
            validators[channel.id].validate(json.loads(message.data))
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
    assert summary.statistics.message_count == sum(counts.values())
    for topic in ["/left/measured_js", "/platform/setpoint_cp", "/scene", "/diagnostics", "/command_ack"]:
        assert counts.get(topic, 0) > 0, topic
    # The ten commands: nine acknowledged (four of CRTK's, then stop, two
    # look_at, move_to, look_at_tips), the unknown one refused before.
    assert counts["/command_ack"] == 9
