"""The ``tables`` map kind: format version 2 of the error-map payload.

Instead of a dense grid of corrections (format version 1, :mod:`protocol.mapformat`) the
center sends the machine's kinematic chain, per axis the 1-D tables of its ISO 230-1
component errors, the location errors and thermal terms; the machine evaluates the tool
tip's error through the chain and solves the corrections itself every cycle
(protocol/README.md sections 6.2 and 6.3: the layout, and how to evaluate it, precisely
enough to implement from).

Little-endian, fixed-size records a PLC parses with fixed offsets. Layout::

    offset      size   field
         0         4   magic b"EDMP"
         4         2   format version u16 = 2
         6         1   value encoding u8: 1 = int32 increments, 2 = float32 mm/deg: how
                       the machine rounds the corrections it computes
         7         1   map kind u8 = 2 (tables)
         8         1   output axes K, 1..16
         9         1   chain axes A, 1..16
        10         1   spindles S, 1..8
        11         1   thermal records H, 0..32
        12         2   component tables T u16, 0..6 A
        14         2   location errors L u16, 0..6 A
        16        32   machine name, ASCII, NUL-padded
        48         4   map version u32 >= 1
        52         4   valid_s u32 (0 = no limit)
        56         8   increment f64: mm (deg) per count for int32, 0 for float32
        64         8   limit_mm f64 > 0: corrections of linear axes are clamped to ±limit_mm
        72         8   limit_deg f64 > 0: corrections of rotary axes, ±limit_deg
        80      72 A   chain axes
          +      104 S   spindles
          +       12 K   output axes (the version-1 record)
          +       32 T   component-table directory
          +       16 L   location errors
          +       48 H   thermal records
          +      4 N   table values float32, N = sum of the tables' counts

Nothing follows the values. Record layouts are in :data:`_AXIS` ... :data:`_THERMAL` and
the README.
"""

from __future__ import annotations

import array
import math
import re
import struct
import sys
from dataclasses import dataclass
from typing import Final, Literal

from . import _check as check
from .codes import MapEncoding
from .limits import MAX_MAP_BYTES, MAX_NAME_BYTES
from .mapfactored import (
    FACTORED_FORMAT_VERSION,
    RETIRED_FACTORED_VERSION,
    FactoredPayload,
    check_grid_ranges,
    decode_factored,
)
from .mapformat import (
    _OUT,
    _THERMAL,
    GRID_THERMAL_FORMAT_VERSION,
    MAP_FORMAT_VERSION,
    MAP_MAGIC,
    MAX_THERMAL,
    THERMAL_DRIFT,
    THERMAL_EXPANSION,
    ErrorMapPayload,
    MapFormatError,
    OutputAxis,
    ThermalRecord,
    _f32,
    _name_field,
    _name_from,
    checked_output,
    decode_map,
    encode_map,
    pack_thermal,
    thermal_at,
)

__all__ = [
    "KIND_TABLES",
    "TABLES_FORMAT_VERSION",
    "THERMAL_DRIFT",
    "THERMAL_EXPANSION",
    "ChainAxis",
    "ComponentTable",
    "Spindle",
    "TablesPayload",
    "ThermalRecord",
    "decode_payload",
    "decode_tables",
    "encode_payload",
    "encode_tables",
    "payload_kind",
]

TABLES_FORMAT_VERSION: Final = 2
KIND_TABLES: Final = 2
MAX_CHAIN_AXES: Final = 16
MAX_SPINDLES: Final = 8
UNIT_TOLERANCE: Final = 1e-6
"""How far from 1 the length of a direction may be (the machine description's rule)."""

_HEAD2 = struct.Struct("<4sHBBBBBBHH32sIId")  # 64 bytes
_LIMITS = struct.Struct("<dd")  # 16
_AXIS = struct.Struct("<4sB3s3d3d2d")  # 72
_SPINDLE = struct.Struct("<16sH6sd3d6d")  # 104
_TABLE = struct.Struct("<8sIIdd")  # 32
_LOCATION = struct.Struct("<8sd")  # 16
_AXIS_NAME = re.compile(r"[XYZ][0-9]{0,3}|[ABC]")
_COMPONENT = re.compile(r"E([XYZABC])([XYZABC][0-9]*)")
_LOCATION_NAME = re.compile(r"E([XYZABC])0([XYZABC][0-9]*)")
_LABEL = re.compile(r"[\x21-\x7e]{1,16}")
_BASE_UNIT = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0),
              "A": (1.0, 0.0, 0.0), "B": (0.0, 1.0, 0.0), "C": (0.0, 0.0, 1.0)}

