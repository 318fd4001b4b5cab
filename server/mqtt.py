"""The MQTT bridge (aiomqtt 2.x): machine temperatures in, link status and events out.

Topics (``<prefix>`` is ``EDNC_MQTT_TOPIC_PREFIX``, ``ednc`` by default; see README.md):

* subscribes ``<prefix>/+/temperature/+``: ``<prefix>/<machine>/temperature/<sensor>``
  with a number in °C as text (``21.43``) or JSON ``{"celsius": 21.43, "time": ...}``
  (``time``: ISO 8601 or seconds since the epoch; ``timestamp_ms`` also accepted). The
  sensor ``spindle`` is the model column ``T_spindle_C``. Bad payloads are counted
  (``ednc_mqtt_bad_payloads``) and logged, never fatal; a reading that parses goes to the
  board, where the intake's screen (:mod:`server.intake`: range, known sensor, rate) may
  still refuse it, and from there to the time series and to the machine;
* publishes ``<prefix>/<machine>/status``, retained JSON: connected, map versions sent and
  applied, last seen, the temperatures the center holds (with age and staleness);
* publishes ``<prefix>/events``: JSON of every link event (refusals, connections, pushes,
  applied maps, rejections).

When the broker goes away the bridge keeps the last temperatures, marks those that came by
MQTT stale, and reconnects with jittered, capped exponential backoff; statuses changed
meanwhile are published on return, events of the outage are dropped beyond a bounded queue.
"""

from __future__ import annotations

import asyncio
import contextlib
import datetime as dt
import json
import logging
import math
import random
import socket
import ssl
import time
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass, field
from types import TracebackType
from typing import Any, Final

import aiomqtt
import paho.mqtt.client as mqtt_client
from prometheus_client import Counter

from protocol.backoff import Backoff
from server.background import Background
from server.center import Center
from server.db import maps as map_repo
from server.events import EventKind
from server.feed import Feed, Notice
from server.temperatures import TemperatureBoard, valid_sensor
from volumetric.plausible.temperatures import temperature_problem
from volumetric.plausible.times import stamp_problem

log = logging.getLogger(__name__)


READ_BYTES: Final = 65536
"""Bytes read from the broker's socket in one event-loop wake-up at most: about 900
temperature messages (nearly 2 s of a 500/s plant), so that a backlog is taken in few
loop turns and the machine sessions still get theirs between them."""

_PUBLISH_QOS0_MASK: Final = 0xF6
_PUBLISH_QOS0: Final = 0x30
"""First byte of an MQTT PUBLISH (type 3) with QoS 0, under the mask that drops the DUP
and RETAIN flags."""

PUBLISH_TIMEOUT_S: Final = 60.0
"""How long a status or event publish may wait for the broker's PUBACK. aiomqtt's
default (the client's 5 s) turned a broker or a center busy for 5 s into a lost
connection, and with it the temperatures published meanwhile (the subscription is not
persistent); a broker that is really gone is found by the keepalive and the receive loop,
which ends the publishing with it."""

EVENT_BACKLOG: Final = 1000
"""Events kept for publishing while the broker is away (oldest dropped first)."""


class PayloadError(ValueError):
    """A temperature message that cannot be read; the text says why."""


class PacketError(ValueError):
    """Bytes from the broker that are no MQTT packet (left to paho, which disconnects)."""


def next_packet(buf: bytes | bytearray, pos: int) -> tuple[int, int, int] | None:
    """The MQTT packet starting at ``buf[pos]``: (first byte, body start, body end), body
    being what follows the fixed header; None while it is not complete.

    Raises
    ------
    PacketError
        The remaining length takes more than the 4 bytes MQTT allows.
    """
    n = len(buf)
    i = pos + 1
    length = 0
    shift = 0
    while True:
        if i >= n:
            return None
        byte = buf[i]
        i += 1
        length |= (byte & 0x7F) << shift
        if not byte & 0x80:
            break
        shift += 7
        if shift > 21:
            raise PacketError("remaining length longer than 4 bytes")
    end = i + length
    return (buf[pos], i, end) if end <= n else None


