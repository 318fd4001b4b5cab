"""The ``factored`` map payload (format version 5): sums of products of 1-D tables, for
endpoints that only look up, multiply, shift and add in integers (a Fanuc PMC ladder;
protocol/README.md §6.5 gives the per-scan arithmetic bit for bit).

Every field is an integer: positions, starts, limits and reversals in counts of the
increment (``1 / counts_per_unit`` mm, or degrees on a rotary axis); every table's node
spacing a power of two in counts (so the index is a shift); table values int16 (basis
tables in Q14, term tables times ``2^exponent``); thermal records in binary fixed point.
Every multi-byte field is little-endian, as in the other map kinds. Layout::

    offset   size  field
         0      4  magic b"EDMP"
         4      2  format version u16 = 5
         6      1  value encoding u8 = 1 (int32 increments: the endpoint rounds to them)
         7      1  axes D, 1..8 (the machine's axes in its order: inputs and outputs)
         8      1  basis tables B, 0..254
         9      1  thermal records H, 0..32
        10      2  terms T u16, 1..4096
        12      4  counts_per_unit P u32 >= 1: counts per mm (per degree on a rotary axis)
        16     32  machine name, ASCII, NUL-padded
        48      4  map version u32 (>= 1)
        52      4  valid_s u32 (0 = no limit)
        56      8  reserved, zero
        64  20 D  axes, each: name 4 ASCII NUL-padded; flags u8 (bit 0 rotary, bit 1 has a
                   reversal value); shift k u8 (0..24: term node spacing 2^k counts); term
                   nodes n u16 (1..4096); start i32 counts; reversal i32 counts (0 when
                   absent); limit i32 counts (> 0)
    then B basis tables, each 8 + 2 n bytes: axis u8 (< D); shift k u8 (0..24); nodes n
                   u16 (1..4096); start i32 counts; n values int16, Q14 (|v| <= 2^14)
    then T terms, each 8 + 2 n bytes: field u8; axis u8 (< D); exponent i8 (-60..8);
                   m u8 (bits 0-2: factors 0..4; bit 7: a constant, n = 1; others 0);
                   4 basis indices u8 (the first m < B, the rest 0xFF); n values int16
                   (|v| < 2^15): n = the term nodes of its axis, or 1 for a constant
    then H thermal records, each 32 bytes: sensor 16 (the name the Temperatures message
                   carries, printable ASCII, NUL-padded); axis u8 (a linear axis < D);
                   kind u8 (1 drift, 2 expansion); reserved 2 zero; coefficient i32
                   (drift: 2^-32 counts per m°C; expansion: 2^-48 counts per count per
                   m°C); t_ref i32 (m°C); q_min i32 (counts; 0 for a drift)

Nothing follows; the length is exactly what the header, axes and tables describe. Fields:
``0 .. D-1`` the correction of each axis (counts); then, for each linear axis ``l`` (in
axis order, slowest) and rotary axis ``r``, field ``D + l·R + r`` (``l``, ``r`` counted
among the linear and rotary axes, R rotary axes): the sensitivity ``S_lr``, counts of
linear axis l per count of rotary axis r.
"""

from __future__ import annotations

import math
import re
import struct
from dataclasses import dataclass
from fractions import Fraction
from typing import Final

from . import _check as check
from .codes import MapEncoding
from .limits import MAX_LABEL_BYTES, MAX_NAME_BYTES
from .mapformat import (
    _AXIS_RE,
    MAP_MAGIC,
    MAX_THERMAL,
    THERMAL_DRIFT,
    THERMAL_EXPANSION,
    ErrorMapPayload,
    MapFormatError,
    ThermalRecord,
    _name_field,
    _name_from,
)

