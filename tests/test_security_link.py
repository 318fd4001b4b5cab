"""The machine port as an attacker on the plant network meets it (issue 12): real sockets
from several loopback addresses (127.0.0.0/8 is all loopback on Linux), the real center
services, SQLite in tmp_path.

Each test fails on the code before it: unregistered peers took handshake slots and wrote
an event row each, a full global handshake limit locked machines out, refusals told the
peer the registered address, failed logins were not throttled, a changed secret left the
old session up, and Hello had the whole 10 s handshake to arrive."""

from __future__ import annotations

import asyncio
from pathlib import Path

from protocol import (
    Controller,
    Error,
    ErrorCode,
    Hello,
    MapEncoding,
    Message,
    Reject,
    Welcome,
)
from server.db import Database, make_engine
from server.db import machines as machine_repo
from server.db.secretbox import SecretBox
from server.events import EventKind
from server.links.ednc import LinkTiming
from server.links.ednc.admission import HandshakeSlots, LoginThrottle, RefusalLog
from tests.support.link import (
    DEADLINE_S,
    SECRET,
    RawMachine,
    description,
    rig,
    until,
)


async def connect_from(ip: str, port: int) -> RawMachine:
    reader, writer = await asyncio.open_connection("127.0.0.1", port, local_addr=(ip, 0))
    return RawMachine(reader, writer)


async def closed(peer: RawMachine) -> bytes:
    """What the center sent before closing (a close with our bytes unread is a reset)."""
    try:
        return await peer.closed()
    except ConnectionResetError:
        return b""


# -- 1. admission at accept

