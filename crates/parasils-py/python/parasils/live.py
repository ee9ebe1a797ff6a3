"""A small client of ``parasils serve``: the robot live over Foxglove's
WebSocket protocol (subprotocol ``foxglove.sdk.v1``), from Python.

Subscribe to channels, publish a hand's input, send a CRTK command and wait
for its acknowledgement::

    from parasils.live import LiveClient

    with LiveClient("ws://127.0.0.1:8765") as c:
        ack = c.command("enable")          # {"state": "ENABLED", "accepted": True, ...}
        c.publish_input("left", [0, 0, 0, 0, 0, 0], buttons=1)   # engage
        c.publish_input("left", [0.5, 0, 0, 0, 0, 0], buttons=1)  # move
        for topic, log_time_ns, msg in c.receive(["/right/setpoint_cp"], duration_s=1.0):
            print(msg["position"])         # mm, fixed frame

Built on the ``websockets`` package (its synchronous client), which this
module needs and the rest of ``parasils`` does not: ``pip install
parasils[live]``. Every message on the server's channels is JSON; each
topic's schema is in the README (*Live*).
"""

from __future__ import annotations

import json
import struct
import time
from typing import Iterable, Optional, Sequence

from websockets.sync.client import connect

#: The subprotocol ``parasils serve`` speaks (the legacy
#: ``foxglove.websocket.v1`` is refused with HTTP 400).
SUBPROTOCOL = "foxglove.sdk.v1"

#: The input topic of each device.
INPUT_TOPICS = {
    "left": "/left/servo_input",
    "right": "/right/servo_input",
    "camera": "/camera/servo_input",
}
#: The command topic.
COMMAND_TOPIC = "/command"
#: The topic a client publishes the server's token on (``parasils serve
#: --token``), before it may drive.
AUTH_TOPIC = "/auth"
#: The topic of the commands' acknowledgements.
ACK_TOPIC = "/command_ack"

_MESSAGE_DATA = 1


class LiveError(RuntimeError):
    """The server refused a message (its status message is the text), or
    an answer did not come in time."""