Vec3 = tuple[float, float, float]


def _vec(field: str, value: object, n: int) -> tuple[float, ...]:
    if not isinstance(value, tuple) or len(value) != n:
        raise ValueError(f"{field} must be a tuple of {n} numbers, got {value!r}")
    for i, v in enumerate(value):
        check.finite(f"{field}[{i}]", v)
    return tuple(float(v) for v in value)


def _unit(field: str, value: object) -> None:
    v = _vec(field, value, 3)
    norm = math.sqrt(sum(c * c for c in v))
    if abs(norm - 1.0) > UNIT_TOLERANCE:
        raise ValueError(f"{field} must be a unit vector, its length is {norm:.9g}")


@dataclass(frozen=True, slots=True)
class ChainAxis:
    """One axis of the chain, in the machine description's chain order.

    Attributes
    ----------
    name : str
        ``X Y Z A B C``, or a spindle axis ``X1``, ``Z2`` ... (linear, own direction).
    rotary : bool
        A B C are rotary, the others linear.
    tool_side : bool
        False: between workpiece and base (w side); True: between base and tool.
    direction : (3,) float
        Unit vector in the base frame: the base axis for X..C, any for spindle axes.
    pivot_mm : (3,) float
        A point on a rotary axis, mm (zeros for linear axes).
    travel : (2,) float
        Lower and upper travel, mm or degrees, lower < upper.
    """

    name: str
    rotary: bool
    tool_side: bool
    direction: Vec3
    pivot_mm: Vec3 = (0.0, 0.0, 0.0)
    travel: tuple[float, float] = (-180.0, 180.0)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _AXIS_NAME.fullmatch(self.name):
            raise ValueError(f"chain axis name must be X, Y, Z, A, B, C or a spindle axis "
                             f"such as Z1, got {self.name!r}")
        for flag in ("rotary", "tool_side"):
            if not isinstance(getattr(self, flag), bool):
                raise ValueError(f"chain axis {self.name} {flag} must be a bool")
        if self.rotary != (self.name in ("A", "B", "C")):
            raise ValueError(f"chain axis {self.name} must be "
                             f"{'rotary' if self.name in 'ABC' else 'linear'}")
        _unit(f"chain axis {self.name} direction", self.direction)
        if self.name in _BASE_UNIT and _vec("", self.direction, 3) != _BASE_UNIT[self.name]:
            raise ValueError(f"chain axis {self.name} direction must be "
                             f"{_BASE_UNIT[self.name]}, got {self.direction}")
        _vec(f"chain axis {self.name} pivot_mm", self.pivot_mm, 3)
        lo, hi = _vec(f"chain axis {self.name} travel", self.travel, 2)
        if not lo < hi:
            raise ValueError(f"chain axis {self.name} travel must have lower < upper, "
                             f"got {self.travel}")


