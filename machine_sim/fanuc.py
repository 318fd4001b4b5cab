"""A Fanuc-style controller: PMC R memory and a ladder scan driving EMZPS.

The ladder (one :meth:`FanucPMC.scan` every ``scan_s``, 8 ms by default) reads the machine
coordinates, looks the compensation up in the stored map (:mod:`machine_sim.controller`),
converts it to integer increments (``increment_mm``, 0.001 mm for IS-B), clamps it to the
external machine zero point shift's range (``±limit_counts``) and writes it to the R
addresses the EMZPS function reads. A change larger than ``max_step_counts`` in one scan
is split over several scans (``on_jump="ramp"``), or latches an alarm and holds the shift
(``on_jump="alarm"``) until :meth:`FanucPMC.reset_alarm`.

Factored maps (format version 5, protocol/README.md §6.5): the ladder looks its 1-D
tables up, multiplies and adds them into the correction and sensitivity fields, and rounds
the rotary corrections first, letting the linear axes absorb what that rounding leaves
(:class:`machine_sim.lookup.FactoredLadder`); it declares ``MapEncoding.FACTORED``.

Thermal records (grid maps of format version 3, protocol/README.md §6.4): the ladder keeps
per output a constant and a slope, recomputed when a temperature arrives (the center's
Temperatures messages), and adds ``constant + slope · position`` to the looked-up value
every scan before rounding to increments: multiply-add only. It declares
``INT32_INCREMENTS | THERMAL`` in Hello (``FanucConfig.thermal_records``).

R address layout (offsets from ``r_base``, default R7000; multi-byte values
little-endian, as PMC memory is)::

    R+0   .. R+31   int32 × 8   EMZPS shift of controlled axis 1..8, increments
    R+32            u8          status: bit 0 map in use, bit 1 ramping (shift not yet at
                                target), bit 2 releasing, bit 3 alarm, bit 4 clamped
                                (a target exceeded the range), bit 5 map expired
    R+33            u8          alarm code: 0 none, 1 jump exceeds max_step_counts
    R+34  .. R+35   reserved
    R+36            u32         version of the map in use (0 none)
    R+40            u32         scan counter
    R+44  .. R+75   int32 × 8   machine coordinate read by the scan, increments
    R+76  .. R+107  int32 × 8   target shift before rate limiting, increments

Controlled axis k is the machine's k-th axis (``Machine.axes`` order).
"""

from __future__ import annotations

import math
import struct
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from protocol.codes import MapEncoding

from .controller import Compensator
from .mapstore import MapStore
from .temperatures import JUMP_ALLOWANCE_K, MAX_RATE_K_PER_S, PLAUSIBLE_C, TemperatureStore

__all__ = ["ALARM_JUMP", "FanucConfig", "FanucPMC", "RLayout"]

F64 = NDArray[np.float64]
ALARM_JUMP = 1
MAX_AXES = 8


@dataclass(frozen=True)
class RLayout:
    """Offsets (bytes from ``base``) of the R addresses; see the module docstring."""

    base: int = 7000
    shift: int = 0
    status: int = 32
    alarm: int = 33
    version: int = 36
    counter: int = 40
    position: int = 44
    target: int = 76
    size: int = 108


@dataclass(frozen=True)
class FanucConfig:
    """Ladder and EMZPS settings.

    Attributes
    ----------
    scan_s : float
        Ladder scan period, s.
    increment_mm : float
        Least input increment, mm per count.
    limit_counts : int
        EMZPS range: shifts are clamped to ±limit_counts.
    max_step_counts : int
        Largest change of a shift in one scan.
    on_jump : {"ramp", "alarm"}
    r_size : int
        Bytes of R memory (R0 .. R<r_size - 1>).
    layout : RLayout
    expiry_ramp_s : float
    thermal_records : bool
        The ladder applies the thermal records of grid maps (declares
        ``MapEncoding.THERMAL``); False: a ladder that takes version-1 grids only.
    factored : bool
        The ladder evaluates factored maps (declares ``MapEncoding.FACTORED``); False: an
        older ladder that takes grids only.
    stale_after_s : float
        A temperature older than this is stale, s (machine time): the thermal part holds
        its last good value.
    plausible_C : (float, float)
        Temperatures outside are refused, °C.
    max_temp_rate_K_per_s, temp_jump_allowance_K : float
        A temperature further from its sensor's last good one than the rate times the
        time between them plus the allowance is refused (as on the Siemens-style NC).
    """

    scan_s: float = 0.008
    increment_mm: float = 0.001
    limit_counts: int = 500
    max_step_counts: int = 5
    on_jump: Literal["ramp", "alarm"] = "ramp"
    r_size: int = 8000
    layout: RLayout = RLayout()
    expiry_ramp_s: float = 2.0
    thermal_records: bool = True
    factored: bool = True
    stale_after_s: float = 60.0
    plausible_C: tuple[float, float] = PLAUSIBLE_C
    max_temp_rate_K_per_s: float = MAX_RATE_K_PER_S
    temp_jump_allowance_K: float = JUMP_ALLOWANCE_K

    def __post_init__(self) -> None:
        if self.on_jump not in ("ramp", "alarm"):
            raise ValueError(f"on_jump must be 'ramp' or 'alarm', got {self.on_jump!r}")
        if not (self.scan_s > 0 and self.increment_mm > 0 and self.limit_counts > 0
                and self.max_step_counts > 0):
            raise ValueError("scan_s, increment_mm, limit_counts and max_step_counts must "
                             "be > 0")
        if self.layout.base + self.layout.size > self.r_size:
            raise ValueError(f"R layout R{self.layout.base}..R"
                             f"{self.layout.base + self.layout.size - 1} does not fit R "
                             f"memory of {self.r_size} bytes")


