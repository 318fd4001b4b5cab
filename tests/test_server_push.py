"""The push scheduler against simulated machines on loopback: a model change pushes a new
version at once, a reconnect gets the current map again, a temperature its thermal model
uses gives a new version, rejections and silence are recorded."""

from __future__ import annotations

import asyncio
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

from machine_sim.lookup import GridMap
from protocol import (
    Controller,
    Error,
    ErrorCode,
    Hello,
    MapAck,
    MapAssembler,
    MapBegin,
    MapChunk,
    MapEncoding,
    MapEnd,
    MapReject,
    MapRejectReason,
    Telemetry,
    Welcome,
)
from server.db import error_models as model_repo
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.events import EventKind
from server.links.ednc.session import Verdict
from server.push import Delivery, thermal_sensors
from server.push.scheduler import PREPARING
from tests.support.link import (
    DEADLINE_S,
    RawMachine,
    model_body,
    rig,
    simulator,
    until,
)


def test_thermal_sensors_reads_the_model_terms() -> None:
    assert thermal_sensors(model_body()) == frozenset()
    assert thermal_sensors(model_body(thermal_sensor="T_spindle_C")) == {"T_spindle_C"}


async def test_a_new_model_is_pushed_at_once(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, period_s=600.0) as r:
        mid = await r.register(model=model_body())
        async with simulator(r.port) as sim:
            await until(lambda: sim.runtime.controller.store.version == 1)
            await r.db.run(model_repo.add_model, mid, source="fit",
                           body=model_body(slope=0.02))
            await until(lambda: sim.runtime.controller.store.version == 2)

            async def acked_2() -> bool:
                return await r.acked_version(mid) == 2

            await until(acked_2)
            v2 = await r.db.run(map_repo.get_map_version, mid, 2)
            assert v2 is not None and v2.model_version == 2
            v1 = await r.db.run(map_repo.get_map_version, mid, 1)
            assert v1 is not None and v1.payload != v2.payload
        pushed = await r.events(EventKind.PUSHED)
        assert "model version 2" in pushed[0].detail


async def test_a_burst_of_model_changes_gives_few_builds(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, period_s=600.0) as r:
        mid = await r.register(model=model_body())
        async with simulator(r.port) as sim:
            await until(lambda: sim.runtime.controller.store.version == 1)
            for i in range(10):
                await r.db.run(model_repo.add_model, mid, source="fit",
                               body=model_body(slope=0.02 + 0.001 * i))
            await until(lambda: r.acked_version(mid))
            latest = await r.db.run(model_repo.get_model, mid)
            assert latest is not None and latest.version == 11

            async def current() -> bool:
                row = await r.db.run(map_repo.get_map_version, mid, with_payload=False)
                return row is not None and row.model_version == 11

            await until(current)
            maps = await r.db.run(map_repo.list_map_versions, mid)
            assert len(maps) < 11  # coalesced: not one map per stored model
            await until(lambda: sim.runtime.controller.store.version == maps[0].version)