def publish_parts(buf: bytes | bytearray, start: int, end: int) -> tuple[bytes, bytes]:
    """(topic, payload) of a QoS 0 PUBLISH body ``buf[start:end]`` (MQTT 3.1.1: topic
    length u16 big-endian, topic, payload; no packet identifier at QoS 0).

    Raises
    ------
    PacketError
        The topic runs past the packet.
    """
    if end - start < 2:
        raise PacketError("PUBLISH shorter than its topic length")
    topic_end = start + 2 + (buf[start] << 8 | buf[start + 1])
    if topic_end > end:
        raise PacketError("PUBLISH topic runs past the packet")
    return bytes(buf[start + 2:topic_end]), bytes(buf[topic_end:end])


class PacketReader:
    """The broker's byte stream cut into MQTT 3.1.1 packets, across ``recv`` boundaries.

    :meth:`feed` yields, in stream order, each complete QoS 0 PUBLISH as ``(topic,
    payload)`` and every other packet (or bytes that are no packet) as its raw bytes, to
    be handed to paho; an incomplete packet waits for the next :meth:`feed`.
    """

    def __init__(self) -> None:
        self._buf = bytearray()

    def feed(self, data: bytes) -> Iterator[tuple[bytes, bytes] | bytes]:
        buf = self._buf
        buf += data
        pos, size = 0, len(buf)
        try:
            while pos < size:
                try:
                    found = next_packet(buf, pos)
                except PacketError:  # paho finds it malformed and disconnects
                    rest, pos = bytes(buf[pos:]), size
                    yield rest
                    return
                if found is None:
                    return
                first, start, end = found
                if first & _PUBLISH_QOS0_MASK == _PUBLISH_QOS0:
                    try:
                        parts: tuple[bytes, bytes] | bytes = publish_parts(buf, start, end)
                    except PacketError:
                        parts = bytes(buf[pos:end])
                else:
                    parts = bytes(buf[pos:end])
                pos = end
                yield parts
        finally:
            del buf[:pos]

    @property
    def waiting(self) -> int:
        """Bytes of an incomplete packet held for the next :meth:`feed`."""
        return len(self._buf)


class _PahoSocket:
    """What paho reads from once the bridge reads the broker's socket itself: the packets
    the bridge hands it (:meth:`push`), then the socket's end (:meth:`end`) when the
    broker goes; every other use (send, fileno, close) goes to the real socket."""

    def __init__(self, sock: Any) -> None:
        self.sock = sock
        self.data = bytearray()
        self.ended = False
        self.error: OSError | None = None

    def push(self, packet: bytes | bytearray) -> None:
        self.data += packet

    def end(self, error: OSError | None) -> None:
        self.ended, self.error = True, error

    @property
    def unread(self) -> bool:
        return bool(self.data) or self.ended

    def recv(self, size: int) -> bytes:
        if self.data:
            out = bytes(self.data[:size])
            del self.data[:size]
            return out
        if self.error is not None:
            raise self.error
        if self.ended:
            return b""  # paho's "connection lost"
        raise BlockingIOError

    def send(self, data: bytes | bytearray) -> int:
        return int(self.sock.send(data))

    def __getattr__(self, name: str) -> Any:
        return getattr(self.sock, name)


_QUICKACK: Final = getattr(socket, "TCP_QUICKACK", None)  # Linux only


def ack_at_once(sock: socket.socket) -> None:
    """Have the kernel acknowledge what ``sock`` receives at once, not up to 40 ms later.

    Linux delays an ACK when a connection looks interactive (it sent data shortly after
    receiving: the bridge's status publishes), hoping to carry the ACK on the next write.
    The broker, by default without ``TCP_NODELAY`` (Mosquitto's ``set_tcp_nodelay``),
    holds its next small segment until that ACK (Nagle): temperatures then arrive in
    bursts every 40-50 ms. ``TCP_QUICKACK`` is not sticky: the kernel may return to
    delayed ACKs, so it is set again after every read. Measured
    (``benchmarks/mqtt_to_map.py``, 1,000 machines, 500 temperatures/s): p99 44.5-49.8 ms
    -> 8.8-9.5 ms. Does nothing where the option does not exist.
    """
    if _QUICKACK is not None:
        with contextlib.suppress(OSError):
            sock.setsockopt(socket.IPPROTO_TCP, _QUICKACK, 1)


