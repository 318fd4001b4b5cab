"""Whole sessions: an in-memory center/machine pair through authentication, a chunked map
push and its ack, telemetry, heartbeat and release; then the same over a real TCP socket
on port 0 (the only place the protocol tests touch a socket)."""

from __future__ import annotations

import socket
import threading

import pytest

from protocol import (
    CONNECTION_CLOSED,
    NEED_DATA,
    AuthResponse,
    AxisReading,
    Challenge,
    Connection,
    Error,
    ErrorCode,
    Heartbeat,
    HeartbeatReply,
    Hello,
    MapAccepted,
    MapAck,
    MapAssembler,
    MapBegin,
    MapChunk,
    MapEnd,
    MapReject,
    Message,
    Reject,
    ReleaseCompensation,
    Released,
    Role,
    SensorReading,
    Sentinel,
    State,
    Telemetry,
    Welcome,
    compute_mac,
    encode_map,
    new_nonce,
    split_into_chunks,
    verify_mac,
)
from tests.support.protocol import HELLO, SECRET, sample_map


class Machine:
    """A minimal machine-side driver: what a PLC program does, event by event."""

    def __init__(self, secret: bytes) -> None:
        self.conn = Connection(Role.MACHINE)
        self.secret = secret
        self.assembler = MapAssembler(HELLO.name, HELLO.map_formats)
        self.applied: MapAccepted | None = None

    def react(self, event: Message | Sentinel) -> list[Message]:
        match event:
            case Challenge(nonce=nonce):
                return [AuthResponse(compute_mac(self.secret, nonce, HELLO.name))]
            case Welcome():
                return [self.telemetry()]
            case MapBegin() | MapChunk() | MapEnd():
                result = self.assembler.feed(event)
                if result is None:
                    return []
                if isinstance(result, MapAccepted):
                    self.applied = result  # the swap: only a whole, verified map
                    self.assembler.applied_version = result.version
                    return [result.ack(), self.telemetry()]
                return [result.message()]
            case Heartbeat(token=token):
                return [HeartbeatReply(token)]
            case ReleaseCompensation():
                self.applied = None
                self.assembler.applied_version = 0
                return [Released()]
            case _:
                return []

    def telemetry(self) -> Telemetry:
        version = self.applied.version if self.applied else 0
        return Telemetry(1_700_000_000_000, "compensating" if version else "idle", version,
                         (AxisReading("X", 100.0, 0.002),), (SensorReading("bed", 20.5),))


class Center:
    """A minimal center-side driver checking the machine's secret."""

    def __init__(self, secrets: dict[str, bytes]) -> None:
        self.conn = Connection(Role.CENTER)
        self.secrets = secrets
        self.nonce = new_nonce()
        self.hello: Hello | None = None
        self.seen: list[Message] = []

    def react(self, event: Message | Sentinel) -> list[Message]:
        if not isinstance(event, Sentinel):
            self.seen.append(event)
        match event:
            case Hello(name=name) if name not in self.secrets:
                return [Reject(ErrorCode.UNKNOWN_MACHINE, f"no machine named {name}")]
            case Hello():
                self.hello = event
                return [Challenge(self.nonce)]
            case AuthResponse(mac=mac):
                assert self.hello is not None
                if not verify_mac(self.secrets[self.hello.name], self.nonce, self.hello.name,
                                  mac):
                    return [Reject(ErrorCode.AUTH_FAILED, "wrong HMAC")]
                return [Welcome(5000, 1000)]
            case _:
                return []


def pump(center: Center, machine: Machine, bytewise: bool) -> None:
    """Deliver frames both ways until both ends wait for data."""
    busy = True
    while busy:
        busy = False
        for me, peer in ((center, machine), (machine, center)):
            while (event := me.conn.next_event()) is not NEED_DATA:
                busy = True
                for reply in me.react(event):
                    wire = me.conn.send(reply)
                    if bytewise:
                        for i in range(len(wire)):
                            peer.conn.receive_data(wire[i:i + 1])
                    else:
                        peer.conn.receive_data(wire)


def last(center: Center) -> Message:
    """The latest message the center received."""
    return center.seen[-1]


def send(sender: Center | Machine, receiver: Center | Machine, msg: Message) -> None:
    receiver.conn.receive_data(sender.conn.send(msg))


@pytest.mark.parametrize("bytewise", [False, True], ids=["whole", "byte-by-byte"])
def test_in_memory_session(bytewise: bool) -> None:
    center, machine = Center({"vmc-01": SECRET}), Machine(SECRET)
    send(machine, center, HELLO)
    pump(center, machine, bytewise)
    assert center.conn.session is machine.conn.session is State.READY
    first = center.seen[-1]
    assert isinstance(first, Telemetry) and first.map_version == 0

    payload = encode_map(sample_map(version=7))
    for msg in split_into_chunks(payload, 7, chunk_size=700):
        send(center, machine, msg)
    pump(center, machine, bytewise)
    assert machine.applied is not None and machine.applied.payload == sample_map(version=7)
    assert center.seen[-2:] == [MapAck(7), machine.telemetry()]
    assert machine.telemetry().map_version == 7

    send(center, machine, Heartbeat(42))
    pump(center, machine, bytewise)
    assert last(center) == HeartbeatReply(42)

    send(center, machine, ReleaseCompensation(2000, "thermal model out of date"))
    pump(center, machine, bytewise)
    assert last(center) == Released()
    assert machine.telemetry().map_version == 0  # released: no map applied

    send(center, machine, Error(ErrorCode.SHUTDOWN, "center stopping"))
    assert machine.conn.next_event() == Error(ErrorCode.SHUTDOWN, "center stopping")
    assert {center.conn.session, machine.conn.session} == {State.CLOSED}