FACTORED_FORMAT_VERSION: Final = 5
RETIRED_FACTORED_VERSION: Final = 4
"""Format version 4 (f64 grids, int32 values, no fixed-point rules) is refused by name."""
MAX_AXES: Final = 8
MAX_BASES: Final = 254
MAX_TERMS: Final = 4096
MAX_NODES: Final = 4096
MAX_FACTORS: Final = 4
MAX_SHIFT: Final = 24
BASIS_ONE: Final = 1 << 14
"""Basis values are Q14: 2^14 is 1.0, the largest magnitude allowed."""
VALUE_LIMIT: Final = 1 << 15
"""Term values are int16 with |v| < 2^15 (−32768 excluded, so negation never overflows)."""
EXPONENT_RANGE: Final = (-60, 8)
"""Term exponents: a value times 2^(e+1) stays within 2^39, a shift below 63 bits."""
DRIFT_SHIFT: Final = 32
"""A drift record's coefficient is in 2^-32 counts per m°C."""
EXPANSION_SHIFT: Final = 48
"""An expansion record's coefficient is in 2^-48 counts per count per m°C."""
NO_FACTOR: Final = 0xFF

_HEAD = struct.Struct("<4sHBBBBHI32sII8s")  # 64 bytes
_AXIS = struct.Struct("<4sBBHiii")  # 20 bytes
_BASIS = struct.Struct("<BBHi")  # 8 bytes
_TERM = struct.Struct("<BBbB4B")  # 8 bytes
_THERMAL = struct.Struct("<16sBB2siii")  # 32 bytes
_LABEL = re.compile(r"[\x21-\x7e]{1,16}")
_I32 = (-(1 << 31), (1 << 31) - 1)
_I30 = (-(1 << 30) + 1, (1 << 30) - 1)
"""|·| < 2^30: starts, limits, reversals, a table's last node, t_ref, q_min (§6 "Ranges
and word sizes": so that ``q − start`` < 2^31 and every product fits 64 bits)."""
EXPANSION_LIMIT: Final = 1 << 24
"""|expansion coefficient| < 2^24 (2^-48 counts per count per m°C: 60 µm/(m·K))."""


def round_half_up(x: Fraction) -> int:
    """The tie rule of every map kind (protocol/README.md §6): the integer nearest ``x``,
    halves rounded up (towards +infinity), ``floor(x + 1/2)``."""
    return (x + Fraction(1, 2)).__floor__()


def milli_celsius(celsius: float) -> int:
    """A reading in °C as int32 m°C (protocol/README.md §6, "Temperatures"):
    ``round_half_up(celsius · 1000)`` of the **exact** value the f64 stands for, not of
    the product rounded to a double (20.0005 °C is stored as 20.000499999…, so 20000).

    Raises
    ------
    ValueError
        ``celsius`` is not finite.
    """
    c = float(celsius)
    if not math.isfinite(c):
        raise ValueError(f"temperature {celsius!r} °C is not finite")
    return round_half_up(Fraction(c) * 1000)


def _int(what: str, v: object, lo: int, hi: int) -> None:
    ok = type(v) is int or (isinstance(v, int) and not isinstance(v, bool))  # plain int first
    if not ok or not lo <= v <= hi:  # type: ignore[operator]
        raise ValueError(f"{what} must be an int in {lo}..{hi}, got {v!r}")


def _values(what: str, values: tuple[int, ...], bound: int, n: int | None = None) -> None:
    if not isinstance(values, tuple) or not values:
        raise ValueError(f"{what} values must be a non-empty tuple of ints")
    if n is not None and len(values) != n:
        raise ValueError(f"{what} has {len(values)} values, its axis grid has {n} nodes")
    if len(values) > MAX_NODES:
        raise ValueError(f"{what} has {len(values)} values, at most {MAX_NODES}")
    # the common case checked in C loops (a decode makes thousands of these); a value
    # that fails it is found and named below (bool is not taken for an int)
    if _INT.issuperset(map(type, values)) and -bound <= min(values) and max(values) <= bound:
        return
    for i, v in enumerate(values):
        if not isinstance(v, int) or isinstance(v, bool) or not -bound <= v <= bound:
            raise ValueError(f"{what} value {i} must be an int with |v| <= {bound}, "
                             f"got {v!r}")


_INT: Final = frozenset({int})