class FanucPMC(Compensator):
    """A Fanuc-style machine's PMC with its compensation ladder.

    Parameters
    ----------
    machine : str
        Machine name (maps must name it).
    axes : sequence of str
        Controlled axes in order (at most 8).
    config : FanucConfig
    """

    def __init__(self, machine: str, axes: Sequence[str], config: FanucConfig | None = None
                 ) -> None:
        self.config = config or FanucConfig()
        if not 1 <= len(axes) <= MAX_AXES:
            raise ValueError(f"a Fanuc path has 1 to {MAX_AXES} axes here, got {len(axes)}")
        c = self.config
        # a ladder has no trigonometry: grid and factored maps (lookups, multiplies and
        # adds), never tables; thermal records need only a multiply-add per output
        accepted = MapEncoding.INT32_INCREMENTS
        if c.thermal_records:
            accepted |= MapEncoding.THERMAL
        if c.factored:
            accepted |= MapEncoding.FACTORED
        store = MapStore(machine, axes, accepted=accepted,
                         limit_mm=c.limit_counts * c.increment_mm, integer_ladder=True)
        super().__init__(axes, store, expiry_ramp_s=c.expiry_ramp_s)
        self.temperatures = TemperatureStore(
            c.stale_after_s, plausible_C=c.plausible_C,
            max_rate_K_per_s=c.max_temp_rate_K_per_s, jump_allowance_K=c.temp_jump_allowance_K)
        self.r = bytearray(c.r_size)
        self.scans = 0
        self._expired_seen = False

    # -- R memory access
    def _addr(self, offset: int, k: int = 0) -> int:
        return self.config.layout.base + offset + 4 * k

    def read_i32(self, address: int) -> int:
        """R<address> .. R<address+3> as a little-endian int32."""
        value: int = struct.unpack_from("<i", self.r, address)[0]
        return value

    def shifts(self) -> NDArray[np.int64]:
        """EMZPS shift per axis, increments."""
        return np.array(self._shift_list(), dtype=np.int64)

    def _shift_list(self) -> list[int]:
        return list(struct.unpack_from(f"<{len(self.axes)}i", self.r,
                                       self._addr(self.config.layout.shift)))

    def applied_mm(self) -> F64:
        return np.asarray(self.shifts() * self.config.increment_mm, dtype=np.float64)

    @property
    def status(self) -> int:
        return self.r[self._addr(self.config.layout.status)]

    @property
    def alarm(self) -> int:
        return self.r[self._addr(self.config.layout.alarm)]

    def reset_alarm(self) -> None:
        """Operator reset: clear the alarm; the next scan moves on again."""
        self.r[self._addr(self.config.layout.alarm)] = 0

    @property
    def state(self) -> str:
        """Telemetry label: ``alarm``, ``releasing``, ``ramping``, ``compensating``, ``idle``."""
        s = self.status
        if s & 8:
            return "alarm"
        if s & 4:
            return "releasing"
        if s & 2:
            return "ramping"
        return "compensating" if s & 1 else "idle"

    # -- the ladder
    def scan(self, now_s: float, positions: Mapping[str, float] | F64,
             directions: Mapping[str, int] | NDArray[np.integer] | None = None
             ) -> NDArray[np.int64]:
        """One ladder scan; returns the EMZPS shifts now in R (increments)."""
        c, lay = self.config, self.config.layout
        pos = self._vector(positions, float)
        wanted = self.wanted_mm(now_s, pos, directions)
        if self.store.active is None and not self.releasing and self.store.events and \
                self.store.events[-1].kind == "expired":
            self._expired_seen = True
        if self.store.active is not None:
            self._expired_seen = False
        # one axis at a time in Python numbers: a scan has one point, where array calls
        # cost more than their arithmetic; each step is the IEEE operation the array form
        # did (a division, an add, a floor), so the integers are the same
        inc, lim, most = c.increment_mm, c.limit_counts, c.max_step_counts
        # halves up, the one tie rule of protocol/README.md §6 (np.rint would round a half
        # to even)
        target = [math.floor(w / inc + 0.5) for w in wanted.tolist()]
        clamped = any(abs(t) > lim for t in target)
        target = [min(max(t, -lim), lim) for t in target]
        current = self._shift_list()
        delta = [t - cur for t, cur in zip(target, current, strict=True)]
        if self.alarm:
            new = current
        elif c.on_jump == "alarm" and not self.releasing and any(abs(d) > most for d in delta):
            self.r[self._addr(lay.alarm)] = ALARM_JUMP
            new = current
        else:
            new = [cur + min(max(d, -most), most) for cur, d in zip(current, delta, strict=True)]
        n = len(self.axes)
        struct.pack_into(f"<{n}i", self.r, self._addr(lay.shift), *new)
        struct.pack_into(f"<{n}i", self.r, self._addr(lay.target), *target)
        struct.pack_into(f"<{n}i", self.r, self._addr(lay.position),
                         *[math.floor(q / inc + 0.5) for q in pos.tolist()])
        status = (1 if self.store.active is not None else 0)
        status |= 2 if new != target else 0
        status |= 4 if self.releasing else 0
        status |= 8 if self.alarm else 0
        status |= 16 if clamped else 0
        status |= 32 if self._expired_seen else 0
        self.r[self._addr(lay.status)] = status
        struct.pack_into("<I", self.r, self._addr(lay.version), self.store.version)
        self.scans += 1
        struct.pack_into("<I", self.r, self._addr(lay.counter), self.scans & 0xFFFFFFFF)
        return np.array(new, dtype=np.int64)
