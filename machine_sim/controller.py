"""What every simulated controller does with a map, before its own personality.

Per cycle the controller wants a compensation per axis (mm, degrees for rotary axes):

* with a map in use: the map looked up at the current (commanded, uncompensated) machine
  coordinates of its grid axes (:mod:`machine_sim.lookup`), on its output axes (a tables
  map: evaluated through the chain at the coordinates of its chain axes and the latest
  temperatures, :mod:`machine_sim.chaineval`; a grid with thermal records adds their
  corrections at the latest temperatures, :class:`machine_sim.lookup.GridMap`); the values
  are the corrections for a positive approach, so while an output axis last moved in the
  negative direction its reversal value is added (protocol/README.md section 6: reversal =
  negative-approach minus positive-approach correction; a backlash of ``-(B/2)·d`` in
  :mod:`machine_sim.effects` needs the reversal ``-B``);
* while releasing (ReleaseCompensation, or the map's validity ran out): the compensation
  applied when the release began, ramped linearly to zero over the ramp time; at the end
  the map is dropped (map version 0), and an asked-for release counts one Released to send;
* otherwise zero.

A map applied during a release ends the release at once (its Released is still owed): the
new map is the operator's latest word. Personalities (:mod:`machine_sim.fanuc`,
:mod:`machine_sim.siemens`) turn the wanted value into what their NC applies.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from protocol.messages import MapAck, MapBegin, MapChunk, MapEnd, MapReject

from .lookup import ActiveMap
from .mapstore import MapStore
from .temperatures import TemperatureStore

__all__ = ["Compensator"]

F64 = NDArray[np.float64]


@dataclass
class _Release:
    start_s: float
    ramp_s: float
    snapshot: F64
    asked: bool  # ReleaseCompensation (True) or expiry (False)


class Compensator:
    """Map handling shared by the personalities.

    Parameters
    ----------
    axes : sequence of str
        The controller's axes in its own order (upper case names).
    store : MapStore
    expiry_ramp_s : float
        Ramp time to zero when a map expires.
    """

    def __init__(self, axes: Sequence[str], store: MapStore, *, expiry_ramp_s: float = 2.0
                 ) -> None:
        self.axes = tuple(a.upper() for a in axes)
        self.store = store
        self.expiry_ramp_s = float(expiry_ramp_s)
        self._release: _Release | None = None
        self.released_owed = 0
        self.now_s = 0.0
        self.temperatures = TemperatureStore()
        """Latest temperatures (own sensors or the center's Temperatures), read each cycle."""
        self._folded_s = float("-inf")  # updated_s of the readings folded into the map
        self._axes_of: tuple[ActiveMap, list[int], list[int]] | None = None

    # -- to be provided by the personality
    def applied_mm(self) -> F64:
        """Compensation the NC applies now, per axis, mm."""
        raise NotImplementedError

    # -- map messages and commands
    def feed_map(self, msg: MapBegin | MapChunk | MapEnd, now_s: float
                 ) -> MapAck | MapReject | None:
        """A map message from the center; returns the reply to send, if any."""
        reply = self.store.feed(msg, now_s)
        if isinstance(reply, MapAck) and self._release is not None:
            if self._release.asked:
                self.released_owed += 1
            self._release = None
        return reply

    def set_temperatures(self, temperatures: Mapping[str, float]) -> None:
        """Fold temperatures (°C by sensor label) into the map's thermal records now;
        the cycle does it by itself from :attr:`temperatures` whenever those change."""
        self.store.set_temperatures(temperatures)

    def release(self, now_s: float, ramp_s: float) -> None:
        """Ramp the applied compensation linearly to zero over ``ramp_s``, then drop the map."""
        if self._release is not None and self._release.asked:
            self.released_owed += 1  # the earlier release is superseded, still answered
        self._release = _Release(now_s, max(float(ramp_s), 0.0), self.applied_mm().copy(),
                                 True)

    @property
    def releasing(self) -> bool:
        return self._release is not None

    def take_released(self) -> int:
        """How many Released messages are now owed (and forget them)."""
        n, self.released_owed = self.released_owed, 0
        return n

    # -- the per-cycle computation
    def wanted_mm(self, now_s: float, positions: Mapping[str, float] | F64,
                  directions: Mapping[str, int] | NDArray[np.integer] | None = None) -> F64:
        """The compensation wanted now per axis (module docstring), mm.

        Parameters
        ----------
        now_s : float
            Controller time, s.
        positions : mapping of axis name to float, or ndarray (n_axes,)
            Current machine coordinates (mm, degrees).
        directions : mapping or ndarray (n_axes,) of -1, 0, +1, optional
            Last direction of motion per axis (for the reversal value); none = positive.
        """
        self.now_s = now_s
        pos = self._vector(positions, float)
        if self.store.expired(now_s) and self._release is None:
            self._release = _Release(now_s, self.expiry_ramp_s, self.applied_mm().copy(), False)
        if self._release is not None:
            r = self._release
            frac = 1.0 if r.ramp_s <= 0 else (now_s - r.start_s) / r.ramp_s
            if frac >= 1.0:
                self.store.drop(now_s, "released" if r.asked else "expired")
                if r.asked:
                    self.released_owed += 1
                self._release = None
                return np.zeros(len(self.axes))
            out: F64 = r.snapshot * (1.0 - frac)
            return out
        if self.temperatures.updated_s != self._folded_s:
            # new readings (own sensors or the center's): refold the map's thermal records
            self._folded_s = self.temperatures.updated_s
            self.store.set_temperatures(self.temperatures.values(now_s))
        m = self.store.active
        wanted = np.zeros(len(self.axes))
        if m is None:
            return wanted
        at = getattr(m, "lookup_directed_at", None)
        if at is not None:
            # one point in Python numbers (a scan's case; the same values as below)
            ins, outs = self._map_axes(m)
            p = pos.tolist()
            if directions is None:
                neg = [False] * len(outs)
            else:
                dl = self._vector(directions, float).tolist()
                neg = [dl[i] < 0 for i in outs]
            for i, v in zip(outs, at([p[i] for i in ins], neg), strict=True):
                wanted[i] = v
            return wanted
        q = np.array([pos[self.axes.index(g)] for g in m.inputs])
        dirs = (np.zeros(len(self.axes)) if directions is None
                else self._vector(directions, float))
        negative = np.array([dirs[self.axes.index(name)] < 0 for name in m.outputs])
        directed = getattr(m, "lookup_directed", None)
        if directed is not None:
            # a map with its own limits (factored, §6.5 step 6): the reversal goes in
            # before its final clamp, so the applied value never exceeds the limit
            values = directed(q[None, :], negative[None, :])[0]
            for k, name in enumerate(m.outputs):
                wanted[self.axes.index(name)] = values[k]
            return wanted
        values = m.lookup(q[None, :])[0]
        for k, name in enumerate(m.outputs):
            wanted[self.axes.index(name)] = values[k] + (m.reversal[k] if negative[k]
                                                         else 0.0)
        return wanted

    def _map_axes(self, m: ActiveMap) -> tuple[list[int], list[int]]:
        """The controller's index of each of the map's inputs and outputs (kept while
        the map is in use)."""
        held = self._axes_of
        if held is None or held[0] is not m:
            held = (m, [self.axes.index(g) for g in m.inputs],
                    [self.axes.index(name) for name in m.outputs])
            self._axes_of = held
        return held[1], held[2]

    def _vector(self, values: Mapping[str, float] | Mapping[str, int] | NDArray[np.generic],
                kind: type[float]) -> F64:
        if isinstance(values, Mapping):
            out = np.zeros(len(self.axes))
            for k, v in values.items():
                key = k.upper()
                if key not in self.axes:
                    raise ValueError(f"no axis {k!r} on this controller ({' '.join(self.axes)})")
                out[self.axes.index(key)] = kind(v)
            return out
        arr = np.asarray(values, dtype=float)
        if arr.shape != (len(self.axes),):
            raise ValueError(f"expected {len(self.axes)} values for axes {self.axes}, "
                             f"got shape {arr.shape}")
        return arr