@dataclass(frozen=True, slots=True)
class FactoredAxis:
    """One machine axis of a factored map: flags, reversal and limit in counts, and the
    grid of its term tables (``count`` nodes from ``start`` counts, spacing ``2^shift``
    counts)."""

    name: str
    rotary: bool
    reversal: int | None
    limit: int
    count: int
    start: int
    shift: int

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _AXIS_RE.fullmatch(self.name):
            raise ValueError(f"axis name must be 1 to 4 ASCII letters/digits starting with "
                             f"a letter, got {self.name!r}")
        if not isinstance(self.rotary, bool):
            raise ValueError(f"axis {self.name} rotary must be a bool")
        if self.reversal is not None:
            _int(f"axis {self.name} reversal", self.reversal, *_I30)
        _int(f"axis {self.name} limit", self.limit, 1, _I30[1])
        _int(f"axis {self.name} term nodes", self.count, 1, MAX_NODES)
        _int(f"axis {self.name} start", self.start, *_I30)
        _int(f"axis {self.name} shift", self.shift, 0, MAX_SHIFT)
        _int(f"axis {self.name} last term node", self.start + ((self.count - 1) << self.shift),
             *_I30)


@dataclass(frozen=True, slots=True)
class BasisTable:
    """A shared factor: ``values[i] / 2^14`` at ``start + i·2^shift`` counts of axis
    ``axis``."""

    axis: int
    start: int
    shift: int
    values: tuple[int, ...]

    def __post_init__(self) -> None:
        _int("basis table axis", self.axis, 0, MAX_AXES - 1)
        _int("basis table start", self.start, *_I30)
        _int("basis table shift", self.shift, 0, MAX_SHIFT)
        _values("basis table", self.values, BASIS_ONE)
        _int("basis table last node", self.start + ((len(self.values) - 1) << self.shift),
             *_I30)


@dataclass(frozen=True, slots=True)
class TermTable:
    """One term: ``values[i] · 2^exponent`` on its axis's term grid (or one value for a
    constant), times basis tables ``factors``, added to field ``field``."""

    field: int
    axis: int
    exponent: int
    factors: tuple[int, ...]
    values: tuple[int, ...]

    def __post_init__(self) -> None:
        _int("term field", self.field, 0, 255)
        _int("term axis", self.axis, 0, MAX_AXES - 1)
        _int("term exponent", self.exponent, *EXPONENT_RANGE)
        if not isinstance(self.factors, tuple) or len(self.factors) > MAX_FACTORS:
            raise ValueError(f"term factors must be a tuple of at most {MAX_FACTORS} basis "
                             f"indices, got {self.factors!r}")
        for b in self.factors:
            _int("term factor", b, 0, MAX_BASES - 1)
        _values("term", self.values, VALUE_LIMIT - 1)


@dataclass(frozen=True, slots=True)
class FactoredThermal:
    """A thermal record in fixed point (module docstring): ``sensor`` exactly as the
    Temperatures message names it, ``axis`` the index of a linear axis."""

    sensor: str
    axis: int
    kind: int
    coefficient: int
    t_ref_mC: int
    q_min: int = 0

    def __post_init__(self) -> None:
        if not isinstance(self.sensor, str) or not _LABEL.fullmatch(self.sensor) \
                or len(self.sensor) > MAX_LABEL_BYTES:
            raise ValueError(f"thermal sensor must be 1 to {MAX_LABEL_BYTES} printable ASCII "
                             f"characters without spaces, got {self.sensor!r}")
        _int("thermal record axis", self.axis, 0, MAX_AXES - 1)
        if self.kind not in (THERMAL_DRIFT, THERMAL_EXPANSION) or isinstance(self.kind, bool):
            raise ValueError(f"thermal record kind must be 1 (drift) or 2 (expansion), "
                             f"got {self.kind!r}")
        if self.kind == THERMAL_EXPANSION:
            _int(f"thermal record {self.sensor} expansion coefficient", self.coefficient,
                 -EXPANSION_LIMIT + 1, EXPANSION_LIMIT - 1)
        _int(f"thermal record {self.sensor} coefficient", self.coefficient, *_I32)
        _int(f"thermal record {self.sensor} t_ref", self.t_ref_mC, *_I30)
        _int(f"thermal record {self.sensor} q_min", self.q_min, *_I30)
        if self.kind == THERMAL_DRIFT and self.q_min:
            raise ValueError(f"thermal record {self.sensor}: a drift has q_min 0")