@dataclass(frozen=True, slots=True)
class Spindle:
    """One tool branch.

    Attributes
    ----------
    name : str
        1..16 printable ASCII characters, no spaces.
    axes : tuple of str
        The branch's links, in chain order (a subsequence of the chain axes).
    tool_length_mm : float
    tool_direction : (3,) float
        Unit vector from the gauge line to the tool tip, base frame at zero.
    weights : (6,) float
        Solver weights px py pz (per µm²) and ox oy oz (per µrad²), >= 0.
    """

    name: str
    axes: tuple[str, ...]
    tool_length_mm: float
    tool_direction: Vec3
    weights: tuple[float, float, float, float, float, float] = (1.0, 1.0, 1.0, 0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _LABEL.fullmatch(self.name):
            raise ValueError(f"spindle name must be 1 to 16 printable ASCII characters "
                             f"without spaces, got {self.name!r}")
        if (not isinstance(self.axes, tuple) or not self.axes
                or not all(isinstance(a, str) for a in self.axes)):
            raise ValueError(f"spindle {self.name} axes must be a non-empty tuple of names")
        check.unique(f"spindle {self.name} axes", list(self.axes))
        check.finite(f"spindle {self.name} tool_length_mm", self.tool_length_mm)
        _unit(f"spindle {self.name} tool_direction", self.tool_direction)
        w = _vec(f"spindle {self.name} weights", self.weights, 6)
        if any(x < 0 for x in w):
            raise ValueError(f"spindle {self.name} weights must be >= 0, got {self.weights}")


@dataclass(frozen=True, slots=True)
class ComponentTable:
    """One ISO 230-1 component error of one axis, tabulated on a uniform grid.

    Attributes
    ----------
    name : str
        ``E<c><K>``: ``EXX``, ``EBC``, ``EXZ1`` ...
    start : float
        Position of ``values[0]``, mm or degrees.
    step : float
        Node spacing > 0, mm or degrees; any finite value when there is one value (a
        constant).
    values : tuple of float
        µm (c = X, Y, Z) or µrad (c = A, B, C), rounded to float32 on construction (what
        the wire carries). Linear interpolation, end values hold outside.
    """

    name: str
    start: float
    step: float
    values: tuple[float, ...]

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _COMPONENT.fullmatch(self.name) \
                or len(self.name) > 8:
            raise ValueError(f"component table name must be an ISO 230-1 component error "
                             f"such as EXX, EBC or EXZ1, got {self.name!r}")
        check.finite(f"table {self.name} start", self.start)
        check.finite(f"table {self.name} step", self.step)
        if not isinstance(self.values, tuple) or not self.values:
            raise ValueError(f"table {self.name} values must be a non-empty tuple")
        if len(self.values) >= 2 and not self.step > 0:
            raise ValueError(f"table {self.name} step must be > 0, got {self.step}")
        rounded = []
        for i, v in enumerate(self.values):
            check.finite(f"table {self.name} value {i}", v)
            try:
                rounded.append(_f32(float(v)))
            except ValueError:
                raise ValueError(f"table {self.name} value {i} = {v} does not fit a "
                                 f"float32") from None
        object.__setattr__(self, "values", tuple(rounded))

    @property
    def axis(self) -> str:
        """The axis the table belongs to (``Z1`` for ``EXZ1``)."""
        m = _COMPONENT.fullmatch(self.name)
        assert m is not None
        return m.group(2)


@dataclass(frozen=True, slots=True)
class TablesPayload:
    """A decoded ``tables`` map (format version 2); see the module docstring."""

    machine: str
    version: int
    encoding: MapEncoding
    valid_s: int
    increment_mm: float
    axes: tuple[ChainAxis, ...]
    spindles: tuple[Spindle, ...]
    outputs: tuple[OutputAxis, ...]
    tables: tuple[ComponentTable, ...]
    locations: tuple[tuple[str, float], ...]
    thermal: tuple[ThermalRecord, ...] = ()
    limit_mm: float = 1.0
    limit_deg: float = 1.0

    def __post_init__(self) -> None:
        check.name("map machine", self.machine, MAX_NAME_BYTES)
        check.uint("map version", self.version, 32, minimum=1)
        check.uint("map valid_s", self.valid_s, 32)
        check.member("map encoding", self.encoding, MapEncoding)
        if self.encoding not in (MapEncoding.INT32_INCREMENTS, MapEncoding.FLOAT32_MM):
            raise ValueError(f"tables map encoding must be INT32_INCREMENTS or FLOAT32_MM, "
                             f"got {self.encoding!r}")
        check.finite("map increment_mm", self.increment_mm)
        if self.encoding is MapEncoding.INT32_INCREMENTS and not 0 < self.increment_mm <= 1:
            raise ValueError(f"int32 map increment_mm must be in (0, 1], "
                             f"got {self.increment_mm}")
        if self.encoding is MapEncoding.FLOAT32_MM and self.increment_mm != 0:
            raise ValueError(f"float32 map increment_mm must be 0, got {self.increment_mm}")
        for f in ("limit_mm", "limit_deg"):
            check.finite(f"map {f}", getattr(self, f))
            if not getattr(self, f) > 0:
                raise ValueError(f"map {f} must be > 0, got {getattr(self, f)}")
        self._check_axes()
        self._check_spindles()
        self._check_outputs()
        self._check_tables()
        self._check_locations()
        self._check_thermal()
        if self.size > MAX_MAP_BYTES:
            raise ValueError(f"tables map needs {self.size} bytes, limit {MAX_MAP_BYTES}")

    # -- the checks, one per section
    def _check_axes(self) -> None:
        if not isinstance(self.axes, tuple) or not 1 <= len(self.axes) <= MAX_CHAIN_AXES:
            raise ValueError(f"map axes must be a tuple of 1 to {MAX_CHAIN_AXES} ChainAxis")
        if not all(isinstance(a, ChainAxis) for a in self.axes):
            raise ValueError("map axes must hold ChainAxis objects")
        check.unique("map axes", [a.name for a in self.axes])

    def _check_spindles(self) -> None:
        if not isinstance(self.spindles, tuple) or not 1 <= len(self.spindles) <= MAX_SPINDLES:
            raise ValueError(f"map spindles must be a tuple of 1 to {MAX_SPINDLES} Spindle")
        if not all(isinstance(s, Spindle) for s in self.spindles):
            raise ValueError("map spindles must hold Spindle objects")
        check.unique("map spindles", [s.name for s in self.spindles])
        names = self.axis_names
        for s in self.spindles:
            where = [names.index(a) if a in names else -1 for a in s.axes]
            if -1 in where:
                raise ValueError(f"spindle {s.name} names axis {s.axes[where.index(-1)]!r}, "
                                 f"not a chain axis ({' '.join(names)})")
            if where != sorted(where):
                raise ValueError(f"spindle {s.name} axes {s.axes} are not in chain order")
        if not any(any(w > 0 for w in s.weights) for s in self.spindles):
            raise ValueError("map spindle weights are all zero: nothing to compensate")

    def _check_outputs(self) -> None:
        if not isinstance(self.outputs, tuple) or not 1 <= len(self.outputs) <= 16:
            raise ValueError("map outputs must be a tuple of 1 to 16 OutputAxis")
        if not all(isinstance(o, OutputAxis) for o in self.outputs):
            raise ValueError("map outputs must hold OutputAxis objects")
        check.unique("map outputs", [o.name for o in self.outputs])
        for o in self.outputs:
            if o.name not in self.axis_names:
                raise ValueError(f"output axis {o.name} is not a chain axis "
                                 f"({' '.join(self.axis_names)})")
        object.__setattr__(self, "outputs",
                           tuple(checked_output(self.encoding, o) for o in self.outputs))

    def _check_tables(self) -> None:
        if not isinstance(self.tables, tuple) or len(self.tables) > 6 * len(self.axes):
            raise ValueError(f"map tables must be a tuple of at most 6 per chain axis "
                             f"({6 * len(self.axes)})")
        if not all(isinstance(t, ComponentTable) for t in self.tables):
            raise ValueError("map tables must hold ComponentTable objects")
        check.unique("map tables", [t.name for t in self.tables])
        for t in self.tables:
            if t.axis not in self.axis_names:
                raise ValueError(f"table {t.name}: {t.axis} is not a chain axis "
                                 f"({' '.join(self.axis_names)})")

    def _check_locations(self) -> None:
        if not isinstance(self.locations, tuple) or len(self.locations) > 6 * len(self.axes):
            raise ValueError("map locations must be a tuple of (name, value) pairs, at most "
                             "6 per chain axis")
        for item in self.locations:
            if not (isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str)):
                raise ValueError(f"map location {item!r} is not a (name, value) pair")
            name, value = item
            m = _LOCATION_NAME.fullmatch(name)
            if m is None or len(name) > 8:
                raise ValueError(f"location error name must be E<c>0<axis> such as EC0Y or "
                                 f"EX0C, got {name!r}")
            axis = self.axis(m.group(2)) if m.group(2) in self.axis_names else None
            if axis is None:
                raise ValueError(f"location error {name}: {m.group(2)} is not a chain axis")
            if not axis.rotary and m.group(1) in "XYZ":
                raise ValueError(f"location error {name}: a linear axis has only angular "
                                 f"location errors (E[ABC]0{axis.name})")
            check.finite(f"location error {name}", value)
        check.unique("map locations", [n for n, _ in self.locations])

    def _check_thermal(self) -> None:
        if not isinstance(self.thermal, tuple) or len(self.thermal) > MAX_THERMAL:
            raise ValueError(f"map thermal must be a tuple of at most {MAX_THERMAL} "
                             f"ThermalRecord")
        for r in self.thermal:
            if not isinstance(r, ThermalRecord):
                raise ValueError("map thermal must hold ThermalRecord objects")
            if r.axis not in self.axis_names:
                raise ValueError(f"thermal record {r.sensor}: axis {r.axis} is not a chain "
                                 f"axis")

    # -- derived
    @property
    def axis_names(self) -> tuple[str, ...]:
        return tuple(a.name for a in self.axes)

    def axis(self, name: str) -> ChainAxis:
        """The chain axis called ``name``."""
        for a in self.axes:
            if a.name == name:
                return a
        raise KeyError(f"map of {self.machine} has no chain axis {name!r}")

    @property
    def value_count(self) -> int:
        """Table values in all: N."""
        return sum(len(t.values) for t in self.tables)

    @property
    def size(self) -> int:
        """Length of the encoded payload in bytes."""
        return (_HEAD2.size + _LIMITS.size + _AXIS.size * len(self.axes)
                + _SPINDLE.size * len(self.spindles) + _OUT.size * len(self.outputs)
                + _TABLE.size * len(self.tables) + _LOCATION.size * len(self.locations)
                + _THERMAL.size * len(self.thermal) + 4 * self.value_count)