def parse_temperature(payload: bytes) -> tuple[float, float | None]:
    """(°C, time in s since the epoch or None) from a temperature message.

    Raises
    ------
    PayloadError
    """
    try:
        text = payload.decode("utf-8").strip()
    except UnicodeDecodeError:
        raise PayloadError("payload is not UTF-8") from None
    if not text:
        raise PayloadError("payload is empty")
    stamp: float | None = None
    if text.startswith("{"):
        try:
            body = json.loads(text)
        except json.JSONDecodeError as exc:
            raise PayloadError(f"payload is not valid JSON: {exc.msg}") from None
        if not isinstance(body, dict) or "celsius" not in body:
            raise PayloadError('JSON payload needs a "celsius" key')
        value = body["celsius"]
        stamp = _stamp(body)
    else:
        value = text
    if isinstance(value, bool):
        raise PayloadError(f"celsius must be a number, got {value!r}")
    try:
        celsius = float(value)
    except (TypeError, ValueError):
        raise PayloadError(f"celsius must be a number, got {str(value)[:40]!r}") from None
    # the limits every entry point shares, with the likely unit (293: kelvin; a time in
    # milliseconds): MQTT, REST and the CLI refuse alike, in the same words
    problem = temperature_problem(celsius, "celsius")
    if problem is not None:
        raise PayloadError(problem)
    if stamp is not None:
        late = stamp_problem(stamp, "timestamp_ms" if "timestamp_ms" in text else "time")
        if late is not None:
            raise PayloadError(late)
    return celsius, stamp


def _stamp(body: dict[str, Any]) -> float | None:
    if "timestamp_ms" in body:
        raw = body["timestamp_ms"]
        if isinstance(raw, int | float) and not isinstance(raw, bool) and math.isfinite(raw):
            return float(raw) / 1000.0
        raise PayloadError(f"timestamp_ms must be a number, got {raw!r}")
    raw = body.get("time")
    if raw is None:
        return None
    if isinstance(raw, int | float) and not isinstance(raw, bool) and math.isfinite(raw):
        return float(raw)
    if isinstance(raw, str):
        try:
            when = dt.datetime.fromisoformat(raw)
        except ValueError:
            raise PayloadError(f"time {raw[:40]!r} is not ISO 8601") from None
        if when.tzinfo is None:
            when = when.replace(tzinfo=dt.UTC)
        return when.timestamp()
    raise PayloadError(f"time must be ISO 8601 or seconds, got {raw!r}")


@dataclass
class _Status:
    connected: bool = False
    sent: int | None = None
    applied: int | None = None
    rejected: int | None = None
    seeded: bool = False


@dataclass
class BridgeStats:
    connects: int = 0
    received: int = 0
    bad_payloads: int = 0
    published: int = 0
    read_cpu_s: float = 0.0
    """CPU time of this thread in the bridge's reader (the ``recv``, cutting packets,
    paho's share for the packets that are not temperatures, :meth:`handle`, the intake
    and the Temperatures frames it writes), s: what the messages cost the event loop,
    without its other work."""
    last_error: str = ""
    bad_examples: deque[str] = field(default_factory=lambda: deque(maxlen=20))


async def _send(client: aiomqtt.Client, topic: str, payload: str, *, retain: bool) -> None:
    """Publish at QoS 1 and wait for the broker's PUBACK; a cancel is never lost.

    aiomqtt waits for the PUBACK with ``asyncio.wait_for``, which in Python 3.11 returns
    the result and drops a cancellation that arrives in the same loop turn as the PUBACK
    (the awaited future is already done). With a thousand statuses republished, PUBACKs
    arrive every turn: the bridge then went on waiting for work after its connection
    was cancelled, and held the shutdown (or, after a lost broker, its reconnect). A
    pending cancel request (``Task.cancelling``) is raised here instead. Only for a task
    that lives as long as one connection (the publisher): the connection loop's own count
    of cancel requests is not reliable across a lost broker's task group, and it checks the
    stop flag instead.
    """
    await client.publish(topic, payload, qos=1, retain=retain, timeout=PUBLISH_TIMEOUT_S)
    task = asyncio.current_task()
    if task is not None and task.cancelling():
        raise asyncio.CancelledError


