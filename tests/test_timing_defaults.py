"""The center's link timing defaults are the protocol's (protocol/limits.py), not a second
set of numbers: the server once sent a 10 s heartbeat where the README says 5 s."""

from __future__ import annotations

from protocol.limits import HEARTBEAT_PERIOD_MS, MISSED_HEARTBEATS
from server.links.ednc.server import LinkTiming
from server.settings import Settings


def test_the_default_heartbeat_is_the_protocols() -> None:
    assert Settings().heartbeat_s * 1000 == HEARTBEAT_PERIOD_MS
    timing = LinkTiming()
    assert timing.heartbeat_s * 1000 == HEARTBEAT_PERIOD_MS
    assert timing.dead_after_s * 1000 == MISSED_HEARTBEATS * HEARTBEAT_PERIOD_MS