class LiveClient:
    """A connection to ``parasils serve`` at ``url``.

    On connecting it reads the server's channels (``channels``: topic to
    channel id); :meth:`subscribe` asks for some, :meth:`receive` returns
    what arrives; :meth:`publish_input` and :meth:`command` publish on the
    client channels, advertised on first use. Status messages the server
    sends this client (acknowledgements, errors) are kept in ``statuses`` as
    ``(level, message)``, level 0 info, 1 warning, 2 error.
    """

    def __init__(
        self,
        url: str = "ws://127.0.0.1:8765",
        *,
        token: Optional[str] = None,
        timeout_s: float = 5.0,
    ):
        self.timeout_s = timeout_s
        # Entered as a context manager: the form every version of
        # websockets' synchronous client takes.
        self._connection = connect(url, subprotocols=[SUBPROTOCOL], open_timeout=timeout_s)
        self._ws = self._connection.__enter__()
        self.channels: dict[str, int] = {}
        self.schemas: dict[str, str] = {}
        self.statuses: list[tuple[int, str]] = []
        self._subscriptions: dict[int, str] = {}
        self._inputs: dict[str, int] = {}
        self._pending: list[tuple[str, int, dict]] = []
        deadline = time.monotonic() + timeout_s
        while not self.channels and time.monotonic() < deadline:
            self._read(deadline - time.monotonic())
        if not self.channels:
            raise LiveError(f"{url}: no channel advertised within {timeout_s} s")
        if token is not None:
            self.publish(AUTH_TOPIC, {"token": token})

    def __enter__(self) -> "LiveClient":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Closes the connection."""
        self._connection.__exit__(None, None, None)

    # Reading.

    def _read(self, timeout_s: float) -> bool:
        """Reads one message; False when none came in ``timeout_s`` or the
        connection closed."""
        try:
            data = self._ws.recv(timeout=max(timeout_s, 0.0))
        except TimeoutError:
            return False
        except Exception:  # the server closed the connection
            return False
        if isinstance(data, str):
            msg = json.loads(data)
            op = msg.get("op")
            if op == "advertise":
                for ch in msg["channels"]:
                    self.channels[ch["topic"]] = ch["id"]
                    self.schemas[ch["topic"]] = ch.get("schemaName", "")
            elif op == "status":
                self.statuses.append((msg.get("level", 0), msg.get("message", "")))
            return True
        if len(data) >= 13 and data[0] == _MESSAGE_DATA:
            sub, log_time = struct.unpack_from("<IQ", data, 1)
            topic = self._subscriptions.get(sub)
            if topic is not None:
                self._pending.append((topic, log_time, json.loads(data[13:])))
        return True

    def subscribe(self, topics: Iterable[str]) -> None:
        """Subscribes to ``topics`` (names of the server's channels).

        Raises:
            LiveError: for a topic the server does not have.
        """
        subs = []
        for topic in topics:
            if topic not in self.channels:
                raise LiveError(f"{topic}: no such channel (the server has {sorted(self.channels)})")
            if topic in self._subscriptions.values():
                continue
            sub = len(self._subscriptions) + 1
            self._subscriptions[sub] = topic
            subs.append({"id": sub, "channelId": self.channels[topic]})
        if subs:
            self._ws.send(json.dumps({"op": "subscribe", "subscriptions": subs}))

    def receive(
        self, topics: Optional[Sequence[str]] = None, *, duration_s: float = 1.0
    ) -> list[tuple[str, int, dict]]:
        """The messages that arrive within ``duration_s`` (s), as ``(topic,
        log_time_ns, message)``, subscribing first to ``topics`` if given."""
        if topics:
            self.subscribe(topics)
        end = time.monotonic() + duration_s
        while time.monotonic() < end:
            self._read(end - time.monotonic())
        out, self._pending = self._pending, []
        return out

    def wait_for(self, topic: str, predicate, *, timeout_s: Optional[float] = None) -> dict:
        """The first message on ``topic`` (subscribed if it is not) for
        which ``predicate(message)`` is true; messages of other topics read
        meanwhile are kept for :meth:`receive`.

        Raises:
            LiveError: when none comes within ``timeout_s`` (default: the
            client's ``timeout_s``).
        """
        self.subscribe([topic])
        end = time.monotonic() + (self.timeout_s if timeout_s is None else timeout_s)
        while True:
            for k, (t, _, msg) in enumerate(self._pending):
                if t == topic and predicate(msg):
                    del self._pending[k]
                    return msg
            if time.monotonic() >= end:
                raise LiveError(f"{topic}: no matching message within the time limit")
            self._read(min(0.05, end - time.monotonic()))

    # Publishing.

    def _channel(self, topic: str) -> int:
        if topic not in self._inputs:
            cid = len(self._inputs) + 1
            self._ws.send(
                json.dumps(
                    {
                        "op": "advertise",
                        "channels": [
                            {"id": cid, "topic": topic, "encoding": "json", "schemaName": "parasils.Input"}
                        ],
                    }
                )
            )
            self._inputs[topic] = cid
        return self._inputs[topic]

    def publish(self, topic: str, message: dict) -> None:
        """Publishes ``message`` (JSON) on the client channel ``topic``."""
        cid = self._channel(topic)
        self._ws.send(struct.pack("<BI", _MESSAGE_DATA, cid) + json.dumps(message).encode())

    def publish_input(
        self,
        device: str,
        axes: Sequence[float],
        *,
        buttons: int = 0,
        id: Optional[int] = None,
    ) -> None:
        """Publishes a device's state: ``device`` is ``"left"``, ``"right"``
        or ``"camera"``; ``axes`` the six normalised axes ``tx ty tz rx ry
        rz``, each in [-1, 1]; ``buttons`` bit 0 enable, bit 1 clutch. The
        input holds until the device's next one; ``id`` comes back in
        ``/diagnostics``' ``last_input``."""
        if device not in INPUT_TOPICS:
            raise ValueError(f"device must be one of {sorted(INPUT_TOPICS)}, not {device!r}")
        msg = {"axes": [float(a) for a in axes], "buttons": int(buttons)}
        if id is not None:
            msg["id"] = int(id)
        self.publish(INPUT_TOPICS[device], msg)

    def command(self, name: str, *, timeout_s: Optional[float] = None, **goal) -> dict:
        """Sends the command ``name`` and returns its acknowledgement:
        ``{"command", "id", "accepted", "before", "state", "reason", "t_s"}``
        (``state`` is the state it led to; ``reason`` says why a refused
        command was invalid or a move was refused).

        ``name`` is a CRTK command (``enable``, ``disable``, ``pause``,
        ``resume``), ``home``, ``look_at_tips``, ``stop``, or a planned move
        with its goal in ``goal``: ``look_at`` with ``point_mm=[x, y, z]``
        (fixed frame), ``move_to`` with ``psi_deg``, ``theta_deg`` and
        optionally ``left_tip_mm``, ``right_tip_mm``. For example
        ``c.command("look_at", point_mm=[20, 30, -600])``.

        Raises:
            LiveError: when the server refuses the message itself (an
            unknown command: its error text), or no acknowledgement comes.
        """
        self.subscribe([ACK_TOPIC])
        self._command_id = getattr(self, "_command_id", 0) + 1
        ident = self._command_id
        errors = len([s for s in self.statuses if s[0] == 2])
        self.publish(COMMAND_TOPIC, {**goal, "command": name, "id": ident})
        end = time.monotonic() + (self.timeout_s if timeout_s is None else timeout_s)
        while time.monotonic() < end:
            for k, (t, _, msg) in enumerate(self._pending):
                if t == ACK_TOPIC and msg.get("id") == ident:
                    del self._pending[k]
                    return msg
            new_errors = [m for lvl, m in self.statuses if lvl == 2][errors:]
            if any(COMMAND_TOPIC in m for m in new_errors):
                raise LiveError(new_errors[-1])
            self._read(0.05)
        raise LiveError(f"{name}: no acknowledgement within the time limit")
