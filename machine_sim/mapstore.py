"""The machine's map memory: staging, the swap rule, the last good map, validity.

Pushed map messages go through :class:`protocol.maptransfer.MapAssembler` (whole, in
order, checksum, decodes, this machine, an accepted encoding). A map that passes those
must then suit this controller, or it is refused with ``APPLY_FAILED`` and a text naming
the problem:

* every grid dimension and every output is an axis of this machine;
* every value (and reversal) is within ``±limit_mm``: the range the controller's
  compensation channel can hold (EMZPS range, SD43900 limit);
* a tables map: every chain axis is an axis of this machine, every reversal within
  ``±limit_mm``, and the map evaluates to finite corrections at the centre and the
  corners of the travel (a probe of its tables, thermal records and solve). Its
  corrections are clamped to the smaller of the map's limits and ``limit_mm``.

A map of either kind is kept as :data:`~machine_sim.lookup.ActiveMap`; a map with thermal
records (tables, or a grid of format version 3) folds in the latest temperatures
(:meth:`MapStore.set_temperatures`) before it is swapped in, and again whenever they
change.

Only then does the store swap to the new map, in one assignment between two scans. On
any rejection the map in use stays as it was.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from protocol.codes import MapEncoding, MapRejectReason
from protocol.limits import MAX_MAP_BYTES
from protocol.mapfactored import FactoredPayload
from protocol.mapformat import ErrorMapPayload
from protocol.maptables import TablesPayload
from protocol.maptransfer import MapAccepted, MapAssembler, MapRejected
from protocol.messages import MapAck, MapBegin, MapChunk, MapEnd, MapReject

from .chaineval import StructureError
from .lookup import ActiveMap, FactoredLadder, GridLadder, GridMap, TablesMap

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
    integer_ladder : bool
        Evaluate int32 grid maps with the PMC ladder's integer arithmetic
        (:class:`~machine_sim.lookup.GridLadder`), as the Fanuc-style machine does.
    """

    def __init__(self, machine: str, axes: Sequence[str], *, accepted: MapEncoding,
                 limit_mm: float, max_bytes: int = MAX_MAP_BYTES,
                 integer_ladder: bool = False) -> None:
        self.integer_ladder = integer_ladder
        self.machine = machine
        self.axes = tuple(a.upper() for a in axes)
        self.limit_mm = float(limit_mm)
        self.assembler = MapAssembler(machine, accepted, max_bytes)
        self.active: ActiveMap | None = None
        self.applied_payload: ErrorMapPayload | TablesPayload | FactoredPayload | None = None
        """The active map as decoded from the bytes pushed (before this controller's
        clamp of a factored map's limits); None with no map."""
        self.applied_at_s: float | None = None
        self.events: list[StoreEvent] = []
        self.temperatures: dict[str, float] = {}

    def set_temperatures(self, temperatures: Mapping[str, float]) -> None:
        """The latest temperatures (°C by sensor label); sensors not named keep theirs."""
        self.temperatures.update({k: float(v) for k, v in temperatures.items()})
        if self.active is not None:  # either kind may carry thermal records
            self.active.set_temperatures(self.temperatures)

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
            p = verdict.payload
            built: ActiveMap
            factored: FactoredLadder | None = None
            if isinstance(p, ErrorMapPayload):
                problem = self.check(p)
                if problem is None and self.integer_ladder:
                    try:  # the integer ladder needs start and step in whole counts
                        ladder_grid = GridLadder.from_payload(p)
                    except ValueError as exc:
                        problem = f"map does not suit the integer ladder: {exc}"
            elif isinstance(p, FactoredPayload):
                p = self._clamped_factored(p)
                problem, factored = self.check_factored(p)
            else:
                problem = self.check_tables(p)
            if problem is None:
                if isinstance(p, ErrorMapPayload) and self.integer_ladder:
                    built = ladder_grid
                    built.set_temperatures(self.temperatures)
                elif isinstance(p, ErrorMapPayload):
                    built = GridMap.from_payload(p, self.temperatures)
                elif isinstance(p, FactoredPayload):
                    assert factored is not None  # what the check built
                    built = factored
                else:
                    built = TablesMap.from_payload(self._clamped(p), self.temperatures)
                self.active = built  # the one-step swap, after everything is built
                self.applied_payload = verdict.payload
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

    def _clamped(self, p: TablesPayload) -> TablesPayload:
        return dataclasses.replace(p, limit_mm=min(p.limit_mm, self.limit_mm),
                                   limit_deg=min(p.limit_deg, self.limit_mm))

    def check_tables(self, p: TablesPayload) -> str | None:
        """Why this controller refuses an otherwise valid tables map, or None."""
        for a in p.axes:
            if a.name.upper() not in self.axes:
                return (f"map chain axis {a.name!r} is not an axis of {self.machine} "
                        f"({' '.join(self.axes)})")
        scale = p.increment_mm if p.encoding is MapEncoding.INT32_INCREMENTS else 1.0
        for o in p.outputs:
            if o.reversal is not None and abs(o.reversal * scale) > self.limit_mm:
                return (f"map reversal {o.reversal * scale:.6g} for axis {o.name} exceeds "
                        f"the controller's ±{self.limit_mm:g}")
        # probe: the centre and every corner of the travel (at most 2^6 corners)
        travel = [a.travel for a in p.axes]
        probes = [[0.5 * (lo + hi) for lo, hi in travel]]
        if len(travel) <= 6:
            probes += [list(c) for c in itertools.product(*travel)]
        try:
            dq = TablesMap.from_payload(p, self.temperatures).corrections(np.array(probes))
        except (StructureError, ValueError, FloatingPointError) as exc:
            return f"map does not evaluate: {exc}"
        if not np.all(np.isfinite(dq)):
            return "map evaluates to non-finite corrections within the travel"
        return None

    def _clamped_factored(self, p: FactoredPayload) -> FactoredPayload:
        """Each axis's limit at most what this controller's channel holds."""
        cap = max(1, int(self.limit_mm / p.increment_mm + 1e-9))
        return dataclasses.replace(p, axes=tuple(
            dataclasses.replace(a, limit=min(a.limit, cap)) for a in p.axes))

    def check_factored(self, p: FactoredPayload) -> tuple[str | None, FactoredLadder | None]:
        """Why this controller refuses an otherwise valid factored map (None if it does
        not), and the ladder built from it (None if refused), with the current
        temperatures: the map goes into use as built here, not built a second time.
        Refused: an axis that is not this machine's (axes are matched by name, never by
        place: protocol/README.md §6.6) or a reversal over the limit.

        Unlike a tables map (float arithmetic, probed for non-finite corrections), a
        factored map is evaluated in integers whose word sizes its decode has checked
        (§6 "Ranges and word sizes"): nothing in it can become non-finite, so there is
        nothing to probe (the fields at the span's corners, turned into floats, are
        always finite: such a probe could not refuse and cost the simulated PMC 0.4 ms
        of CPU a map)."""
        for a in p.axes:
            if a.name.upper() not in self.axes:
                return (f"map axis {a.name!r} is not an axis of {self.machine} "
                        f"({' '.join(self.axes)})"), None
        for a in p.axes:
            if a.reversal is not None and abs(a.reversal * p.increment_mm) > self.limit_mm:
                return (f"map reversal {a.reversal * p.increment_mm:.6g} for axis {a.name} "
                        f"exceeds the controller's ±{self.limit_mm:g}"), None
        return None, FactoredLadder(p, self.temperatures)

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
        self.applied_payload = None
        self.applied_at_s = None

    @property
    def version(self) -> int:
        """Version of the map in use, 0 for none."""
        return 0 if self.active is None else self.active.version
