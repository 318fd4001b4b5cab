"""The ``factored`` map payload (format version 4): sums of products of 1-D tables, for
endpoints that only look up, multiply and add in fixed point (protocol/README.md §6.5).

Every multi-byte field is little-endian, as in the other map kinds. Layout::

    offset   size  field
         0      4  magic b"EDMP"
         4      2  format version u16 = 4
         6      1  value encoding u8 = 1 (int32 increments: the endpoint rounds to them)
         7      1  axes D, 1..8 (the machine's axes in its order: inputs and outputs)
         8      2  basis tables B u16, 0..256
        10      2  terms T u16, 1..4096
        12      4  reserved, zero
        16     32  machine name, ASCII, NUL-padded
        48      4  map version u32 (>= 1)
        52      4  valid_s u32 (0 = no limit)
        56      8  increment f64 > 0: mm (degrees on a rotary axis) per count
        64   36 D  axes, each: name 4 ASCII NUL-padded; flags u8 (bit 0 rotary, bit 1 has a
                   reversal value); reserved 3 zero; reversal int32 counts (0 when absent);
                   limit int32 counts (> 0); term nodes u32 (1..4096); start f64; step
                   f64 (> 0), mm or degrees: the grid of every term table of this axis
    then B basis tables, each 24 + 4 n bytes: axis u8 (< D); exponent i8 (-126..126);
                   reserved 2 zero; nodes n u32 (1..4096); start f64; step f64 (> 0);
                   n values int32
    then T terms, each 16 + 4 n bytes: field u16; axis u8 (< D); exponent i8;
                   factors m u8 (0..4); flags u8 (bit 0: a constant, n = 1); reserved 2
                   zero; 4 basis indices u16 (the first m < B, the others 0xFFFF); n
                   values int32 (n the term nodes of its axis, or 1 for a constant)
    then           thermal records H u32 (0..32) and H records of 48 bytes (as in format
                   version 3; each names a linear axis of the map)

Nothing follows; the length is exactly what the header, axes and tables describe. Every
table value is an int32 ``v`` with ``|v| < 2^30`` meaning ``v · 2^exponent``. Fields:
``0 .. D-1`` the correction of each axis (mm or degrees); then, for each linear axis ``l``
(in axis order, slowest) and rotary axis ``r``, field ``D + l·R + r`` (``l``, ``r`` counted
among the linear and rotary axes, R rotary axes): the sensitivity ``S_lr``, mm per degree.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Final

from . import _check as check
from .codes import MapEncoding
from .limits import MAX_NAME_BYTES
from .mapformat import (
    _AXIS_RE,
    MAP_MAGIC,
    MAX_THERMAL,
    MapFormatError,
    ThermalRecord,
    _name_field,
    _name_from,
    pack_thermal,
    thermal_at,
)

FACTORED_FORMAT_VERSION: Final = 4
MAX_AXES: Final = 8
MAX_BASES: Final = 256
MAX_TERMS: Final = 4096
MAX_NODES: Final = 4096
MAX_FACTORS: Final = 4
VALUE_LIMIT: Final = 1 << 30
"""|value| < 2^30: one bit of headroom, so two neighbouring values add without overflow."""
NO_FACTOR: Final = 0xFFFF

_HEAD = struct.Struct("<4sHBBHHI32sIId")  # 64 bytes
_AXIS = struct.Struct("<4sB3siiIdd")  # 36 bytes
_BASIS = struct.Struct("<BbHIdd")  # 24 bytes
_TERM = struct.Struct("<HBbBB2s4H")  # 16 bytes
_COUNT = struct.Struct("<I")
_THERMAL_SIZE = 48


def _values(what: str, values: tuple[int, ...], n: int | None = None) -> None:
    if not isinstance(values, tuple) or not values:
        raise ValueError(f"{what} values must be a non-empty tuple of ints")
    if n is not None and len(values) != n:
        raise ValueError(f"{what} has {len(values)} values, its axis grid has {n} nodes")
    if len(values) > MAX_NODES:
        raise ValueError(f"{what} has {len(values)} values, at most {MAX_NODES}")
    for i, v in enumerate(values):
        if not isinstance(v, int) or isinstance(v, bool) or not -VALUE_LIMIT < v < VALUE_LIMIT:
            raise ValueError(f"{what} value {i} must be an int with |v| < 2^30, got {v!r}")


def _exponent(what: str, e: int) -> None:
    if not isinstance(e, int) or isinstance(e, bool) or not -126 <= e <= 126:
        raise ValueError(f"{what} exponent must be an int in -126..126, got {e!r}")


@dataclass(frozen=True, slots=True)
class FactoredAxis:
    """One machine axis of a factored map: its flags, reversal and limit in counts, and
    the grid (``count`` nodes from ``start`` by ``step``) of its term tables."""

    name: str
    rotary: bool
    reversal: int | None
    limit: int
    count: int
    start: float
    step: float

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _AXIS_RE.fullmatch(self.name):
            raise ValueError(f"axis name must be 1 to 4 ASCII letters/digits starting with "
                             f"a letter, got {self.name!r}")
        if not isinstance(self.rotary, bool):
            raise ValueError(f"axis {self.name} rotary must be a bool")
        if self.reversal is not None and (
                not isinstance(self.reversal, int) or isinstance(self.reversal, bool)
                or not -(1 << 31) <= self.reversal < 1 << 31):
            raise ValueError(f"axis {self.name} reversal must be an int32 count or None, "
                             f"got {self.reversal!r}")
        check.uint(f"axis {self.name} limit", self.limit, 31, minimum=1)
        check.uint(f"axis {self.name} term nodes", self.count, 13, minimum=1)
        if self.count > MAX_NODES:
            raise ValueError(f"axis {self.name} term nodes {self.count} > {MAX_NODES}")
        check.finite(f"axis {self.name} start", self.start)
        check.finite(f"axis {self.name} step", self.step)
        if self.step <= 0:
            raise ValueError(f"axis {self.name} step must be > 0, got {self.step}")


@dataclass(frozen=True, slots=True)
class BasisTable:
    """A shared factor: ``values[i] · 2^exponent`` at ``start + i·step`` of axis ``axis``."""

    axis: int
    exponent: int
    start: float
    step: float
    values: tuple[int, ...]

    def __post_init__(self) -> None:
        check.uint("basis table axis", self.axis, 8)
        _exponent("basis table", self.exponent)
        check.finite("basis table start", self.start)
        check.finite("basis table step", self.step)
        if self.step <= 0:
            raise ValueError(f"basis table step must be > 0, got {self.step}")
        _values("basis table", self.values)


@dataclass(frozen=True, slots=True)
class TermTable:
    """One term: a table on its axis's term grid, times basis tables ``factors``, added to
    field ``field``."""

    field: int
    axis: int
    exponent: int
    factors: tuple[int, ...]
    values: tuple[int, ...]

    def __post_init__(self) -> None:
        check.uint("term field", self.field, 16)
        check.uint("term axis", self.axis, 8)
        _exponent("term", self.exponent)
        if not isinstance(self.factors, tuple) or len(self.factors) > MAX_FACTORS:
            raise ValueError(f"term factors must be a tuple of at most {MAX_FACTORS} basis "
                             f"indices, got {self.factors!r}")
        for b in self.factors:
            check.uint("term factor", b, 16)
            if b == NO_FACTOR:
                raise ValueError(f"term factor {NO_FACTOR:#x} means none; leave it out")
        _values("term", self.values)


@dataclass(frozen=True, slots=True)
class FactoredPayload:
    """A decoded factored map (module docstring). A payload that could not be encoded
    validly cannot be constructed."""

    machine: str
    version: int
    valid_s: int
    increment_mm: float
    axes: tuple[FactoredAxis, ...]
    bases: tuple[BasisTable, ...]
    terms: tuple[TermTable, ...]
    thermal: tuple[ThermalRecord, ...] = ()
    encoding: MapEncoding = MapEncoding.INT32_INCREMENTS

    def __post_init__(self) -> None:
        check.name("machine", self.machine, MAX_NAME_BYTES)
        check.uint("map version", self.version, 32, minimum=1)
        check.uint("valid_s", self.valid_s, 32)
        check.finite("increment", self.increment_mm)
        if self.increment_mm <= 0:
            raise ValueError(f"increment must be > 0, got {self.increment_mm}")
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
        linear = {a.name for a in self.axes if not a.rotary}
        for i, th in enumerate(self.thermal):
            if th.axis not in linear:
                raise ValueError(f"thermal record {i}: axis {th.axis} is not a linear axis "
                                 f"of the map ({' '.join(sorted(linear))})")

    @property
    def n_fields(self) -> int:
        """D corrections plus one sensitivity per linear and rotary axis pair."""
        r = sum(a.rotary for a in self.axes)
        return len(self.axes) + (len(self.axes) - r) * r

    @property
    def format_version(self) -> int:
        return FACTORED_FORMAT_VERSION


def encode_factored(p: FactoredPayload) -> bytes:
    """The wire bytes of ``p`` (layout in the module docstring)."""
    parts = [_HEAD.pack(MAP_MAGIC, FACTORED_FORMAT_VERSION, int(p.encoding), len(p.axes),
                        len(p.bases), len(p.terms), 0, _name_field(p.machine, 32), p.version,
                        p.valid_s, float(p.increment_mm))]
    for a in p.axes:
        flags = (1 if a.rotary else 0) | (2 if a.reversal is not None else 0)
        parts.append(_AXIS.pack(_name_field(a.name, 4), flags, bytes(3), a.reversal or 0,
                                a.limit, a.count, float(a.start), float(a.step)))
    for b in p.bases:
        parts.append(_BASIS.pack(b.axis, b.exponent, 0, len(b.values), float(b.start),
                                 float(b.step)))
        parts.append(struct.pack(f"<{len(b.values)}i", *b.values))
    for t in p.terms:
        factors = (*t.factors, *([NO_FACTOR] * (MAX_FACTORS - len(t.factors))))
        parts.append(_TERM.pack(t.field, t.axis, t.exponent, len(t.factors),
                                1 if len(t.values) == 1 else 0, bytes(2), *factors))
        parts.append(struct.pack(f"<{len(t.values)}i", *t.values))
    parts.append(_COUNT.pack(len(p.thermal)))
    parts += [pack_thermal(th) for th in p.thermal]
    return b"".join(parts)


def _need(data: bytes, end: int, what: str) -> None:
    if len(data) < end:
        raise MapFormatError(f"map payload is {len(data)} bytes, {what} needs {end}")


def _ints(data: bytes, at: int, n: int, what: str) -> tuple[int, ...]:
    _need(data, at + 4 * n, what)
    values: tuple[int, ...] = struct.unpack_from(f"<{n}i", data, at)
    for i, v in enumerate(values):
        if not -VALUE_LIMIT < v < VALUE_LIMIT:
            raise MapFormatError(f"{what} value {i} at offset {at + 4 * i} is {v}, "
                                 f"|v| must be < 2^30")
    return values


def decode_factored(data: bytes) -> FactoredPayload:
    """Parse and check a factored map (format version 4).

    Raises
    ------
    MapFormatError
        Wrong magic, version or encoding, reserved bytes set, counts out of range, an
        index that points nowhere, a value out of range, a length that does not match;
        the text names the field and its offset.
    """
    _need(data, _HEAD.size, "the 64-byte header")
    (magic, fmt, enc, n_axes, n_bases, n_terms, reserved, machine_raw, version, valid_s,
     increment) = _HEAD.unpack_from(data, 0)
    if magic != MAP_MAGIC:
        raise MapFormatError(f"map magic is {magic!r}, expected {MAP_MAGIC!r}")
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
    if not 1 <= n_terms <= MAX_TERMS:
        raise MapFormatError(f"map has {n_terms} terms (offset 10), 1 to {MAX_TERMS}")
    if reserved:
        raise MapFormatError("map header reserved bytes 12..15 are not zero")
    try:
        machine = _name_from(machine_raw, "machine name", 16)
        at = _HEAD.size
        _need(data, at + _AXIS.size * n_axes, f"its {n_axes} axis records")
        axes = []
        for i in range(n_axes):
            raw, flags, pad, rev, limit, count, start, step = _AXIS.unpack_from(data, at)
            if flags & ~3 or any(pad):
                raise MapFormatError(f"axis {i} at offset {at} has unknown flags "
                                     f"0x{flags:02x} or non-zero reserved bytes")
            if not flags & 2 and rev:
                raise MapFormatError(f"axis {i} at offset {at + 8}: reversal is not 0 "
                                     f"though flagged absent")
            if limit < 1:
                raise MapFormatError(f"axis {i} at offset {at + 12}: limit {limit} counts "
                                     f"must be > 0")
            if not 1 <= count <= MAX_NODES:
                raise MapFormatError(f"axis {i} at offset {at + 16}: {count} term nodes, "
                                     f"1 to {MAX_NODES} allowed")
            try:
                axes.append(FactoredAxis(_name_from(raw, f"axis {i} name", at),
                                         bool(flags & 1), rev if flags & 2 else None, limit,
                                         count, start, step))
            except ValueError as exc:
                raise MapFormatError(f"axis {i} at offset {at}: {exc}") from None
            at += _AXIS.size
        bases = []
        for i in range(n_bases):
            _need(data, at + _BASIS.size, f"basis table {i}")
            axis, exponent, pad2, n, start, step = _BASIS.unpack_from(data, at)
            if pad2:
                raise MapFormatError(f"basis table {i} at offset {at + 2}: reserved bytes "
                                     f"are not zero")
            if axis >= n_axes:
                raise MapFormatError(f"basis table {i} at offset {at}: axis {axis}, the map "
                                     f"has {n_axes}")
            if not 1 <= n <= MAX_NODES:
                raise MapFormatError(f"basis table {i} at offset {at + 4}: {n} nodes, 1 to "
                                     f"{MAX_NODES} allowed")
            values = _ints(data, at + _BASIS.size, n, f"basis table {i}")
            try:
                bases.append(BasisTable(axis, exponent, start, step, values))
            except ValueError as exc:
                raise MapFormatError(f"basis table {i} at offset {at}: {exc}") from None
            at += _BASIS.size + 4 * n
        terms = []
        for i in range(n_terms):
            _need(data, at + _TERM.size, f"term {i}")
            fld, axis, exponent, m, flags, pad3, *raw_factors = _TERM.unpack_from(data, at)
            if flags & ~1 or any(pad3):
                raise MapFormatError(f"term {i} at offset {at + 5}: unknown flags "
                                     f"0x{flags:02x} or non-zero reserved bytes")
            if axis >= n_axes:
                raise MapFormatError(f"term {i} at offset {at + 2}: axis {axis}, the map has "
                                     f"{n_axes}")
            if m > MAX_FACTORS:
                raise MapFormatError(f"term {i} at offset {at + 4}: {m} factors, at most "
                                     f"{MAX_FACTORS}")
            factors = tuple(raw_factors[:m])
            if any(f == NO_FACTOR or f >= n_bases for f in factors) or \
                    any(f != NO_FACTOR for f in raw_factors[m:]):
                raise MapFormatError(f"term {i} at offset {at + 8}: basis indices "
                                     f"{tuple(raw_factors)} with {m} factors; the map has "
                                     f"{n_bases} basis tables, unused slots 0xFFFF")
            n = 1 if flags & 1 else axes[axis].count
            values = _ints(data, at + _TERM.size, n, f"term {i}")
            try:
                terms.append(TermTable(fld, axis, exponent, factors, values))
            except ValueError as exc:
                raise MapFormatError(f"term {i} at offset {at}: {exc}") from None
            at += _TERM.size + 4 * n
        _need(data, at + _COUNT.size, "the thermal record count")
        (h,) = _COUNT.unpack_from(data, at)
        if h > MAX_THERMAL:
            raise MapFormatError(f"map has {h} thermal records (offset {at}), at most "
                                 f"{MAX_THERMAL}")
        at += _COUNT.size
        _need(data, at + _THERMAL_SIZE * h, f"its {h} thermal records")
        thermal = tuple(thermal_at(data, at + _THERMAL_SIZE * i, i) for i in range(h))
        at += _THERMAL_SIZE * h
        if len(data) != at:
            raise MapFormatError(f"map payload is {len(data)} bytes, its header and tables "
                                 f"describe {at}")
        return FactoredPayload(machine, version, valid_s, increment, tuple(axes),
                               tuple(bases), tuple(terms), thermal)
    except MapFormatError:
        raise
    except ValueError as exc:
        raise MapFormatError(f"factored map: {exc}") from None


__all__ = [
    "FACTORED_FORMAT_VERSION",
    "BasisTable",
    "FactoredAxis",
    "FactoredPayload",
    "TermTable",
    "decode_factored",
    "encode_factored",
]