def thermal_fixed(rec: ThermalRecord, axis: int, counts_per_unit: int) -> FactoredThermal:
    """The fixed-point record of ``rec`` (f64 fields, as in format versions 2 and 3) for
    an endpoint of ``counts_per_unit`` counts per mm: the conversion rule of
    protocol/README.md §6.1, exact (rational arithmetic on the f64 values), halves up.

    Raises
    ------
    ValueError
        When a converted field does not fit an int32.
    """
    p = Fraction(counts_per_unit)
    coef = Fraction(rec.coefficient)
    if rec.kind == THERMAL_DRIFT:
        # µm/K → counts per m°C: coefficient · 1e-3 (K per m°C) · P / 1000 (counts per µm)
        k = round_half_up(coef * p / 1_000_000 * (1 << DRIFT_SHIFT))
        q_min = 0
    else:
        # µm/(m·K) → counts per count per m°C: µm per m is 1e-6 mm per mm, a m°C 1e-3 K
        k = round_half_up(coef / 1_000_000_000 * (1 << EXPANSION_SHIFT))
        q_min = round_half_up(Fraction(rec.q_min) * p)
    return FactoredThermal(rec.sensor, axis, rec.kind, k,
                           round_half_up(Fraction(rec.t_ref_C) * 1000), q_min)


def check_grid_ranges(p: ErrorMapPayload) -> None:
    """The ranges of protocol/README.md §6 ("Ranges and word sizes") of an int32 grid
    map (format version 1 or 3) after the loader's conversion of its f64 fields: grid
    starts and last nodes, reversals, t_ref and q_min below 2^30 in magnitude, an
    expansion coefficient below 2^24. A float32 map is not converted: nothing to check.

    Raises
    ------
    MapFormatError
        The first field out of range, named with its offset.
    """
    if p.encoding is not MapEncoding.INT32_INCREMENTS:
        return
    per_unit = round_half_up(1 / Fraction(p.increment_mm))
    lo, hi = _I30
    at = 64
    for g in p.grid:
        start = round_half_up(Fraction(g.start) * per_unit)
        last = start + (g.count - 1) * round_half_up(Fraction(g.step) * per_unit)
        if not (lo <= start <= hi and lo <= last <= hi):
            raise MapFormatError(f"grid axis {g.name} at offset {at + 8}: start {start} or "
                                 f"last node {last} counts, |·| < 2^30 (section 6)")
        at += 24
    for o in p.outputs:
        if o.reversal is not None and not lo <= o.reversal <= hi:
            raise MapFormatError(f"output axis {o.name} at offset {at + 8}: reversal "
                                 f"{o.reversal} counts, |·| < 2^30 (section 6)")
        at += 12
    records_at = at + len(p.values) + 4  # after the values and the record count
    names = [o.name for o in p.outputs]
    for i, rec in enumerate(p.thermal):
        try:
            thermal_fixed(rec, names.index(rec.axis), per_unit)
        except ValueError as exc:
            raise MapFormatError(f"thermal record {i} at offset {records_at + 48 * i}: "
                                 f"{exc} (after conversion, section 6)") from None