# --- encoding -------------------------------------------------------------------------

def _flags(a: ChainAxis) -> int:
    return (1 if a.rotary else 0) | (2 if a.tool_side else 0)


def encode_tables(p: TablesPayload) -> bytes:
    """The wire bytes of a tables map (layout in the module docstring)."""
    int32 = p.encoding is MapEncoding.INT32_INCREMENTS
    parts = [_HEAD2.pack(MAP_MAGIC, TABLES_FORMAT_VERSION, p.encoding, KIND_TABLES,
                         len(p.outputs), len(p.axes), len(p.spindles), len(p.thermal),
                         len(p.tables), len(p.locations), _name_field(p.machine, 32),
                         p.version, p.valid_s, float(p.increment_mm)),
             _LIMITS.pack(float(p.limit_mm), float(p.limit_deg))]
    for a in p.axes:
        parts.append(_AXIS.pack(_name_field(a.name, 4), _flags(a), bytes(3), *a.direction,
                                *a.pivot_mm, *a.travel))
    names = p.axis_names
    for s in p.spindles:
        mask = sum(1 << names.index(a) for a in s.axes)
        parts.append(_SPINDLE.pack(_name_field(s.name, 16), mask, bytes(6),
                                   float(s.tool_length_mm), *s.tool_direction, *s.weights))
    for o in p.outputs:
        r = 0 if o.reversal is None else o.reversal
        raw = struct.pack("<i", int(r)) if int32 else struct.pack("<f", r)
        parts.append(_OUT.pack(_name_field(o.name, 4), o.reversal is not None, bytes(3), raw))
    first = 0
    for t in p.tables:
        parts.append(_TABLE.pack(_name_field(t.name, 8), len(t.values), first,
                                 float(t.start), float(t.step)))
        first += len(t.values)
    for name, value in p.locations:
        parts.append(_LOCATION.pack(_name_field(name, 8), float(value)))
    parts += [pack_thermal(th) for th in p.thermal]
    values = array.array("f", (v for t in p.tables for v in t.values))
    if sys.byteorder == "big":
        values.byteswap()
    parts.append(values.tobytes())
    return b"".join(parts)