async def test_a_peer_where_no_machine_is_registered_is_closed_at_accept_without_a_row(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register()  # at 127.0.0.1
        for _ in range(200):
            peer = await connect_from("127.0.0.9", r.port)
            await peer.send(Hello("vmc-01", "127.0.0.1", Controller.FANUC,
                                  MapEncoding.INT32_INCREMENTS, "x", "w X Y b Z t"))
            assert await closed(peer) == b""  # not even a Reject
            peer.close()
        assert r.services.server.handshaking == 0
        assert r.center.metrics.refusals.labels(reason="unregistered")._value.get() == 200
        await r.services.server.refusal_log.flush(everything=True)
        assert await r.events(EventKind.REFUSED) == []
        # and the registered machine is served
        raw = await RawMachine.connect(r.port)
        assert isinstance(await raw.login(), Welcome)
        raw.close()


async def test_a_machine_registered_later_is_admitted_at_once(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register()
        peer = await connect_from("127.0.0.2", r.port)
        assert await peer.closed() == b""
        await r.register("vmc-02", ip="127.0.0.2")  # a commit refreshes the address book
        await until(lambda: r.services.server.addresses.admits("127.0.0.2"))
        late = await connect_from("127.0.0.2", r.port)
        assert isinstance(await late.login("vmc-02", ip="127.0.0.2"), Welcome)
        late.close()


async def test_a_registered_machine_gets_in_while_registered_addresses_hold_every_slot(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, handshake_s=10.0,
                                               max_handshakes=8) as r:
        await r.register()
        holders: list[RawMachine] = []
        for i in range(12):  # addresses of registered machines, each as full as allowed
            ip = f"127.0.1.{i + 1}"
            await r.register(f"held-{i}", ip=ip)
        await until(lambda: r.services.server.addresses.admits("127.0.1.12"))
        for i in range(12):
            for _ in range(4):
                holders.append(await connect_from(f"127.0.1.{i + 1}", r.port))
                holders[-1].writer.write(b"E")  # one byte of a frame, then nothing
        await until(lambda: r.services.server.handshaking == 8)
        logins = []
        for _ in range(10):
            raw = await RawMachine.connect(r.port)
            logins.append(await raw.login())
            raw.close()
            await until(lambda: not r.center.registry.get("vmc-01").connected)
        assert all(isinstance(m, Welcome) for m in logins), logins
        assert r.services.server.slots.evicted >= 10
        for h in holders:
            h.close()


def test_handshake_slots_per_address_and_eviction_of_the_oldest_waiter() -> None:
    evicted: list[str] = []
    slots = HandshakeSlots(total=3, per_address=2)
    a1 = slots.acquire("a", lambda: evicted.append("a1"))
    a2 = slots.acquire("a", lambda: evicted.append("a2"))
    assert a1 is not None and a2 is not None
    assert slots.acquire("a", lambda: None) is None  # per address
    b1 = slots.acquire("b", lambda: evicted.append("b1"))
    assert b1 is not None and len(slots) == 3
    slots.waiting(a1, False)  # a1 is being worked on by the center: never evicted
    assert slots.acquire("b", lambda: None) is None  # b holds one: may not push out
    c1 = slots.acquire("c", lambda: evicted.append("c1"))
    assert c1 is not None and evicted == ["a2"]  # the oldest waiting on its peer
    slots.waiting(b1, False)
    slots.waiting(c1, False)
    assert slots.acquire("d", lambda: None) is None  # nobody waiting: refused
    slots.release(a1)
    assert slots.acquire("d", lambda: None) is not None


# -- 2. a Hello deadline

async def test_a_peer_that_does_not_say_hello_is_dropped_after_the_hello_deadline(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, handshake_s=10.0) as r:
        await r.register()
        r.services.server.timing = LinkTiming(handshake_s=10.0, hello_s=0.2, heartbeat_s=0.5)
        silent = await RawMachine.connect(r.port)
        silent.conn.receive_data(await silent.closed())
        error = silent.conn.next_event()
        assert isinstance(error, Error) and error.code is ErrorCode.TIMEOUT
        refused = await r.wait_events(EventKind.REFUSED)
        assert "no Hello within 0.2 s" in refused[0].detail


# -- 3. say less before login

async def test_a_refused_peer_learns_the_code_only(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register()  # vmc-01 at 127.0.0.1
        await r.register("vmc-02", ip="127.0.0.2")
        raw = await RawMachine.connect(r.port)  # from 127.0.0.1, claiming vmc-02
        answer = await raw.login("vmc-02", ip="127.0.0.1")
        assert isinstance(answer, Reject) and answer.code is ErrorCode.ADDRESS_MISMATCH
        assert answer.text == ""
        await closed(raw)  # the center closes once it has stored the refusal
        r.services.server.throttle = LoginThrottle()  # that failure throttles 127.0.0.1
        raw = await RawMachine.connect(r.port)  # vmc-01, claiming to be a Siemens
        await raw.send(Hello("vmc-01", "127.0.0.1", Controller.SIEMENS,
                             MapEncoding.FLOAT32_MM, "x", "w X Y b Z t"))
        answer = await raw.next()
        assert isinstance(answer, Reject) and answer.code is ErrorCode.UNSUPPORTED
        assert answer.text == ""
        await closed(raw)  # the center closes once it has stored the refusal
        # the center's side has the detail: the dashboard's refusal list
        await r.services.server.refusal_log.flush(everything=True)
        details = " | ".join(e.detail for e in await r.events(EventKind.REFUSED))
        assert "registered at 127.0.0.2" in details


# -- 4. login throttle

async def test_failed_logins_are_throttled_and_counted(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register()
        r.services.server.throttle = LoginThrottle(base_s=60.0)  # long enough for the test
        raw = await RawMachine.connect(r.port)
        answer = await raw.login(secret="a-wrong-secret-0123")
        assert isinstance(answer, Reject) and answer.code is ErrorCode.AUTH_FAILED
        raw.close()
        # the right secret right after: refused without a look at the answer
        raw = await RawMachine.connect(r.port)
        await raw.send(Hello("vmc-01", "127.0.0.1", Controller.FANUC,
                             MapEncoding.INT32_INCREMENTS, "x", "w X Y b Z t"))
        answer = await raw.next()
        assert isinstance(answer, Reject) and answer.code is ErrorCode.AUTH_FAILED
        raw.close()
        metrics = r.center.metrics
        assert metrics.logins_throttled._value.get() == 1
        assert metrics.refusals.labels(reason="throttled")._value.get() == 1
        assert b"ednc_logins_throttled_total 1.0" in metrics.exposition()


def test_the_throttle_doubles_its_delay_and_forgets_after_a_success() -> None:
    now = [0.0]
    t = LoginThrottle(base_s=0.5, max_s=8.0, clock=lambda: now[0])
    delays = []
    for _ in range(6):
        t.failed("ip:a", "name:m")
        start = now[0]
        while t.blocked("ip:a") is not None:
            now[0] += 0.25
        delays.append(now[0] - start)
    assert delays == [0.5, 1.0, 2.0, 4.0, 8.0, 8.0]
    assert t.blocked("ip:b", "name:m") is None  # ...and the name's block ran out too
    t.failed("name:m")
    assert t.blocked("ip:b", "name:m") == "name:m"
    t.succeeded("ip:a", "name:m")
    assert t.blocked("ip:a", "name:m") is None


# -- 5. refusals aggregated

async def test_a_stream_of_refusals_from_one_peer_is_two_rows(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register()
        for _ in range(100):
            raw = await RawMachine.connect(r.port)
            answer = await raw.login("nobody-01")
            assert isinstance(answer, Reject)
            raw.close()
        refusals = r.center.metrics.refusals
        counted = sum(refusals.labels(reason=k)._value.get() for k in ("unknown", "throttled"))
        assert counted == 100
        await r.services.server.refusal_log.flush(everything=True)
        rows = await r.events(EventKind.REFUSED)
        assert len(rows) == 2, [e.detail for e in rows]
        assert rows[0].detail.startswith("99 more refusals")


async def test_refusal_log_windows() -> None:
    now = [0.0]
    stored: list[tuple[str, str]] = []

    async def store(rows: list[tuple[str, str, str]]) -> None:
        stored.extend((who, detail) for who, detail, _ in rows)

    log = RefusalLog(store, window_s=60.0, clock=lambda: now[0])
    for _ in range(5):
        await log.refused("10.0.0.9", "bad frame", "protocol")
    await log.refused("10.0.0.8", "timeout", "timeout")
    assert [w for w, _ in stored] == ["10.0.0.9", "10.0.0.8"]
    now[0] = 61.0
    await log.flush()
    assert stored[-1] == ("10.0.0.9", "4 more refusals in 60 s after: bad frame")
    assert len(stored) == 3  # 10.0.0.8 had one: no summary


# -- 6. a changed secret closes the session

async def test_a_changed_secret_closes_the_session_that_used_the_old_one(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, heartbeat_s=5.0) as r:
        r.db.secrets = SecretBox.from_text("a-key-for-this-test")
        await r.register()
        raw = await RawMachine.connect(r.port)
        assert isinstance(await raw.login(), Welcome)
        await r.db.run(machine_repo.update_machine, "vmc-01", description=description(),
                       secret="a-brand-new-secret-0123", box=r.db.secrets)
        raw.conn.receive_data(await raw.closed())
        last = None
        while isinstance(e := raw.conn.next_event(), (Error, Welcome)) or hasattr(e, "token"):
            last = e
        assert isinstance(last, Error) and last.code is ErrorCode.AUTH_FAILED
        await until(lambda: not r.center.registry.get("vmc-01").connected)
        # the new secret logs in (sealed in the database, opened for the challenge)
        raw = await RawMachine.connect(r.port)
        assert isinstance(await raw.login(secret="a-brand-new-secret-0123"), Welcome)
        raw.close()
        assert SECRET  # the old one is refused
        raw = await RawMachine.connect(r.port)
        assert isinstance(await raw.login(), Reject)
        raw.close()


async def test_refusals_at_once_are_stored_in_a_few_transactions() -> None:
    batches: list[int] = []

    async def store(rows: list[tuple[str, str, str]]) -> None:
        batches.append(len(rows))
        await asyncio.sleep(0.01)  # a commit takes time; others queue meanwhile

    log = RefusalLog(store)
    runner = asyncio.create_task(log.run(period_s=3600.0))
    await asyncio.sleep(0)
    await asyncio.gather(*(log.refused(f"10.0.0.{i}", "timeout", "timeout")
                           for i in range(50)))
    assert sum(batches) == 50 and len(batches) <= 3, batches  # not 50 database calls
    runner.cancel()
    await asyncio.gather(runner, return_exceptions=True)


async def test_a_secret_changed_through_another_node_closes_the_session_at_the_next_read(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, heartbeat_s=5.0) as r:
        await r.register()
        raw = await RawMachine.connect(r.port)
        assert isinstance(await raw.login(), Welcome)
        other = Database(make_engine(r.center.settings.database_url))  # another node's
        try:
            await other.run(machine_repo.update_machine, "vmc-01", description=description(),
                            secret="a-brand-new-secret-0123")
        finally:
            other.engine.dispose()
        assert r.center.registry.get("vmc-01").connected  # this node has not read it yet
        await r.services.server.addresses.refresh()  # what it does every 30 s
        raw.conn.receive_data(await raw.closed())
        messages = []
        while isinstance(e := raw.conn.next_event(), Message):
            messages.append(e)
        assert isinstance(messages[-1], Error) and messages[-1].code is ErrorCode.AUTH_FAILED
        await until(lambda: not r.center.registry.get("vmc-01").connected)
        # a session that logged in with the new secret outlives the next read
        fresh = await RawMachine.connect(r.port)
        assert isinstance(await fresh.login(secret="a-brand-new-secret-0123"), Welcome)
        await r.services.server.addresses.refresh()
        assert r.center.registry.get("vmc-01").connected
        fresh.close()
