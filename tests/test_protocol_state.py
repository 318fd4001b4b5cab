"""The state table's rules, for both roles, sending (LocalProtocolError) and receiving
(RemoteProtocolError), and the per-direction sequence numbers."""

from __future__ import annotations

import re

import pytest

from protocol import (
    NEED_DATA,
    Channel,
    Connection,
    Error,
    ErrorCode,
    Heartbeat,
    HeartbeatReply,
    LocalProtocolError,
    MapAck,
    MapBegin,
    MapChunk,
    MapEnd,
    MapReject,
    MapRejectReason,
    Message,
    Reject,
    ReleaseCompensation,
    Released,
    RemoteProtocolError,
    Role,
    State,
    Telemetry,
)
from protocol.codec import encode_payload
from protocol.messages import TYPE_OF
from protocol.state import CHANNEL_OF, INITIAL, TRANSITIONS
from tests.support.protocol import HELLO, deliver, frame
from tests.support.protocol_pair import AUTH, CHALLENGE, WELCOME, Raw, pair

TELEMETRY = Telemetry(1, "idle", 0)
BEGIN = MapBegin(3, 10, 1, bytes(32))
CHUNK = MapChunk(3, 0, bytes(10))
END = MapEnd(3)


def test_table_entries_stay_in_one_channel_and_cover_every_message() -> None:
    for (role, kind), moves in TRANSITIONS.items():
        channels = {CHANNEL_OF[s] for s in (*moves, *moves.values())}
        assert len(channels) == 1, (role, kind)
    assert {kind for _, kind in TRANSITIONS} == set(TYPE_OF)
    senders = {kind: {r for r, k in TRANSITIONS if k is kind} for kind in TYPE_OF}
    assert {k for k, roles in senders.items() if len(roles) == 2} == {Error}  # rule 1
    assert set(INITIAL.values()) == {State.AWAIT_HELLO, State.MAP_IDLE, State.RELEASE_IDLE}


def test_handshake_states_let_exactly_one_role_speak() -> None:  # rule 3
    for state in (State.AWAIT_HELLO, State.AWAIT_CHALLENGE, State.AWAIT_AUTH,
                  State.AWAIT_VERDICT):
        speakers = {role for (role, kind), moves in TRANSITIONS.items()
                    if state in moves and kind is not Error}
        assert len(speakers) == 1, state


# (who is in which handshake stage, sender role, message, rule text in the error)
VIOLATIONS: list[tuple[str, Role, Message, str]] = [
    ("start", Role.CENTER, CHALLENGE, "in state 'await hello'"),             # rule 2
    ("start", Role.MACHINE, AUTH, "in state 'await hello'"),                 # rule 2
    ("start", Role.CENTER, WELCOME, "in state 'await hello'"),               # rule 4
    ("hello", Role.MACHINE, HELLO, "in state 'await challenge'"),            # rule 3
    ("hello", Role.CENTER, WELCOME, "in state 'await challenge'"),           # rule 3/4
    ("challenge", Role.MACHINE, TELEMETRY, "'await auth response'; allowed in 'ready'"),
    ("challenge", Role.CENTER, BEGIN, "before Welcome"),                     # rule 4/5
    ("auth", Role.CENTER, Heartbeat(1), "'await welcome'; allowed in 'ready'"),  # rule 5
    ("auth", Role.CENTER, ReleaseCompensation(0), "before Welcome"),         # rule 5
    ("ready", Role.CENTER, Reject(ErrorCode.AUTH_FAILED), "in state 'ready'"),
    ("ready", Role.CENTER, WELCOME, "in state 'ready'"),
    ("ready", Role.CENTER, CHUNK, "in state 'no map transfer'"),             # rule 6
    ("ready", Role.CENTER, END, "in state 'no map transfer'"),               # rule 6
    ("ready", Role.MACHINE, MapAck(3), "in state 'no map transfer'"),        # rule 6
    ("ready", Role.MACHINE, Released(), "in state 'no release pending'"),    # rule 7
    ("ready", Role.MACHINE, Heartbeat(1), "only the center sends it (rule 1)"),
    ("ready", Role.CENTER, TELEMETRY, "only the machine sends it (rule 1)"),
    ("ready", Role.CENTER, HeartbeatReply(1), "only the machine sends it (rule 1)"),
]


@pytest.mark.parametrize(("stage", "sender", "msg", "text"), VIOLATIONS)
def test_local_violation(stage: str, sender: Role, msg: Message, text: str) -> None:
    center, machine = pair(stage)
    conn = center if sender is Role.CENTER else machine
    before = conn.states
    with pytest.raises(LocalProtocolError, match=f"{sender.value} may not send "
                                                 f"{type(msg).__name__}.*{re.escape(text)}"):
        conn.send(msg)
    assert conn.states == before
    # nothing was consumed: the next legal message still gets the next sequence number
    other = machine if conn is center else center
    deliver(conn, other, Error(ErrorCode.SHUTDOWN))
    assert other.session is State.CLOSED