def encode_payload(p: ErrorMapPayload | TablesPayload) -> bytes:
    """The wire bytes of either map kind."""
    if isinstance(p, TablesPayload):
        return encode_tables(p)
    return encode_map(p)


def payload_kind(p: ErrorMapPayload | TablesPayload | FactoredPayload
                 ) -> Literal["grid", "tables", "factored"]:
    """``"grid"`` (format version 1, or 3 with thermal records), ``"tables"`` (format
    version 2) or ``"factored"`` (format version 4)."""
    if isinstance(p, FactoredPayload):
        return "factored"
    return "tables" if isinstance(p, TablesPayload) else "grid"


# --- decoding -------------------------------------------------------------------------

def decode_payload(data: bytes) -> ErrorMapPayload | TablesPayload | FactoredPayload:
    """Parse any map kind, by the format version at offset 4.

    Raises
    ------
    MapFormatError
        Any deviation from the layout of its version; the text names the field and offset.
    """
    if len(data) < 6:
        raise MapFormatError(f"map payload is {len(data)} bytes, too short for magic and "
                             f"format version")
    magic, fmt = struct.unpack_from("<4sH", data, 0)
    if magic != MAP_MAGIC:
        raise MapFormatError(f"map magic is {magic!r}, expected {MAP_MAGIC!r}")
    if fmt in (MAP_FORMAT_VERSION, GRID_THERMAL_FORMAT_VERSION):
        grid = decode_map(data)
        check_grid_ranges(grid)
        return grid
    if fmt == TABLES_FORMAT_VERSION:
        return decode_tables(data)
    if fmt in (FACTORED_FORMAT_VERSION, RETIRED_FACTORED_VERSION):
        return decode_factored(data)  # refuses the retired version 4 by name
    raise MapFormatError(f"map format version {fmt} at offset 4, this end reads 1 (grid), "
                         f"2 (tables), 3 (grid with thermal records) and 5 (factored)")