@dataclass(frozen=True, slots=True)
class FactoredPayload:
    """A decoded factored map (module docstring). A payload that could not be encoded
    validly cannot be constructed."""

    machine: str
    version: int
    valid_s: int
    counts_per_unit: int
    axes: tuple[FactoredAxis, ...]
    bases: tuple[BasisTable, ...]
    terms: tuple[TermTable, ...]
    thermal: tuple[FactoredThermal, ...] = ()
    encoding: MapEncoding = MapEncoding.INT32_INCREMENTS

    def __post_init__(self) -> None:
        check.name("machine", self.machine, MAX_NAME_BYTES)
        check.uint("map version", self.version, 32, minimum=1)
        check.uint("valid_s", self.valid_s, 32)
        check.uint("counts_per_unit", self.counts_per_unit, 32, minimum=1)
        if self.encoding is not MapEncoding.INT32_INCREMENTS:
            raise ValueError("a factored map's encoding is INT32_INCREMENTS")
        if not 1 <= len(self.axes) <= MAX_AXES:
            raise ValueError(f"a factored map has 1 to {MAX_AXES} axes, got {len(self.axes)}")
        check.unique("axes", [a.name for a in self.axes])
        if len(self.bases) > MAX_BASES:
            raise ValueError(f"at most {MAX_BASES} basis tables, got {len(self.bases)}")
        if not 1 <= len(self.terms) <= MAX_TERMS:
            raise ValueError(f"a factored map has 1 to {MAX_TERMS} terms, got "
                             f"{len(self.terms)}")
        if len(self.thermal) > MAX_THERMAL:
            raise ValueError(f"at most {MAX_THERMAL} thermal records, got {len(self.thermal)}")
        d = len(self.axes)
        for i, b in enumerate(self.bases):
            if b.axis >= d:
                raise ValueError(f"basis table {i} is on axis {b.axis}, the map has {d}")
        n_fields = self.n_fields
        for i, t in enumerate(self.terms):
            if t.axis >= d:
                raise ValueError(f"term {i} is on axis {t.axis}, the map has {d}")
            if t.field >= n_fields:
                raise ValueError(f"term {i} adds to field {t.field}, the map has {n_fields}")
            if len(t.values) not in (1, self.axes[t.axis].count):
                raise ValueError(f"term {i} has {len(t.values)} values, axis "
                                 f"{self.axes[t.axis].name} has {self.axes[t.axis].count} "
                                 f"term nodes (or 1 for a constant)")
            for j in t.factors:
                if j >= len(self.bases):
                    raise ValueError(f"term {i} multiplies basis table {j}, the map has "
                                     f"{len(self.bases)}")
        for i, th in enumerate(self.thermal):
            if th.axis >= d or self.axes[th.axis].rotary:
                raise ValueError(f"thermal record {i}: axis {th.axis} is not a linear axis "
                                 f"of the map")

    @property
    def n_fields(self) -> int:
        """D corrections plus one sensitivity per linear and rotary axis pair."""
        r = sum(a.rotary for a in self.axes)
        return len(self.axes) + (len(self.axes) - r) * r

    @property
    def increment_mm(self) -> float:
        """mm (degrees) per count, ``1 / counts_per_unit``."""
        return 1.0 / self.counts_per_unit

    @property
    def format_version(self) -> int:
        return FACTORED_FORMAT_VERSION


def payload_size(p: FactoredPayload) -> int:
    """Encoded length: 64 + 20 D + Σ (8 + 2 n) over basis tables and terms + 32 H."""
    return (_HEAD.size + _AXIS.size * len(p.axes)
            + sum(_BASIS.size + 2 * len(b.values) for b in p.bases)
            + sum(_TERM.size + 2 * len(t.values) for t in p.terms)
            + _THERMAL.size * len(p.thermal))


def encode_factored(p: FactoredPayload) -> bytes:
    """The wire bytes of ``p`` (layout in the module docstring)."""
    parts = [_HEAD.pack(MAP_MAGIC, FACTORED_FORMAT_VERSION, int(p.encoding), len(p.axes),
                        len(p.bases), len(p.thermal), len(p.terms), p.counts_per_unit,
                        _name_field(p.machine, 32), p.version, p.valid_s, bytes(8))]
    for a in p.axes:
        flags = (1 if a.rotary else 0) | (2 if a.reversal is not None else 0)
        parts.append(_AXIS.pack(_name_field(a.name, 4), flags, a.shift, a.count, a.start,
                                a.reversal or 0, a.limit))
    for b in p.bases:
        parts.append(_BASIS.pack(b.axis, b.shift, len(b.values), b.start))
        parts.append(struct.pack(f"<{len(b.values)}h", *b.values))
    for t in p.terms:
        factors = (*t.factors, *([NO_FACTOR] * (MAX_FACTORS - len(t.factors))))
        m = len(t.factors) | (0x80 if len(t.values) == 1 else 0)
        parts.append(_TERM.pack(t.field, t.axis, t.exponent, m, *factors))
        parts.append(struct.pack(f"<{len(t.values)}h", *t.values))
    for th in p.thermal:
        parts.append(_THERMAL.pack(_name_field(th.sensor, 16), th.axis, th.kind, bytes(2),
                                   th.coefficient, th.t_ref_mC, th.q_min))
    return b"".join(parts)