def test_corrupt_map_keeps_the_old_one() -> None:
    center, machine = Center({"vmc-01": SECRET}), Machine(SECRET)
    send(machine, center, HELLO)
    pump(center, machine, False)
    for msg in split_into_chunks(encode_map(sample_map(version=7)), 7, 4000):
        send(center, machine, msg)
    pump(center, machine, False)
    msgs = split_into_chunks(encode_map(sample_map(version=8)), 8, 4000)
    chunk = msgs[1]
    assert isinstance(chunk, MapChunk)
    msgs[1] = MapChunk(8, 0, bytes([chunk.data[0] ^ 1]) + chunk.data[1:])
    for msg in msgs:
        send(center, machine, msg)
    pump(center, machine, False)
    assert machine.applied is not None and machine.applied.version == 7
    reject = center.seen[-1]
    assert isinstance(reject, MapReject) and "SHA-256" in reject.text


@pytest.mark.parametrize(("secrets", "code"), [
    ({"vmc-01": b"another-secret-of-16+bytes"}, ErrorCode.AUTH_FAILED),
    ({"vmc-02": SECRET}, ErrorCode.UNKNOWN_MACHINE),
])
def test_wrong_secret_or_unknown_machine_is_rejected(secrets: dict[str, bytes],
                                                     code: ErrorCode) -> None:
    center, machine = Center(secrets), Machine(SECRET)
    send(machine, center, HELLO)
    pump(center, machine, False)
    assert center.conn.session is machine.conn.session is State.CLOSED
    assert not any(isinstance(m, Telemetry) for m in center.seen)
    assert machine.conn.next_event() is NEED_DATA


def test_auth_binds_nonce_and_name() -> None:
    nonce = bytes(range(32))
    mac = compute_mac(SECRET, nonce, "vmc-01")
    assert verify_mac(SECRET, nonce, "vmc-01", mac)
    assert not verify_mac(SECRET, nonce, "vmc-02", mac)
    assert not verify_mac(SECRET, bytes(32), "vmc-01", mac)
    assert new_nonce() != new_nonce()
    with pytest.raises(ValueError, match="machine secret is 5 bytes, at least 16 needed"):
        compute_mac(b"short", nonce, "vmc-01")


def _recv_event(conn: Connection, sock: socket.socket) -> Message | Sentinel:
    while (event := conn.next_event()) is NEED_DATA:
        conn.receive_data(sock.recv(65536))
    return event


def _machine_over_tcp(port: int, outcome: list[object]) -> None:
    machine = Machine(SECRET)
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
            sock.sendall(machine.conn.send(HELLO))
            while True:
                event = _recv_event(machine.conn, sock)
                if event is CONNECTION_CLOSED or isinstance(event, Error):
                    outcome.append(event)
                    break
                for reply in machine.react(event):
                    sock.sendall(machine.conn.send(reply))
        outcome.append(machine.applied)
    except Exception as exc:  # reported to the test thread, which fails on it
        outcome.append(exc)


def test_real_socket_on_port_0() -> None:
    outcome: list[object] = []
    with socket.create_server(("127.0.0.1", 0)) as server:
        server.settimeout(10)  # only guards against a hang; no assertion depends on time
        port = server.getsockname()[1]
        thread = threading.Thread(target=_machine_over_tcp, args=(port, outcome))
        thread.start()
        sock, _ = server.accept()
        with sock:
            sock.settimeout(10)
            center = Center({"vmc-01": SECRET})

            def step() -> Message | Sentinel:
                event = _recv_event(center.conn, sock)
                for reply in center.react(event):
                    sock.sendall(center.conn.send(reply))
                return event

            assert step() == HELLO
            assert isinstance(step(), AuthResponse)
            assert isinstance(step(), Telemetry)
            payload = encode_map(sample_map(version=3))
            sock.sendall(b"".join(center.conn.send(m)
                                  for m in split_into_chunks(payload, 3, 1024)))
            assert step() == MapAck(3)
            telemetry = step()
            assert isinstance(telemetry, Telemetry) and telemetry.map_version == 3
            sock.sendall(center.conn.send(Error(ErrorCode.SHUTDOWN, "done")))
        thread.join(10)
    assert not thread.is_alive()
    assert outcome[0] == Error(ErrorCode.SHUTDOWN, "done")
    applied = outcome[1]
    assert isinstance(applied, MapAccepted) and applied.payload == sample_map(version=3)