def decode_tables(data: bytes) -> TablesPayload:
    """Parse and check a tables map (format version 2).

    Raises
    ------
    MapFormatError
        Wrong magic, version or kind, unknown encoding, reserved bytes set, counts out of
        range, a length that does not match the header, any record that breaks its rule;
        the text names the field and its offset.
    """
    fixed = _HEAD2.size + _LIMITS.size
    if len(data) < fixed:
        raise MapFormatError(f"tables map is {len(data)} bytes, shorter than its {fixed}-byte "
                             f"header")
    (magic, fmt, enc, kind, n_out, n_axes, n_sp, n_th, n_tab, n_loc, machine_raw, version,
     valid_s, increment) = _HEAD2.unpack_from(data, 0)
    if magic != MAP_MAGIC:
        raise MapFormatError(f"map magic is {magic!r}, expected {MAP_MAGIC!r}")
    if fmt != TABLES_FORMAT_VERSION:
        raise MapFormatError(f"map format version {fmt} at offset 4, a tables map is "
                             f"version {TABLES_FORMAT_VERSION}")
    if enc not in (MapEncoding.INT32_INCREMENTS, MapEncoding.FLOAT32_MM):
        raise MapFormatError(f"map value encoding {enc} at offset 6 is unknown (1 or 2)")
    if kind != KIND_TABLES:
        raise MapFormatError(f"map kind {kind} at offset 7 is unknown (2 = tables)")
    if not 1 <= n_out <= 16:
        raise MapFormatError(f"map has {n_out} output axes (offset 8), 1 to 16 allowed")
    if not 1 <= n_axes <= MAX_CHAIN_AXES:
        raise MapFormatError(f"map has {n_axes} chain axes (offset 9), 1 to "
                             f"{MAX_CHAIN_AXES} allowed")
    if not 1 <= n_sp <= MAX_SPINDLES:
        raise MapFormatError(f"map has {n_sp} spindles (offset 10), 1 to {MAX_SPINDLES} "
                             f"allowed")
    if n_th > MAX_THERMAL:
        raise MapFormatError(f"map has {n_th} thermal records (offset 11), at most "
                             f"{MAX_THERMAL}")
    if n_tab > 6 * n_axes:
        raise MapFormatError(f"map has {n_tab} component tables (offset 12), at most 6 per "
                             f"chain axis ({6 * n_axes})")
    if n_loc > 6 * n_axes:
        raise MapFormatError(f"map has {n_loc} location errors (offset 14), at most 6 per "
                             f"chain axis ({6 * n_axes})")
    machine = _name_from(machine_raw, "machine name", 16)
    limit_mm, limit_deg = _LIMITS.unpack_from(data, _HEAD2.size)
    at_axes = fixed
    at_sp = at_axes + _AXIS.size * n_axes
    at_out = at_sp + _SPINDLE.size * n_sp
    at_tab = at_out + _OUT.size * n_out
    at_loc = at_tab + _TABLE.size * n_tab
    at_th = at_loc + _LOCATION.size * n_loc
    at_val = at_th + _THERMAL.size * n_th
    if len(data) < at_val:
        raise MapFormatError(f"tables map is {len(data)} bytes, its records need {at_val} "
                             f"(header counts at offsets 8..15)")
    axes = [_axis_at(data, at_axes + _AXIS.size * i, i) for i in range(n_axes)]
    names = tuple(a.name for a in axes)
    spindles = [_spindle_at(data, at_sp + _SPINDLE.size * i, i, names) for i in range(n_sp)]
    outputs = [_output_at(data, at_out + _OUT.size * k, k, enc) for k in range(n_out)]
    directory = []
    expect_first = 0
    for i in range(n_tab):
        at = at_tab + _TABLE.size * i
        raw, count, first, start, step = _TABLE.unpack_from(data, at)
        name = _name_from(raw, f"table {i} name", at)
        if count < 1:
            raise MapFormatError(f"table {i} ({name}) at offset {at}: count is 0, at least 1")
        if first != expect_first:
            raise MapFormatError(f"table {i} ({name}) at offset {at}: first value index "
                                 f"{first}, expected {expect_first} (tables follow each "
                                 f"other without gaps)")
        directory.append((at, name, count, first, start, step))
        expect_first += count
    locations = []
    for i in range(n_loc):
        at = at_loc + _LOCATION.size * i
        raw, value = _LOCATION.unpack_from(data, at)
        locations.append((_name_from(raw, f"location {i} name", at), value))
    thermal = [thermal_at(data, at_th + _THERMAL.size * i, i) for i in range(n_th)]
    want = at_val + 4 * expect_first
    if len(data) != want:
        raise MapFormatError(f"tables map is {len(data)} bytes, its header and table "
                             f"directory describe {want} ({expect_first} values at offset "
                             f"{at_val})")
    values = array.array("f")
    values.frombytes(bytes(data[at_val:]))
    if sys.byteorder == "big":
        values.byteswap()
    tables = []
    for at, name, count, first, start, step in directory:
        vals = tuple(values[first:first + count])
        bad = next((j for j, v in enumerate(vals) if not math.isfinite(v)), None)
        if bad is not None:
            raise MapFormatError(f"table {name}: value {bad} at offset "
                                 f"{at_val + 4 * (first + bad)} is not finite")
        try:
            tables.append(ComponentTable(name, start, step, vals))
        except ValueError as exc:
            raise MapFormatError(f"table record at offset {at}: {exc}") from None
    try:
        return TablesPayload(machine, version, MapEncoding(enc), valid_s, increment,
                             tuple(axes), tuple(spindles), tuple(outputs), tuple(tables),
                             tuple(locations), tuple(thermal), limit_mm, limit_deg)
    except ValueError as exc:
        raise MapFormatError(f"tables map: {exc}") from None