@pytest.mark.parametrize(("stage", "sender", "msg", "text"), VIOLATIONS)
def test_remote_violation(stage: str, sender: Role, msg: Message, text: str) -> None:
    center, machine = pair(stage)
    receiver = machine if sender is Role.CENTER else center
    # rebuild the peer's sequence count: frames it already sent in the handshake
    sent = {"start": 0, "hello": 1, "challenge": 1, "auth": 2, "ready": 2}[stage]
    if sender is Role.CENTER:
        sent = {"start": 0, "hello": 0, "challenge": 1, "auth": 1, "ready": 2}[stage]
    raw = Raw()
    raw.seq = sent
    receiver.receive_data(raw(msg))
    with pytest.raises(RemoteProtocolError, match=f"{sender.value} may not send "
                                                  f"{type(msg).__name__}.*{re.escape(text)}"):
        receiver.next_event()


def test_map_channel_is_one_push_at_a_time() -> None:  # rule 6
    center, machine = pair()
    for m in (BEGIN, CHUNK, CHUNK, END):
        deliver(center, machine, m)
    assert center.states[Channel.MAP] is State.MAP_VERIFYING
    with pytest.raises(LocalProtocolError, match="in state 'map awaiting ack'"):
        center.send(MapBegin(4, 10, 1, bytes(32)))
    deliver(machine, center, MapReject(3, MapRejectReason.CHECKSUM_MISMATCH))
    assert center.states[Channel.MAP] is machine.states[Channel.MAP] is State.MAP_IDLE
    deliver(center, machine, MapBegin(4, 10, 1, bytes(32)))


def test_release_channel_one_outstanding() -> None:  # rule 7
    center, machine = pair()
    deliver(center, machine, ReleaseCompensation(1000, "operator"))
    with pytest.raises(LocalProtocolError, match="in state 'release pending'"):
        center.send(ReleaseCompensation(1000))
    deliver(machine, center, Released())
    assert center.states[Channel.RELEASE] is State.RELEASE_IDLE
    with pytest.raises(LocalProtocolError, match="Released in state 'no release pending'"):
        machine.send(Released())


@pytest.mark.parametrize("stage", ["hello", "auth"])
def test_reject_closes_session(stage: str) -> None:  # rule 8
    center, machine = pair(stage)
    deliver(center, machine, Reject(ErrorCode.UNKNOWN_MACHINE, "who?"))
    assert center.session is machine.session is State.CLOSED
    with pytest.raises(LocalProtocolError, match="the session is closed \\(rule 8\\)"):
        machine.send(Error(ErrorCode.SHUTDOWN))
    raw = Raw()
    raw.seq = 1 if stage == "hello" else 2
    center.receive_data(raw(AUTH))
    with pytest.raises(RemoteProtocolError, match="the session is closed"):
        center.next_event()


@pytest.mark.parametrize("sender", [Role.CENTER, Role.MACHINE])
@pytest.mark.parametrize("stage", ["start", "hello", "challenge", "auth", "ready"])
def test_error_closes_from_any_open_state(stage: str, sender: Role) -> None:  # rule 8
    center, machine = pair(stage)
    a, b = (center, machine) if sender is Role.CENTER else (machine, center)
    deliver(a, b, Error(ErrorCode.TIMEOUT, "too slow"))
    assert a.session is b.session is State.CLOSED


def test_crossing_frames_keep_both_ends_in_step() -> None:  # rule 9
    center, machine = pair()
    to_machine = center.send(BEGIN) + center.send(CHUNK)
    to_center = machine.send(TELEMETRY) + machine.send(HeartbeatReply(9))  # unasked: allowed
    machine.receive_data(to_machine)
    center.receive_data(to_center)
    assert [machine.next_event(), machine.next_event()] == [BEGIN, CHUNK]
    assert [center.next_event(), center.next_event()] == [TELEMETRY, HeartbeatReply(9)]
    deliver(center, machine, END)
    deliver(machine, center, MapAck(3))
    assert center.states == machine.states
    assert center.states[Channel.MAP] is State.MAP_IDLE


def test_sequence_numbers_count_per_direction() -> None:
    center, machine = pair()
    w1 = machine.send(TELEMETRY)
    w2 = machine.send(TELEMETRY)
    assert int.from_bytes(w1[8:12], "big") == 2 and int.from_bytes(w2[8:12], "big") == 3
    assert int.from_bytes(center.send(Heartbeat(1))[8:12], "big") == 2


@pytest.mark.parametrize(("seq", "text"), [(3, "skips ahead of the expected 2"),
                                           (1, "repeats the expected 2")])
def test_sequence_gap_or_repeat_is_remote_error(seq: int, text: str) -> None:
    center, _ = pair()
    center.receive_data(frame(0x20, seq, encode_payload(TELEMETRY)))
    with pytest.raises(RemoteProtocolError, match=f"TELEMETRY frame has sequence number "
                                                  f"{seq}, which {text}"):
        center.next_event()


def test_duplicated_frame_is_caught() -> None:
    center, machine = pair()
    wire = machine.send(TELEMETRY)
    center.receive_data(wire + wire)
    assert center.next_event() == TELEMETRY
    with pytest.raises(RemoteProtocolError, match="repeats"):
        center.next_event()


def test_not_a_message_cannot_be_sent() -> None:
    with pytest.raises(LocalProtocolError, match="str is not a protocol message"):
        Connection(Role.MACHINE).send("Hello")  # type: ignore[arg-type]


def test_need_data_before_anything_arrives() -> None:
    assert Connection(Role.CENTER).next_event() is NEED_DATA
