"""The machine's map memory: staging, the swap rule, the last good map, validity.

Pushed map messages go through :class:`protocol.maptransfer.MapAssembler` (whole, in
order, checksum, decodes, this machine, an accepted encoding). A map that passes those
must then suit this controller, or it is refused with ``APPLY_FAILED`` and a text naming
the problem:

* every grid dimension and every output is an axis of this machine;
* every value (and reversal) is within ``±limit_mm``: the range the controller's
  compensation channel can hold (EMZPS range, SD43900 limit).

Only then does the store swap to the new map, in one assignment between two scans. On
any rejection the map in use stays as it was.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from protocol.codes import MapEncoding, MapRejectReason
from protocol.limits import MAX_MAP_BYTES
from protocol.mapformat import ErrorMapPayload
from protocol.maptransfer import MapAccepted, MapAssembler, MapRejected
from protocol.messages import MapAck, MapBegin, MapChunk, MapEnd, MapReject

from .lookup import GridMap

__all__ = ["MapStore", "StoreEvent"]


@dataclass(frozen=True)
class StoreEvent:
    """Something the operator or the center should hear about."""

    time_s: float
    kind: str  # "applied", "rejected", "expired"
    version: int
    text: str


class MapStore:
    """Map memory of one machine.

    Parameters
    ----------
    machine : str
        This machine's name.
    axes : sequence of str
        This machine's axis names (maps may only use these).
    accepted : MapEncoding
        Encodings the controller takes.
    limit_mm : float
        Largest compensation magnitude the controller accepts, mm (degrees).
    max_bytes : int
        Staging memory.
    """

    def __init__(self, machine: str, axes: Sequence[str], *, accepted: MapEncoding,
                 limit_mm: float, max_bytes: int = MAX_MAP_BYTES) -> None:
        self.machine = machine
        self.axes = tuple(a.upper() for a in axes)
        self.limit_mm = float(limit_mm)
        self.assembler = MapAssembler(machine, accepted, max_bytes)
        self.active: GridMap | None = None
        self.applied_at_s: float | None = None
        self.events: list[StoreEvent] = []

    def feed(self, msg: MapBegin | MapChunk | MapEnd, now_s: float
             ) -> MapAck | MapReject | None:
        """Take one map message; at MapEnd apply the map or keep the old one.

        Returns
        -------
        MapAck, MapReject or None
            The reply to send (None until MapEnd).
        """
        verdict = self.assembler.feed(msg)
        if verdict is None:
            return None
        if isinstance(verdict, MapAccepted):
            problem = self.check(verdict.payload)
            if problem is None:
                self.active = GridMap.from_payload(verdict.payload)  # the one-step swap
                self.applied_at_s = now_s
                self.assembler.applied_version = verdict.version
                self.events.append(StoreEvent(now_s, "applied", verdict.version, ""))
                return verdict.ack()
            verdict = MapRejected(verdict.version, MapRejectReason.APPLY_FAILED, problem)
        self.events.append(StoreEvent(now_s, "rejected", verdict.version, verdict.text))
        return verdict.message()

    def check(self, p: ErrorMapPayload) -> str | None:
        """Why this controller refuses an otherwise valid map, or None."""
        for ga in p.grid:
            if ga.name.upper() not in self.axes:
                return (f"map grid axis {ga.name!r} is not an axis of {self.machine} "
                        f"({' '.join(self.axes)})")
        for o in p.outputs:
            if o.name.upper() not in self.axes:
                return (f"map output axis {o.name!r} is not an axis of {self.machine} "
                        f"({' '.join(self.axes)})")
        g = GridMap.from_payload(p)
        bad = np.flatnonzero(np.abs(g.values) > self.limit_mm)
        if bad.size:
            node, k = divmod(int(bad[0]), len(g.outputs))
            index = np.unravel_index(node, tuple(g.count.tolist()))
            return (f"map value {g.values.flat[bad[0]]:.6g} mm for axis {g.outputs[k]} at "
                    f"node {tuple(int(i) for i in index)} exceeds the controller's "
                    f"±{self.limit_mm:g} mm")
        big = np.flatnonzero(np.abs(g.reversal) > self.limit_mm)
        if big.size:
            return (f"map reversal {g.reversal[big[0]]:.6g} mm for axis "
                    f"{g.outputs[int(big[0])]} exceeds ±{self.limit_mm:g} mm")
        return None

    def expired(self, now_s: float) -> bool:
        """The active map has a validity and it has run out."""
        return (self.active is not None and self.active.valid_s > 0
                and self.applied_at_s is not None
                and now_s - self.applied_at_s >= self.active.valid_s)

    def drop(self, now_s: float, why: str) -> None:
        """Forget the active map (after a release or expiry ramp)."""
        if self.active is not None:
            self.events.append(StoreEvent(now_s, why, self.active.version, ""))
        self.active = None
        self.applied_at_s = None

    @property
    def version(self) -> int:
        """Version of the map in use, 0 for none."""
        return 0 if self.active is None else self.active.version