def _axis_at(data: bytes, at: int, i: int) -> ChainAxis:
    raw, flags, pad, *nums = _AXIS.unpack_from(data, at)
    if flags & ~3 or any(pad):
        raise MapFormatError(f"chain axis {i} at offset {at} has unknown flags 0x{flags:02x} "
                             f"or non-zero reserved bytes")
    name = _name_from(raw, f"chain axis {i} name", at)
    try:
        return ChainAxis(name, bool(flags & 1), bool(flags & 2), (nums[0], nums[1], nums[2]),
                         (nums[3], nums[4], nums[5]), (nums[6], nums[7]))
    except ValueError as exc:
        raise MapFormatError(f"chain axis {i} at offset {at}: {exc}") from None


def _spindle_at(data: bytes, at: int, i: int, names: tuple[str, ...]) -> Spindle:
    raw, mask, pad, length, *nums = _SPINDLE.unpack_from(data, at)
    name = _name_from(raw, f"spindle {i} name", at)
    if any(pad):
        raise MapFormatError(f"spindle {i} ({name}) at offset {at} has non-zero reserved "
                             f"bytes")
    if mask >> len(names) or mask == 0:
        raise MapFormatError(f"spindle {i} ({name}) at offset {at + 16}: axis mask "
                             f"0x{mask:04x} must name 1 or more of the {len(names)} chain "
                             f"axes")
    axes = tuple(n for j, n in enumerate(names) if mask >> j & 1)
    try:
        return Spindle(name, axes, length, (nums[0], nums[1], nums[2]),
                       (nums[3], nums[4], nums[5], nums[6], nums[7], nums[8]))
    except ValueError as exc:
        raise MapFormatError(f"spindle {i} at offset {at}: {exc}") from None


def _output_at(data: bytes, at: int, k: int, enc: int) -> OutputAxis:
    raw_name, flags, pad, raw = _OUT.unpack_from(data, at)
    if flags & ~1 or any(pad):
        raise MapFormatError(f"output axis {k} at offset {at} has unknown flags "
                             f"0x{flags:02x} or non-zero reserved bytes")
    if not flags & 1 and any(raw):  # "0 when absent": one encoding per map
        raise MapFormatError(f"output axis {k} at offset {at + 8}: reversal is not 0 though "
                             f"flagged absent")
    value: float = struct.unpack("<i" if enc == 1 else "<f", raw)[0]
    try:
        return OutputAxis(_name_from(raw_name, f"output axis {k} name", at),
                          value if flags & 1 else None)
    except ValueError as exc:
        raise MapFormatError(f"output axis {k} at offset {at}: {exc}") from None
