"""Shared helpers of the Structured Text PLC tests: deliver a map into a window as the
center does (protocol/README.md §13.2) and read the status."""

from __future__ import annotations

import struct
from collections.abc import MutableSequence, Sequence

from machine_sim.stplc import StPlc
from protocol import decode_payload
from protocol.ctrlmem import (
    SLOTS_VERSION_AT,
    STATUS_AT,
    STATUS_SIZE,
    TEMP_SEQ_AT,
    TEMPERATURES_AT,
    Layout,
    Status,
    Write,
    decode_status,
    plan_map_write,
)
from protocol.mapfactored import FactoredPayload

__all__ = ["loaded", "status", "write_all", "write_map", "write_temperatures"]


def write_all(window: MutableSequence[int] | memoryview | bytearray,
              writes: Sequence[Write]) -> None:
    """Apply the center's writes to the window, in order."""
    for w in writes:
        window[w.offset:w.offset + len(w.data)] = w.data


def write_map(window: memoryview | bytearray, layout: Layout, buffer: int, payload: bytes,
              version: int, seq: int) -> None:
    """Steps 2-5 of §13.2 in one go: clear the header, the payload, the header, the
    switch word."""
    write_all(window, plan_map_write(layout, buffer, payload, version, seq))


def write_temperatures(window: memoryview | bytearray, slots_mC: Sequence[int], seq: int,
                       map_version: int = 0) -> None:
    """The temperature slots (m°C; -2^31 for nothing to say), the slots' map version
    and the sequence, in the order the center writes them (§13.1)."""
    values = list(slots_mC) + [-(1 << 31)] * (32 - len(slots_mC))
    window[TEMPERATURES_AT:TEMP_SEQ_AT] = struct.pack("<32i", *values)
    window[SLOTS_VERSION_AT:SLOTS_VERSION_AT + 4] = struct.pack("<I", map_version)
    window[TEMP_SEQ_AT:TEMP_SEQ_AT + 2] = struct.pack("<H", seq)


def status(window: memoryview | bytearray) -> Status:
    return decode_status(bytes(window[STATUS_AT:STATUS_AT + STATUS_SIZE]))


def loaded(data: bytes, readings_mC: dict[str, int] | None = None,
           axes: Sequence[str] | None = None) -> StPlc:
    """A compiled PLC with the map ``data`` (factored or int32 grid) applied through its
    window, no channel limit but the map's and no step limit, the readings (m°C by
    sensor) written to its temperature slots; ``axes`` the machine's (a factored map's
    own by default)."""
    p = decode_payload(data)
    if axes is None:
        assert isinstance(p, FactoredPayload)
        axes = [a.name for a in p.axes]
    plc = StPlc(p.machine, axes, channel_limit=(1 << 30) - 1, max_step=1 << 30)
    plc.scan([0] * len(plc.axes))
    write_map(plc.window, plc.layout, 1, data, p.version, 1)
    plc.scan([0] * len(plc.axes))
    st = status(plc.window)
    assert (st.ack_seq, st.ack_code, st.active, st.applied_version) == (1, 0, 1, p.version), st
    if readings_mC:
        sensors = list(dict.fromkeys(r.sensor for r in p.thermal))
        write_temperatures(plc.window, [readings_mC[s] for s in sensors], 1, p.version)
        plc.scan([0] * len(plc.axes))
        assert status(plc.window).temp_ack == 1
    return plc