async def test_a_reconnecting_machine_gets_the_current_map_again(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(model=model_body())
        async with simulator(r.port) as sim:
            await until(lambda: sim.runtime.controller.store.version == 1)
        await until(lambda: not r.center.registry.get("vmc-01").connected)
        async with simulator(r.port) as fresh:  # a restarted PLC: no map at all
            await until(lambda: fresh.runtime.controller.store.version == 1)

            async def both_acked() -> bool:
                rows = await r.db.run(map_repo.list_applied, mid)
                return len(rows) == 2 and all(d.acked for d in rows)

            await until(both_acked)
        deliveries = await r.db.run(map_repo.list_applied, mid)
        assert [(d.map_version, d.acked) for d in deliveries] == [(1, True), (1, True)]
        maps = await r.db.run(map_repo.list_map_versions, mid)
        assert len(maps) == 1  # sent again, not rebuilt


async def test_temperature_change_beyond_the_threshold_gives_a_new_version(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, threshold_K=0.05) as r:
        mid = await r.register(model=model_body(thermal_sensor="T_spindle_C"))
        board = r.services.temperatures
        delivered: list[Delivery] = []
        r.services.push.observers.append(delivered.append)
        # a ladder that takes version-1 grids only: the center rebuilds on temperatures
        async with simulator(r.port, thermal_records=False) as sim:
            await sim.ready.wait()
            await asyncio.sleep(0.2)
            assert await r.acked_version(mid) is None  # no temperature yet: no map
            board.update("vmc-01", "spindle", 24.0, source="mqtt")
            await until(lambda: sim.runtime.controller.store.version == 1)
            board.update("vmc-01", "spindle", 24.03, source="mqtt")  # below the threshold
            board.update("vmc-01", "T_air_C", 30.0, source="mqtt")   # not in the model
            await asyncio.sleep(0.3)
            assert len(await r.db.run(map_repo.list_map_versions, mid)) == 1
            board.update("vmc-01", "spindle", 24.5, source="mqtt")
            await until(lambda: sim.runtime.controller.store.version == 2)
            await until(lambda: len(delivered) == 2)
        maps = await r.db.run(map_repo.list_map_versions, mid)
        assert [m.temperatures for m in maps] == [{"T_spindle_C": 24.5},
                                                  {"T_spindle_C": 24.0}]
        assert [d.outcome for d in delivered] == ["applied", "applied"]


async def test_a_grid_with_thermal_records_is_not_rebuilt_for_temperatures(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, threshold_K=0.05) as r:
        mid = await r.register(model=model_body(thermal_sensor="T_spindle_C"))
        board = r.services.temperatures
        delivered: list[Delivery] = []
        r.services.push.observers.append(delivered.append)
        # declares INT32_INCREMENTS | THERMAL, not FACTORED: a factored map (format
        # version 5) would be the smaller kind and auto would pick it
        async with simulator(r.port, factored=False) as sim:
            store = sim.runtime.controller.store
            # no temperature needed: the map is built at the term's reference
            await until(lambda: store.version == 1)
            active = store.active
            assert isinstance(active, GridMap) and [r.sensor for r in active.thermal] == [
                "spindle"]  # the name the Temperatures message carries
            board.update("vmc-01", "spindle", 24.0, source="mqtt")
            board.update("vmc-01", "spindle", 27.5, source="mqtt")
            # a wake rebuilds only when the inputs changed: the temperatures are not inputs
            assert r.services.push.request("vmc-01", "check")
            await asyncio.sleep(0.5)
            assert store.version == 1
        maps = await r.db.run(map_repo.list_map_versions, mid)
        assert len(maps) == 1 and len(delivered) == 1
        v1 = await r.db.run(map_repo.get_map_version, mid, 1)
        assert v1 is not None and v1.payload[4:6] == b"\x03\x00"  # grid + thermal records


async def test_siemens_telemetry_temperatures_drive_its_thermal_map(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(controller="siemens",
                               model=model_body(thermal_sensor="T_spindle_C"))
        async with simulator(r.port, controller="siemens") as sim:
            await until(lambda: sim.runtime.controller.store.version >= 1)
        first = await r.db.run(map_repo.get_map_version, mid, 1)
        assert first is not None and set(first.temperatures) == {"T_spindle_C"}
        readings = r.services.temperatures.readings("vmc-01")
        assert readings["T_spindle_C"].source == "telemetry"
        # the map was built at what the machine reported (a shop-floor temperature; it may
        # have moved on since, with a newer map)
        assert 5.0 < first.temperatures["T_spindle_C"] < 45.0


async def raw_session(port: int) -> tuple[RawMachine, MapBegin, bytes, int]:
    """Log in by hand and collect the first map push up to MapEnd."""
    raw = await RawMachine.connect(port)
    assert isinstance(await raw.login(), Welcome)
    assembler = MapAssembler("vmc-01", MapEncoding.INT32_INCREMENTS)
    begin: MapBegin | None = None
    while True:
        msg = await raw.next()
        match msg:
            case MapBegin():
                begin = msg
                assembler.feed(msg)
            case MapChunk():
                assembler.feed(msg)
            case MapEnd(version=version):
                verdict = assembler.feed(msg)
                assert begin is not None and verdict is not None
                return raw, begin, getattr(verdict, "data", b""), version
            case _:
                continue


async def test_a_rejected_map_is_recorded_with_its_reason(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(model=model_body())
        raw, begin, data, version = await raw_session(r.port)
        assert len(data) == begin.total_size and version == 1
        await raw.send(MapReject(version, MapRejectReason.APPLY_FAILED, "PMC busy"))

        async def answered() -> bool:
            rows = await r.db.run(map_repo.list_applied, mid)
            return bool(rows) and rows[0].reject_reason is not None

        await until(answered)
        rows = await r.db.run(map_repo.list_applied, mid)
        assert rows[0].reject_reason == "APPLY_FAILED: PMC busy" and not rows[0].acked
        rejected = await r.events(EventKind.REJECTED)
        assert "APPLY_FAILED: PMC busy" in rejected[0].detail
        assert r.center.metrics.pushes.labels(outcome="rejected")._value.get() == 1
        raw.close()


async def test_an_answer_just_before_the_machine_leaves_is_kept(tmp_path: Path) -> None:
    # The race behind test_a_reconnecting_machine_gets_the_current_map_again's rare
    # failures: the machine acks and closes at once; the push task queues the database
    # write of the answer, the session's end cancels the task, and a write still queued
    # behind busy worker threads (a loaded machine) was cancelled with it: a delivery the
    # machine applied stayed unanswered. Here the one worker thread is held busy so that
    # the write is queued when the session ends, every time.
    loop = asyncio.get_running_loop()
    loop.set_default_executor(ThreadPoolExecutor(max_workers=1))
    gate = threading.Event()
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(model=model_body())
        raw, _, _, version = await raw_session(r.port)
        held = loop.run_in_executor(None, gate.wait, DEADLINE_S)
        raw.writer.write(raw.conn.send(MapAck(version)))
        raw.close()
        await until(lambda: not r.center.registry.get("vmc-01").connected)
        gate.set()
        await held

        async def answered() -> bool:
            rows = await r.db.run(map_repo.list_applied, mid)
            return bool(rows) and (rows[0].acked or rows[0].reject_reason is not None)

        async with asyncio.timeout(5.0):  # queued writes run at once when the gate opens
            await until(answered)
        rows = await r.db.run(map_repo.list_applied, mid)
        assert [(d.map_version, d.acked) for d in rows] == [(1, True)]
        assert (await r.events(EventKind.APPLIED))[0].detail == "map version 1 applied"


async def test_no_verdict_in_time_closes_the_session(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, verdict_timeout_s=0.3) as r:
        mid = await r.register(model=model_body())
        raw, _, _, _ = await raw_session(r.port)  # and never answer
        assert await raw.reader.read() != b""  # the Error TIMEOUT, then the close
        await until(lambda: not r.center.registry.get("vmc-01").connected)
        rows = await r.db.run(map_repo.list_applied, mid)
        # no answer is no verdict: a failed delivery, not a rejection (issue 30)
        assert rows[0].reject_reason is None and rows[0].state == "failed"
        assert rows[0].failure is not None and "no answer" in rows[0].failure
        assert r.center.metrics.pushes.labels(outcome="failed")._value.get() == 1


async def test_ack_is_recorded_for_a_hand_driven_machine(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(model=model_body())
        raw, _, _, version = await raw_session(r.port)
        await raw.send(MapAck(version))
        await until(lambda: r.acked_version(mid))
        assert await r.acked_version(mid) == 1
        raw.close()


async def test_the_period_resends_a_map_the_machine_no_longer_has(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, period_s=0.2) as r:
        mid = await r.register(model=model_body())
        raw, _, _, version = await raw_session(r.port)
        await raw.send(MapAck(version))
        await until(lambda: r.acked_version(mid))
        # the machine says it has nothing applied (its map expired or was released)
        await raw.send(Telemetry(1763820000000, "idle", 0))
        while not isinstance(msg := await raw.next(), MapBegin):
            assert msg is not None, "closed instead of re-sending"
        assert msg.version == version  # the same map again, not a rebuild
        assert len(await r.db.run(map_repo.list_map_versions, mid)) == 1
        raw.close()


async def test_a_deleted_machine_is_disconnected(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register(model=model_body())
        raw, _, _, version = await raw_session(r.port)
        await raw.send(MapAck(version))  # deleted while the answer may still be stored
        await r.db.run(machine_repo.delete_machine, "vmc-01")
        assert r.services.push.request("vmc-01", "test")
        while (msg := await raw.next()) is not None and not isinstance(msg, Error):
            pass
        assert isinstance(msg, Error) and msg.code is ErrorCode.SHUTDOWN
        assert "no longer registered" in msg.text


class _SlowPlcLink:
    """A controller link whose verdict takes a PLC cycle: what the scheduler sees."""

    def __init__(self, name: str, ip: str) -> None:
        self._name = name
        self.address = f"{ip}:502"
        self.closed_because: str | None = None
        self.hello = Hello(name=name, ip=ip, controller=Controller.FANUC,
                           map_formats=MapEncoding.FLOAT32_MM | MapEncoding.INT32_INCREMENTS,
                           software_version="plc/test", translational_type=1)
        self.pushed: list[int] = []

    @property
    def name(self) -> str:
        return self._name

    @property
    def reported_version(self) -> int | None:
        return None

    def adopt(self, version: int, payload: bytes) -> None:
        pass

    async def push_map(self, version: int, payload: bytes, timeout_s: float) -> Verdict:
        self.pushed.append(version)
        await asyncio.sleep(0.2)
        return Verdict(version, True, None, "", 0.2)

    def send(self, msg: object) -> None:
        pass

    def abort(self, code: ErrorCode | None, text: str) -> None:
        self.closed_because = text

    async def wait_closed(self) -> None:
        await asyncio.Event().wait()


async def test_machines_woken_together_get_maps_before_all_are_prepared(
        tmp_path: Path) -> None:
    """40 machines woken at once: the first maps leave while others are still being
    prepared, not after every machine's first database step (the database threads are
    one FIFO: unbounded, each machine took its first step before any took its second)."""
    count = 40
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, period_s=600.0) as r:
        rows = []
        for i in range(count):
            ip = f"10.0.0.{i + 1}"
            await r.register(f"m-{i:02d}", ip=ip, model=model_body(f"m-{i:02d}"))
            rows.append((await r.db.run(machine_repo.get_machine, f"m-{i:02d}"), ip))
        steps: list[str] = []
        run = r.db.run

        async def logged(fn: Any, *args: Any, **kwargs: Any) -> Any:
            steps.append(fn.__name__)
            return await run(fn, *args, **kwargs)

        r.db.run = logged  # type: ignore[method-assign]
        links = [_SlowPlcLink(row.name, ip) for row, ip in rows if row is not None]
        workers = [asyncio.create_task(r.services.push.serve(link, row))
                   for link, (row, _ip) in zip(links, rows, strict=True) if row is not None]
        try:
            await until(lambda: all(link.pushed for link in links))
        finally:
            for w in workers:
                w.cancel()
            await asyncio.gather(*workers, return_exceptions=True)
        loads = [k for k, s in enumerate(steps) if s == "load_inputs"]
        first_sent = steps.index("store_and_send")
        assert len(loads) == count
        assert first_sent < loads[-1], (
            f"the first map was noted after all {count} machines' first step")
        assert first_sent < loads[PREPARING + 1]
