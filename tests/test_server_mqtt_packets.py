"""The MQTT bridge's own reading of the broker's stream (server/mqtt.py): packets cut
across any recv boundary, QoS 0 PUBLISH taken as (topic, payload), every other packet
handed on whole and in order, malformed bytes handed on for paho to refuse."""

from __future__ import annotations

import pytest

from server.mqtt import PacketError, PacketReader, _PahoSocket, next_packet, publish_parts


def _length(n: int) -> bytes:
    out = bytearray()
    while True:
        byte, n = n & 0x7F, n >> 7
        out.append(byte | (0x80 if n else 0))
        if not n:
            return bytes(out)


def publish(topic: str, payload: bytes, *, qos: int = 0, retain: bool = False) -> bytes:
    name = topic.encode()
    body = len(name).to_bytes(2, "big") + name + (b"\x00\x07" if qos else b"") + payload
    return bytes([0x30 | qos << 1 | int(retain)]) + _length(len(body)) + body


SUBACK = b"\x90\x03\x00\x01\x00"
PUBACK = b"\x40\x02\x00\x05"
PINGRESP = b"\xd0\x00"


def test_remaining_lengths_of_one_to_four_bytes() -> None:
    for n in (0, 127, 128, 16_383, 16_384, 2_097_151, 2_097_152):
        packet = b"\x30" + _length(n) + bytes(n)
        assert next_packet(packet, 0) == (0x30, len(packet) - n, len(packet))
        if n:
            assert next_packet(packet[:-1], 0) is None
    with pytest.raises(PacketError, match="4 bytes"):
        next_packet(b"\x30\xff\xff\xff\xff\x01", 0)


def test_publish_parts_and_a_topic_past_the_packet() -> None:
    packet = publish("ednc/m1/temperature/spindle", b"21.5")
    _, start, end = next_packet(packet, 0) or (0, 0, 0)
    assert publish_parts(packet, start, end) == (b"ednc/m1/temperature/spindle", b"21.5")
    with pytest.raises(PacketError, match="past the packet"):
        publish_parts(b"\x00\x09ab", 0, 4)
    with pytest.raises(PacketError, match="shorter"):
        publish_parts(b"\x00", 0, 1)


def test_a_stream_cut_anywhere_gives_the_same_packets_in_order() -> None:
    stream = [publish("p/a/temperature/s", b"20.5"), SUBACK,
              publish("p/b/temperature/s", b'{"celsius": 21}', retain=True),
              publish("p/c/temperature/s", b"22", qos=1), PUBACK,
              publish("p/d/temperature/s", b"x" * 300), PINGRESP]
    data = b"".join(stream)
    want: list[tuple[bytes, bytes] | bytes] = [
        (b"p/a/temperature/s", b"20.5"), SUBACK,
        (b"p/b/temperature/s", b'{"celsius": 21}'),
        stream[3],  # QoS 1: paho's, it acknowledges it
        PUBACK, (b"p/d/temperature/s", b"x" * 300), PINGRESP]
    for cut in range(1, len(data)):
        reader = PacketReader()
        got = list(reader.feed(data[:cut])) + list(reader.feed(data[cut:]))
        assert got == want, cut
        assert reader.waiting == 0
    reader = PacketReader()  # one byte per recv
    assert [item for k in range(len(data)) for item in reader.feed(data[k:k + 1])] == want


def test_an_incomplete_packet_waits_and_malformed_bytes_go_on_whole() -> None:
    reader = PacketReader()
    first = publish("p/a/temperature/s", b"20")
    assert list(reader.feed(first + first[:5])) == [(b"p/a/temperature/s", b"20")]
    assert reader.waiting == 5
    bad = b"\x30\xff\xff\xff\xff\x01junk"
    assert list(reader.feed(first[5:] + bad)) == [(b"p/a/temperature/s", b"20"), bad]
    assert reader.waiting == 0
    # a PUBLISH whose topic length runs past it is handed on as it is
    broken = b"\x30\x04\x00\x09ab"
    assert list(PacketReader().feed(broken)) == [broken]


def test_a_consumer_that_stops_early_keeps_what_it_did_not_take() -> None:
    reader = PacketReader()
    data = SUBACK + PUBACK + PINGRESP
    items = reader.feed(data)
    assert next(items) == SUBACK
    items.close()  # the connection ended while handing SUBACK on
    assert reader.waiting == len(PUBACK + PINGRESP)


class _Sock:
    def __init__(self) -> None:
        self.sent: list[bytes] = []

    def send(self, data: bytes) -> int:
        self.sent.append(bytes(data))
        return len(data)

    def fileno(self) -> int:
        return 42


def test_paho_reads_what_it_is_handed_then_the_end() -> None:
    real = _Sock()
    stand_in = _PahoSocket(real)
    with pytest.raises(BlockingIOError):
        stand_in.recv(1)
    assert not stand_in.unread
    stand_in.push(SUBACK)
    assert stand_in.unread
    assert stand_in.recv(1) == SUBACK[:1] and stand_in.recv(100) == SUBACK[1:]
    assert stand_in.send(b"ping") == 4 and real.sent == [b"ping"]
    assert stand_in.fileno() == 42  # everything else is the real socket's
    stand_in.end(None)
    assert stand_in.unread and stand_in.recv(1) == b""
    broken = _PahoSocket(real)
    broken.end(ConnectionResetError("reset"))
    with pytest.raises(ConnectionResetError):
        broken.recv(1)