def _need(data: bytes, end: int, what: str) -> None:
    if len(data) < end:
        raise MapFormatError(f"map payload is {len(data)} bytes, {what} needs {end}")


def _int16s(data: bytes, at: int, n: int, bound: int, what: str) -> tuple[int, ...]:
    _need(data, at + 2 * n, what)
    values: tuple[int, ...] = struct.unpack_from(f"<{n}h", data, at)
    for i, v in enumerate(values):
        if not -bound <= v <= bound:
            raise MapFormatError(f"{what} value {i} at offset {at + 2 * i} is {v}, "
                                 f"|v| must be <= {bound}")
    return values


def decode_factored(data: bytes) -> FactoredPayload:
    """Parse and check a factored map (format version 5).

    Raises
    ------
    MapFormatError
        Wrong magic, version or encoding, reserved bytes set, counts out of range, an
        index that points nowhere, a value out of range, a length that does not match;
        the text names the field and its offset.
    """
    _need(data, _HEAD.size, "the 64-byte header")
    (magic, fmt, enc, n_axes, n_bases, n_thermal, n_terms, per_unit, machine_raw, version,
     valid_s, reserved) = _HEAD.unpack_from(data, 0)
    if magic != MAP_MAGIC:
        raise MapFormatError(f"map magic is {magic!r}, expected {MAP_MAGIC!r}")
    if fmt == RETIRED_FACTORED_VERSION:
        raise MapFormatError("map format version 4 at offset 4: factored maps are format "
                             f"version {FACTORED_FORMAT_VERSION} now (integer fields)")
    if fmt != FACTORED_FORMAT_VERSION:
        raise MapFormatError(f"map format version {fmt} at offset 4, a factored map is "
                             f"version {FACTORED_FORMAT_VERSION}")
    if enc != MapEncoding.INT32_INCREMENTS:
        raise MapFormatError(f"map value encoding {enc} at offset 6: a factored map is 1 "
                             f"(int32 increments)")
    if not 1 <= n_axes <= MAX_AXES:
        raise MapFormatError(f"map has {n_axes} axes (offset 7), 1 to {MAX_AXES} allowed")
    if n_bases > MAX_BASES:
        raise MapFormatError(f"map has {n_bases} basis tables (offset 8), at most "
                             f"{MAX_BASES}")
    if n_thermal > MAX_THERMAL:
        raise MapFormatError(f"map has {n_thermal} thermal records (offset 9), at most "
                             f"{MAX_THERMAL}")
    if not 1 <= n_terms <= MAX_TERMS:
        raise MapFormatError(f"map has {n_terms} terms (offset 10), 1 to {MAX_TERMS}")
    if per_unit < 1:
        raise MapFormatError("map counts_per_unit (offset 12) must be >= 1")
    if any(reserved):
        raise MapFormatError("map header reserved bytes 56..63 are not zero")
    try:
        machine = _name_from(machine_raw, "machine name", 16)
        at = _HEAD.size
        _need(data, at + _AXIS.size * n_axes, f"its {n_axes} axis records")
        axes: list[FactoredAxis] = []
        for i in range(n_axes):
            raw, flags, shift, count, start, rev, limit = _AXIS.unpack_from(data, at)
            name = _name_from(raw, f"axis {i} name", at)
            if name.upper() in (a.name.upper() for a in axes):
                raise MapFormatError(f"axis {i} at offset {at}: name {name} repeats an "
                                     f"earlier axis (axis names are distinct)")
            if flags & ~3:
                raise MapFormatError(f"axis {i} at offset {at + 4} has unknown flags "
                                     f"0x{flags:02x}")
            if not flags & 2 and rev:
                raise MapFormatError(f"axis {i} at offset {at + 12}: reversal is not 0 "
                                     f"though flagged absent")
            try:
                axes.append(FactoredAxis(name, bool(flags & 1), rev if flags & 2 else None,
                                         limit, count, start, shift))
            except ValueError as exc:
                raise MapFormatError(f"axis {i} at offset {at}: {exc}") from None
            at += _AXIS.size
        bases = []
        for i in range(n_bases):
            _need(data, at + _BASIS.size, f"basis table {i}")
            axis, shift, n, start = _BASIS.unpack_from(data, at)
            if axis >= n_axes:
                raise MapFormatError(f"basis table {i} at offset {at}: axis {axis}, the map "
                                     f"has {n_axes}")
            if not 1 <= n <= MAX_NODES:
                raise MapFormatError(f"basis table {i} at offset {at + 2}: {n} nodes, 1 to "
                                     f"{MAX_NODES} allowed")
            values = _int16s(data, at + _BASIS.size, n, BASIS_ONE, f"basis table {i}")
            try:
                bases.append(BasisTable(axis, start, shift, values))
            except ValueError as exc:
                raise MapFormatError(f"basis table {i} at offset {at}: {exc}") from None
            at += _BASIS.size + 2 * n
        n_rot = sum(a.rotary for a in axes)
        n_fields = n_axes + (n_axes - n_rot) * n_rot
        terms = []
        for i in range(n_terms):
            _need(data, at + _TERM.size, f"term {i}")
            fld, axis, exponent, m, *raw_factors = _TERM.unpack_from(data, at)
            if fld >= n_fields:
                raise MapFormatError(f"term {i} at offset {at}: field {fld}, the map has "
                                     f"{n_fields} (D + L x R)")
            if m & 0x78 or (m & 7) > MAX_FACTORS:
                raise MapFormatError(f"term {i} at offset {at + 3}: byte 0x{m:02x}, factors "
                                     f"0..{MAX_FACTORS} in bits 0-2, constant in bit 7")
            if axis >= n_axes:
                raise MapFormatError(f"term {i} at offset {at + 1}: axis {axis}, the map has "
                                     f"{n_axes}")
            k = m & 7
            factors = tuple(raw_factors[:k])
            if any(f >= n_bases for f in factors) or \
                    any(f != NO_FACTOR for f in raw_factors[k:]):
                raise MapFormatError(f"term {i} at offset {at + 4}: basis indices "
                                     f"{tuple(raw_factors)} with {k} factors; the map has "
                                     f"{n_bases} basis tables, unused slots 0xFF")
            n = 1 if m & 0x80 else axes[axis].count
            values = _int16s(data, at + _TERM.size, n, VALUE_LIMIT - 1, f"term {i}")
            try:
                terms.append(TermTable(fld, axis, exponent, factors, values))
            except ValueError as exc:
                raise MapFormatError(f"term {i} at offset {at}: {exc}") from None
            at += _TERM.size + 2 * n
        _need(data, at + _THERMAL.size * n_thermal, f"its {n_thermal} thermal records")
        thermal = []
        for i in range(n_thermal):
            raw_sensor, axis, kind, pad, coef, t_ref, q_min = _THERMAL.unpack_from(data, at)
            if any(pad):
                raise MapFormatError(f"thermal record {i} at offset {at + 18}: reserved "
                                     f"bytes are not zero")
            try:
                thermal.append(FactoredThermal(
                    _name_from(raw_sensor, f"thermal record {i} sensor", at), axis, kind,
                    coef, t_ref, q_min))
            except ValueError as exc:
                raise MapFormatError(f"thermal record {i} at offset {at}: {exc}") from None
            at += _THERMAL.size
        if len(data) != at:
            raise MapFormatError(f"map payload is {len(data)} bytes, its header and tables "
                                 f"describe {at}")
        return FactoredPayload(machine, version, valid_s, per_unit, tuple(axes),
                               tuple(bases), tuple(terms), tuple(thermal))
    except MapFormatError:
        raise
    except ValueError as exc:
        raise MapFormatError(f"factored map: {exc}") from None


__all__ = [
    "BASIS_ONE",
    "DRIFT_SHIFT",
    "EXPANSION_LIMIT",
    "EXPANSION_SHIFT",
    "FACTORED_FORMAT_VERSION",
    "BasisTable",
    "FactoredAxis",
    "FactoredPayload",
    "FactoredThermal",
    "TermTable",
    "check_grid_ranges",
    "decode_factored",
    "encode_factored",
    "milli_celsius",
    "payload_size",
    "round_half_up",
    "thermal_fixed",
]
