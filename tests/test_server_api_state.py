"""The live-link registry (server.state) that the machine TCP server fills."""

from __future__ import annotations

import datetime as dt

import pytest

from server.state import Registry

T0 = dt.datetime(2026, 5, 1, 8, 0, tzinfo=dt.UTC)


def test_a_never_seen_machine_is_not_connected() -> None:
    link = Registry().get("vmc-01")
    assert (link.connected, link.address, link.last_seen, dict(link.telemetry)) == (
        False, None, None, {})


def test_connect_telemetry_disconnect() -> None:
    reg = Registry()
    reg.connected("vmc-01", "10.0.0.21:5000", at=T0)
    reg.seen("vmc-01", telemetry={"x_mm": 1.0}, at=T0 + dt.timedelta(seconds=5))
    reg.seen("vmc-01", at=T0 + dt.timedelta(seconds=9))  # a heartbeat keeps the telemetry
    link = reg.get("vmc-01")
    assert link.connected and link.connected_since == T0
    assert link.last_seen == T0 + dt.timedelta(seconds=9)
    assert dict(link.telemetry) == {"x_mm": 1.0}
    assert reg.connected_count() == 1
    reg.disconnected("vmc-01")
    link = reg.get("vmc-01")
    assert not link.connected and link.connected_since is None
    assert link.address == "10.0.0.21:5000" and dict(link.telemetry) == {"x_mm": 1.0}
    assert reg.connected_count() == 0


def test_snapshots_do_not_change_under_the_reader() -> None:
    reg = Registry()
    telemetry = {"x_mm": 1.0}
    reg.seen("vmc-01", telemetry=telemetry)
    before = reg.get("vmc-01")
    telemetry["x_mm"] = 2.0
    reg.seen("vmc-01", telemetry={"x_mm": 3.0})
    assert before.telemetry["x_mm"] == 1.0
    with pytest.raises(TypeError):
        before.telemetry["x_mm"] = 4.0  # type: ignore[index]


def test_all_is_sorted_and_forget_drops() -> None:
    reg = Registry()
    for name in ("b", "a", "c"):
        reg.connected(name, f"{name}:1")
    assert [link.name for link in reg.all()] == ["a", "b", "c"]
    reg.forget("b")
    reg.forget("never-there")
    assert [link.name for link in reg.all()] == ["a", "c"] and reg.connected_count() == 2
