"""Temperatures (0x25, center → machine): one literal frame both ways, fed whole and one
byte at a time, the state rules (5 and 10), field limits, and one real socket on port 0."""

from __future__ import annotations

import math
import socket
import struct
import threading
from pathlib import Path

import pytest

from protocol import (
    NEED_DATA,
    Channel,
    Connection,
    LocalProtocolError,
    MapBegin,
    MapChunk,
    Message,
    RemoteProtocolError,
    State,
    Telemetry,
    TemperatureReading,
    Temperatures,
)
from protocol.codec import decode_payload, encode_payload
from protocol.codes import MessageType
from tests.support.protocol_pair import Raw, pair

MSG = Temperatures(1_700_000_000_000, (TemperatureReading("spindle", 21.25, 150),
                                       TemperatureReading("air", 20.5)))

# The worked example of protocol/README.md section 3 (Temperatures), sent as the center's
# fifth frame (Challenge, Welcome, MapBegin, MapChunk went before: sequence 4).
FRAME = bytes.fromhex(
    "45444e43 01 25 0000 00000004 0000002d"          # EDNC, v1, Temperatures, seq 4, 45 B
    "0000018bcfe56800"                               # timestamp_ms 1 700 000 000 000
    "02"                                             # 2 sensors
    "07 7370696e646c65 4035400000000000 00000096"    # "spindle" 21.25 °C, 150 ms old
    "03 616972 4034800000000000 00000000"            # "air" 20.5 °C, fresh
    "2096b00f"                                       # CRC-32
)


def _ready_after_two_frames() -> tuple[Connection, Connection]:
    """(center, machine) READY, with a map push open so the center has sent 4 frames."""
    center, machine = pair("ready")
    for msg in (MapBegin(1, 10, 1, bytes(32)), MapChunk(1, 0, bytes(10))):
        machine.receive_data(center.send(msg))
        assert isinstance(machine.next_event(), type(msg))
    return center, machine


def test_payload_is_a_few_dozen_bytes() -> None:
    payload = encode_payload(MSG)
    assert len(payload) == 45 == len(FRAME) - 20
    assert decode_payload(MessageType.TEMPERATURES, payload) == MSG


@pytest.mark.parametrize("bytewise", [False, True])
def test_literal_frame_both_ways(bytewise: bool) -> None:
    center, machine = _ready_after_two_frames()
    assert center.send(MSG) == FRAME
    chunks = [FRAME[i:i + 1] for i in range(len(FRAME))] if bytewise else [FRAME]
    for i, chunk in enumerate(chunks):
        machine.receive_data(chunk)
        event = machine.next_event()
        if i < len(chunks) - 1:
            assert event is NEED_DATA
    assert event == MSG
    assert machine.next_event() is NEED_DATA


def test_crosses_a_map_push_and_moves_no_channel() -> None:  # rules 5 and 10
    center, machine = _ready_after_two_frames()
    before = center.states
    for _ in range(3):
        machine.receive_data(center.send(MSG))
        assert machine.next_event() == MSG
    assert center.states == before == machine.states
    assert before[Channel.MAP] is State.MAP_SENDING
    center.receive_data(machine.send(Telemetry(1, "run", 0)))  # the machine talks on
    assert isinstance(center.next_event(), Telemetry)


def test_only_the_center_sends_it_and_only_when_ready() -> None:  # rules 1, 4, 5
    center, machine = pair("ready")
    with pytest.raises(LocalProtocolError, match="only the center sends it"):
        machine.send(MSG)
    center, machine = pair("auth")
    with pytest.raises(LocalProtocolError, match="'await welcome'; allowed in 'ready'"):
        center.send(MSG)
    raw = Raw()
    _, machine = pair("start")
    machine.receive_data(raw(MSG))
    with pytest.raises(RemoteProtocolError, match="'await hello'; allowed in 'ready'"):
        machine.next_event()


def _payload(*sensors: tuple[str, float, int], count: int | None = None) -> bytes:
    out = bytearray((1_700_000_000_000).to_bytes(8, "big"))
    out.append(len(sensors) if count is None else count)
    for name, celsius, age in sensors:
        raw = name.encode()
        out += bytes([len(raw)]) + raw
        out += struct.pack(">d", celsius) + age.to_bytes(4, "big")
    return bytes(out)


@pytest.mark.parametrize(("payload", "why"), [
    (_payload(), "1 to 32 allowed"),
    (_payload(("spindle", math.nan, 0)), "must be finite"),
    (_payload(("spindle", math.inf, 0)), "must be finite"),
    (_payload(("spindle", -300.0, 0)), "below absolute zero"),
    (_payload(("spindle", 20.0, 0), ("spindle", 21.0, 0)), "names 'spindle' twice"),
    (_payload(("", 20.0, 0)), "must not be empty"),
    (_payload(("spindle", 20.0, 0), count=2), "sensor 1 name length needs 1 bytes"),
    (_payload(("spindle", 20.0, 0)) + b"\x00", "1 unexpected bytes"),
])
def test_bad_payloads_are_remote_errors_naming_the_field(payload: bytes, why: str) -> None:
    with pytest.raises(RemoteProtocolError, match=f"bad TEMPERATURES payload: .*{why}"):
        decode_payload(MessageType.TEMPERATURES, payload)


@pytest.mark.parametrize(("build", "why"), [
    (lambda: Temperatures(0, ()), "1 to 32 allowed"),
    (lambda: Temperatures(0, tuple(TemperatureReading(f"s{i}", 20.0) for i in range(33))),
     "33 sensors"),
    (lambda: Temperatures(-1, (TemperatureReading("a", 20.0),)), "timestamp_ms"),
    (lambda: TemperatureReading("a" * 17, 20.0), "at most 16"),
    (lambda: TemperatureReading("a", 20.0, 2**32), "age_ms must be in"),
    (lambda: Temperatures(0, [TemperatureReading("a", 20.0)]),  # type: ignore[arg-type]
     "must be a tuple"),
])
def test_invalid_messages_cannot_be_built(build: object, why: str) -> None:
    assert callable(build)
    with pytest.raises(ValueError, match=why):
        build()


def test_over_a_real_socket_on_port_0() -> None:
    center, machine = _ready_after_two_frames()
    with socket.create_server(("127.0.0.1", 0)) as server:
        port = server.getsockname()[1]
        got: list[Message] = []

        def serve() -> None:
            conn, _ = server.accept()
            with conn:
                while len(got) < 2:
                    data = conn.recv(7)  # small reads: frames arrive in pieces
                    if not data:
                        break
                    machine.receive_data(data)
                    while isinstance(event := machine.next_event(), Temperatures):
                        got.append(event)

        thread = threading.Thread(target=serve)
        thread.start()
        second = Temperatures(1_700_000_000_100, (TemperatureReading("spindle", 21.5),))
        with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
            sock.sendall(center.send(MSG) + center.send(second))
        thread.join(10)
    assert got == [MSG, second]


def test_readme_example_is_the_real_frame() -> None:
    readme = (Path(__file__).resolve().parent.parent / "protocol" / "README.md").read_text()
    section = readme.split("### 0x25 Temperatures")[1].split("\n## ")[0]
    dump = [line.split()[1:] for line in section.splitlines()
            if line.startswith("    00")]
    assert bytes.fromhex("".join(b for row in dump for b in row)) == FRAME