class MqttBridge:
    """Temperatures from the broker, status and events to it; an async context manager.

    Parameters
    ----------
    center, feed, temperatures
    host, port, prefix
        The broker and the first topic level(s).
    stale_check_s : float, optional
        How often readings are checked for age (``temperatures.stale_after_s``); by
        default every 5 s, or every half of the stale limit when that is shorter, so that
        the status says stale at most half the limit late.
    status_refresh_s : float
        Every connected machine's status is republished this often (its ``last_seen``).
    """

    def __init__(self, center: Center, feed: Feed, temperatures: TemperatureBoard, *,
                 host: str, port: int = 1883, prefix: str = "ednc",
                 backoff: Backoff | None = None, stale_check_s: float | None = None,
                 status_refresh_s: float = 30.0, seed: int | None = None) -> None:
        self.center = center
        self.feed = feed
        self.temperatures = temperatures
        self.host = host
        self.port = port
        self.prefix = prefix
        self.backoff = backoff or Backoff(initial_s=0.5, cap_s=30.0)
        self.stale_check_s = (min(5.0, temperatures.stale_after_s / 2)
                              if stale_check_s is None else stale_check_s)
        self.status_refresh_s = status_refresh_s
        self.stats = BridgeStats()
        self.connected = asyncio.Event()
        self._rng = random.Random(seed)
        self._status: dict[str, _Status] = {}
        self._dirty: set[str] = set()
        self._events: deque[dict[str, Any]] = deque(maxlen=EVENT_BACKLOG)
        self._wake = asyncio.Event()
        # aiomqtt's exit waits, without a deadline, for the broker to confirm DISCONNECT;
        # the second cancel after the grace ends that wait when the broker does not answer
        self._background = Background(grace_s=5.0)
        self._unsubscribe: list[Any] = []
        self._bad = Counter("ednc_mqtt_bad_payloads", "MQTT temperature messages refused.",
                            registry=center.metrics.registry)

    async def __aenter__(self) -> MqttBridge:
        self._stopping = False
        self._unsubscribe.append(self.feed.subscribe(self._on_notice))
        self._background.start(self._connection_loop(), "mqtt:connection")
        self._background.start(self._stale_loop(), "mqtt:stale")
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        for unsubscribe in self._unsubscribe:
            unsubscribe()
        # The flag as well as the cancel: aiomqtt can turn the CancelledError into an
        # MqttError mid-operation, which the reconnect loop would otherwise take for a lost
        # broker and retry forever, holding the shutdown.
        self._stopping = True
        await self._background.stop()

    def topic(self, *levels: str) -> str:
        return "/".join((self.prefix, *levels))

    # -- the connection
    async def _connection_loop(self) -> None:
        attempt = 0
        while True:
            try:
                node = self.center.settings.node_id
                ident = f"ednc-center-{node}-{self._rng.getrandbits(32):08x}"
                async with aiomqtt.Client(self.host, self.port, identifier=ident,
                                          keepalive=15, timeout=5.0) as client:
                    attempt = 0
                    self.stats.connects += 1
                    self._read_in_batches(client)
                    await client.subscribe(self.topic("+", "temperature", "+"))
                    if self._stopping:  # a cancel dropped with the CONNACK or SUBACK (_send)
                        raise asyncio.CancelledError
                    self._dirty.update(self._status)  # the broker may have lost retained ones
                    self._wake.set()
                    self.connected.set()
                    log.info("MQTT bridge connected to %s:%d", self.host, self.port)
                    async with asyncio.TaskGroup() as tg:
                        tg.create_task(self._receive(client), name="mqtt:receive")
                        tg.create_task(self._publish(client), name="mqtt:publish")
            except* aiomqtt.MqttError as group:
                self.stats.last_error = str(group.exceptions[0])
            except* (OSError, TimeoutError) as group:
                self.stats.last_error = repr(group.exceptions[0])
            if self._stopping:  # shutting down, whatever aiomqtt made of the cancel
                raise asyncio.CancelledError
            if self.connected.is_set():
                self.connected.clear()
                stale = self.temperatures.mark_stale(source="mqtt")
                log.warning("MQTT broker lost (%s); %d readings marked stale",
                            self.stats.last_error, stale)
            delay = self.backoff.delay(attempt, self._rng)
            attempt += 1
            await asyncio.sleep(delay)

    async def _receive(self, client: aiomqtt.Client) -> None:
        # the messages come through _read_in_batches; this loop is what ends the
        # connection when the broker goes (aiomqtt's iterator raises then), and takes any
        # message aiomqtt queued itself
        async for message in client.messages:
            self.stats.received += 1
            self.handle(message.topic.value, message.payload)

    def _read_in_batches(self, client: aiomqtt.Client) -> None:
        """Read the broker's socket here, as much as has arrived per event-loop wake-up,
        and take the temperature messages without paho.

        aiomqtt's reader reads one MQTT packet per event-loop wake-up (paho's
        ``loop_read`` stops after one QoS 0 packet) and hands each message to a queue and
        a task: with a thousand machine sessions sharing the loop, one loop turn takes
        milliseconds, so at 500 temperatures/s the messages queued up in the socket for
        seconds (issue 13). paho itself reads a packet in three ``recv`` calls (type,
        length, body) and builds a message object, takes locks and matches callbacks for
        each. Here one ``recv`` takes up to :data:`READ_BYTES`; every complete QoS 0
        PUBLISH in it goes to :meth:`handle` at once, and every other packet (CONNACK,
        SUBACK, PUBACK of the status publishes, PINGRESP, a QoS 1 PUBLISH) is handed to
        paho, in order, through a socket stand-in it reads from (:class:`_PahoSocket`),
        so the protocol's state stays paho's. The end of the connection is handed to
        paho the same way: it disconnects as it would have. Reaches into aiomqtt 2.x's
        paho client (``_client``, ``_sock``, ``_protocol``), the one place that knows
        them; without them (another aiomqtt, MQTT 5, TLS) the bridge falls back to
        aiomqtt's own reading.
        """
        paho = getattr(client, "_client", None)
        sock = paho.socket() if paho is not None else None
        if (paho is None or sock is None or getattr(paho, "_sock", None) is not sock
                or getattr(paho, "_protocol", None) not in (mqtt_client.MQTTv31,
                                                            mqtt_client.MQTTv311)
                or isinstance(sock, ssl.SSLSocket)):
            log.info("MQTT bridge: aiomqtt's reader kept (no plain MQTT 3.1.1 paho socket)")
            return
        disconnected = getattr(client, "_disconnected", None)
        stats = self.stats
        real: Any = sock
        stand_in = _PahoSocket(real)
        paho._sock = stand_in
        packets = PacketReader()

        def on_message(_client: Any, _userdata: Any, message: Any) -> None:
            stats.received += 1  # a QoS 1 or 2 message: paho acknowledges it
            try:
                self.handle(message.topic, message.payload)
            except Exception:  # a bug in one reading must not end the bridge
                log.exception("MQTT message on %r not taken", message.topic)

        def to_paho() -> bool:
            """Let paho read what it was handed; False when the connection is over."""
            while stand_in.unread:
                try:
                    rc = paho.loop_read()
                except Exception as exc:  # as aiomqtt's reader: the connection broke
                    if disconnected is not None and not disconnected.done():
                        disconnected.set_exception(exc)
                    return False
                if rc != 0:  # paho has handled the end of the connection
                    return False
            return True

        def publish(topic: bytes, payload: bytes) -> None:
            stats.received += 1
            try:
                name = topic.decode("utf-8")
            except UnicodeDecodeError:
                self._refuse(repr(topic)[:80], PayloadError("topic is not UTF-8"))
                return
            try:
                self.handle(name, payload)
            except Exception:  # a bug in one reading must not end the bridge
                log.exception("MQTT message on %r not taken", name)

        def readable() -> None:
            cpu0 = time.thread_time()
            try:
                try:
                    data = real.recv(READ_BYTES)
                except (BlockingIOError, InterruptedError):
                    return
                except OSError as exc:
                    stand_in.end(exc)
                    to_paho()
                    return
                if not data:
                    stand_in.end(None)
                    to_paho()
                    return
                ack_at_once(real)
                taken = 0
                for item in packets.feed(data):
                    if isinstance(item, tuple):
                        publish(*item)
                        taken += 1
                        continue
                    stand_in.push(item)
                    if not to_paho():
                        return
                if taken:  # what paho notes for its keepalive on every packet read
                    with paho._msgtime_mutex:
                        paho._last_bytes_received = mqtt_client.time_func()
            finally:
                stats.read_cpu_s += time.thread_time() - cpu0

        paho.on_message = on_message
        asyncio.get_running_loop().add_reader(real.fileno(), readable)

    def handle(self, topic: str, payload: Any) -> bool:
        """Take one temperature message; False (counted, logged) when it is refused."""
        try:
            machine, sensor = self._parse_topic(topic)
            if not isinstance(payload, bytes | bytearray):
                payload = str(payload).encode()
            celsius, stamp = parse_temperature(bytes(payload))
        except PayloadError as exc:
            self._refuse(topic, exc)
            return False
        return self.temperatures.update(machine, sensor, celsius, source="mqtt", at=stamp)

    def _refuse(self, topic: str, exc: PayloadError) -> None:
        self.stats.bad_payloads += 1
        self._bad.inc()
        self.stats.bad_examples.append(f"{topic}: {exc}")
        level = logging.WARNING if self.stats.bad_payloads <= 10 else logging.DEBUG
        log.log(level, "MQTT %s refused: %s", topic, exc)

    def _parse_topic(self, topic: str) -> tuple[str, str]:
        head = self.prefix + "/"
        levels = topic[len(head):].split("/") if topic.startswith(head) else []
        if len(levels) != 3 or levels[1] != "temperature":
            raise PayloadError(f"topic is not {head}<machine>/temperature/<sensor>")
        machine, _, sensor = levels
        if not machine or len(machine) > 64:
            raise PayloadError("machine level is empty or too long")
        if not valid_sensor(sensor):
            raise PayloadError(f"sensor {sensor[:40]!r}: use letters, digits and '_'")
        return machine, sensor

    # -- publishing
    def _on_notice(self, notice: Notice) -> None:
        self._events.append({"kind": notice.kind.value, "machine": notice.machine,
                             "detail": notice.detail, "version": notice.version,
                             "time": notice.at.isoformat()})
        status = self._status.get(notice.machine)
        if status is None and notice.kind is not EventKind.REFUSED:
            status = self._status[notice.machine] = _Status()
        if status is not None:
            match notice.kind:
                case EventKind.CONNECTED:
                    status.connected = True
                case EventKind.DISCONNECTED:
                    status.connected = False
                case EventKind.PUSHED:
                    status.sent = notice.version
                case EventKind.APPLIED:
                    status.applied = notice.version
                case EventKind.REJECTED:
                    status.rejected = notice.version
                case _:
                    pass
            self._dirty.add(notice.machine)
        self._wake.set()

    async def _seed(self) -> None:
        """Versions sent and applied before this process started, from the database: for
        every machine not yet seeded at once (after a connect storm, a thousand of them,
        seeded one query each over 11 s of database thread in the MQTT benchmark; now 7
        calls)."""
        names = [n for n, s in self._status.items() if not s.seeded]
        for n in names:
            self._status[n].seeded = True
        found = await self.center.db.run(map_repo.latest_versions, names)
        for n in names:  # statuses are never removed, and news meanwhile wins
            st = self._status[n]
            sent, applied = found.get(n, (None, None))
            st.sent = st.sent if st.sent is not None else sent
            st.applied = st.applied if st.applied is not None else applied

    def status_of(self, name: str) -> dict[str, Any]:
        """The retained status JSON of one machine."""
        status = self._status.get(name) or _Status()
        link = self.center.registry.get(name)
        now_mono, now = time.monotonic(), time.time()
        temps = {column: {"celsius": r.celsius, "age_s": round(now_mono - r.received, 3),
                          "time": r.time, "source": r.source, "stale": r.stale}
                 for column, r in self.temperatures.readings(name).items()}
        return {
            "machine": name, "connected": link.connected,
            "map_version_sent": status.sent, "map_version_applied": status.applied,
            "map_version_rejected": status.rejected,
            "last_seen": link.last_seen.isoformat() if link.last_seen else None,
            "temperatures": temps, "time": now,
        }

    async def _publish(self, client: aiomqtt.Client) -> None:
        next_refresh = time.monotonic() + self.status_refresh_s
        while True:
            with contextlib.suppress(TimeoutError):
                async with asyncio.timeout(max(0.0, next_refresh - time.monotonic())):
                    await self._wake.wait()
            self._wake.clear()
            if time.monotonic() >= next_refresh:
                next_refresh = time.monotonic() + self.status_refresh_s
                self._dirty.update(n for n, s in self._status.items() if s.connected)
            while self._events:
                body = self._events[0]
                await _send(client, self.topic("events"), json.dumps(body), retain=False)
                self._events.popleft()
                self.stats.published += 1
            while self._dirty:
                name = self._dirty.pop()
                status = self._status.setdefault(name, _Status())
                if not status.seeded:
                    await self._seed()
                try:
                    await _send(client, self.topic(name, "status"),
                                json.dumps(self.status_of(name)), retain=True)
                except aiomqtt.MqttError:
                    self._dirty.add(name)
                    raise
                self.stats.published += 1

    async def _stale_loop(self) -> None:
        while True:
            await asyncio.sleep(self.stale_check_s)
            self.temperatures.mark_stale()
