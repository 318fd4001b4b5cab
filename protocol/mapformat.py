"""The error-map payload: what the MapChunks of one push carry, concatenated.

A binary layout a PLC can parse with fixed offsets. Unlike frames (big-endian, network
order), every multi-byte field here is **little-endian**, because the machine copies the
values straight into PMC / NC memory, which is little-endian. Layout::

    offset        size  field
         0           4  magic b"EDMP"
         4           2  format version u16 = 1
         6           1  value encoding u8: 1 = int32 increments (Fanuc), 2 = float32 mm (Siemens)
         7           1  grid dimensions D, 1..6
         8           1  output axes K, 1..16
         9           7  reserved, zero
        16          32  machine name, ASCII, NUL-padded
        48           4  map version u32 (>= 1)
        52           4  valid_s u32: seconds the map stays valid after it is applied, 0 = no limit
        56           8  increment f64, mm per count (int32 encoding, e.g. 0.001); 0 for float32
        64      24 * D  grid axes, each: name 4 ASCII NUL-padded, count u32 (>= 2),
                        start f64, step f64 (> 0); mm for X Y Z..., degrees for A B C
    64+24D      12 * K  output axes, each: name 4 ASCII NUL-padded, flags u8 (bit 0: has a
                        reversal value), reserved 3 zero, reversal int32 or float32
                        (value encoding; 0 when absent): negative-approach minus
                        positive-approach correction, added while the axis last moved in -
    64+24D+12K  4 * N * K  values, N = count_1 * ... * count_D, shape (count_1, ..., count_D, K),
                        row-major: output axis fastest, then the last grid axis

Nothing follows the values; the payload length is exactly 64 + 24 D + 12 K + 4 N K.

Format version 3 (a grid with thermal records, protocol/README.md §6.4) is exactly this
layout with 3 in the version field, followed by a trailer at T = 64 + 24 D + 12 K + 4 N K::

         T           4  thermal records H u32, 1..32
       T+4      48 * H  thermal records, the tables kind's (:class:`ThermalRecord`); each
                        names an output axis

Only a machine that set ``MapEncoding.THERMAL`` in Hello gets one; it adds, every cycle,
``-ΔE`` of each record (at its latest temperature) to the correction of the record's axis.
"""

from __future__ import annotations

import array
import math
import re
import struct
import sys
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Final

from . import _check as check
from .codes import MapEncoding
from .limits import MAX_LABEL_BYTES, MAX_MAP_BYTES, MAX_NAME_BYTES

MAP_MAGIC: Final = b"EDMP"
MAP_FORMAT_VERSION: Final = 1
GRID_THERMAL_FORMAT_VERSION: Final = 3
"""A grid map followed by thermal records (the machine applies them)."""
MAX_THERMAL: Final = 32
THERMAL_DRIFT: Final = 1
THERMAL_EXPANSION: Final = 2
MAX_GRID_DIMS: Final = 6
MAX_OUTPUTS: Final = 16
DEFAULT_INCREMENT_MM: Final = 0.001
"""Fanuc's least input increment for IS-B, the usual setting."""

_HEAD = struct.Struct("<4sHBBB7s32sIId")  # 64 bytes
_GRID = struct.Struct("<4sIdd")  # 24 bytes
_OUT = struct.Struct("<4sB3s4s")  # 12 bytes
_THERMAL = struct.Struct("<16s4sB3sddd")  # 48 bytes
_COUNT = struct.Struct("<I")  # the version-3 trailer's record count
_AXIS_RE = re.compile(r"[A-Za-z][A-Za-z0-9]{0,3}")
_LABEL = re.compile(r"[\x21-\x7e]{1,16}")
_INT32_MIN, _INT32_MAX = -(1 << 31), (1 << 31) - 1


class MapFormatError(ValueError):
    """The bytes are not a valid error-map payload; the text names the field and offset."""


@dataclass(frozen=True, slots=True)
class GridAxis:
    """One grid dimension: ``count`` nodes at ``start + i * step`` (mm or degrees)."""

    name: str
    start: float
    step: float
    count: int

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _AXIS_RE.fullmatch(self.name):
            raise ValueError(f"grid axis name must be 1 to 4 ASCII letters/digits starting "
                             f"with a letter, got {self.name!r}")
        check.finite(f"grid axis {self.name} start", self.start)
        check.finite(f"grid axis {self.name} step", self.step)
        if self.step <= 0:
            raise ValueError(f"grid axis {self.name} step must be > 0, got {self.step}")
        check.uint(f"grid axis {self.name} count", self.count, 32, minimum=2)


@dataclass(frozen=True, slots=True)
class OutputAxis:
    """One corrected axis. ``reversal`` (backlash) is the negative-approach minus the
    positive-approach correction, in the map's value unit (counts for int32, mm for
    float32), or None when the axis has no direction-dependent term."""

    name: str
    reversal: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _AXIS_RE.fullmatch(self.name):
            raise ValueError(f"output axis name must be 1 to 4 ASCII letters/digits starting "
                             f"with a letter, got {self.name!r}")
        if self.reversal is not None:
            check.finite(f"output axis {self.name} reversal", self.reversal)


@dataclass(frozen=True, slots=True)
class ThermalRecord:
    """A thermal term of the model on axis K's positioning error ``E<K><K>`` (carried by
    tables maps, format version 2, and grid maps of format version 3).

    Attributes
    ----------
    sensor : str
        Temperature label, 1..16 printable ASCII characters without spaces: exactly the
        name the Temperatures message carries (``spindle``; the center writes no
        measurement column ``T_spindle_C`` here), matched exactly by an int32 ladder
        (protocol/README.md section 6).
    axis : str
        A linear axis (a chain axis of a tables map, an output axis of a grid map).
    kind : int
        1 = drift: ``coefficient · (T - t_ref_C)`` µm, coefficient in µm/K;
        2 = expansion: ``coefficient · (T - t_ref_C) · (q - q_min) · 1e-3`` µm,
        coefficient in µm/(m·K), q and q_min in mm.
    coefficient, t_ref_C, q_min : float
    """

    sensor: str
    axis: str
    kind: int
    coefficient: float
    t_ref_C: float
    q_min: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.sensor, str) or not _LABEL.fullmatch(self.sensor) \
                or len(self.sensor) > MAX_LABEL_BYTES:
            raise ValueError(f"thermal sensor must be 1 to 16 printable ASCII characters "
                             f"without spaces, got {self.sensor!r}")
        if not isinstance(self.axis, str) or not re.fullmatch(r"[XYZ][0-9]{0,3}", self.axis):
            raise ValueError(f"thermal record axis must be a linear axis name, "
                             f"got {self.axis!r}")
        if self.kind not in (THERMAL_DRIFT, THERMAL_EXPANSION) or isinstance(self.kind, bool):
            raise ValueError(f"thermal record kind must be 1 (drift) or 2 (expansion), "
                             f"got {self.kind!r}")
        for f in ("coefficient", "t_ref_C", "q_min"):
            check.finite(f"thermal record {self.sensor}/{self.axis} {f}", getattr(self, f))
        if self.kind == THERMAL_DRIFT and self.q_min != 0:
            raise ValueError(f"thermal record {self.sensor}/{self.axis}: a drift has q_min 0, "
                             f"got {self.q_min!r}")


def pack_thermal(th: ThermalRecord) -> bytes:
    """The 48-byte wire record of a thermal term (both map kinds)."""
    return _THERMAL.pack(_name_field(th.sensor, 16), _name_field(th.axis, 4), th.kind,
                         bytes(3), float(th.coefficient), float(th.t_ref_C), float(th.q_min))


def thermal_at(data: bytes, at: int, i: int) -> ThermalRecord:
    """Thermal record ``i`` at offset ``at``; MapFormatError names the field and offset."""
    raw_sensor, raw_axis, kind, pad, coef, t_ref, q_min = _THERMAL.unpack_from(data, at)
    if any(pad):
        raise MapFormatError(f"thermal record {i} at offset {at} has non-zero reserved bytes")
    sensor = _name_from(raw_sensor, f"thermal record {i} sensor", at)
    axis = _name_from(raw_axis, f"thermal record {i} axis", at + 16)
    try:
        return ThermalRecord(sensor, axis, kind, coef, t_ref, q_min)
    except ValueError as exc:
        raise MapFormatError(f"thermal record {i} at offset {at}: {exc}") from None


def _f32(value: float) -> float:
    """``value`` rounded to the nearest float32 (what the wire will carry)."""
    try:
        rounded: float = struct.unpack("<f", struct.pack("<f", value))[0]
    except OverflowError:
        raise ValueError(f"{value} does not fit a float32") from None
    return rounded


def checked_output(encoding: MapEncoding, o: OutputAxis) -> OutputAxis:
    """``o`` with its reversal in the encoding's unit: a whole int32 count, or rounded to
    float32 (what the wire will carry); ValueError when it does not fit."""
    if o.reversal is None:
        return o
    if encoding is MapEncoding.INT32_INCREMENTS:
        r = o.reversal
        if r != int(r) or not _INT32_MIN <= r <= _INT32_MAX:
            raise ValueError(f"output axis {o.name} reversal must be an int32 count for "
                             f"an int32 map, got {r}")
        return OutputAxis(o.name, int(r))
    return OutputAxis(o.name, _f32(o.reversal))


@dataclass(frozen=True, slots=True)
class ErrorMapPayload:
    """A decoded error map.

    ``values`` holds the raw little-endian values (4 bytes each) in the order of the
    module docstring; ``np.frombuffer(p.values, p.dtype).reshape(p.shape)`` gives the
    array, in counts of ``increment_mm`` (int32) or in mm (float32). Float32 reversal
    values are rounded to float32 on construction, so what you build is what arrives.
    """

    machine: str
    version: int
    encoding: MapEncoding
    grid: tuple[GridAxis, ...]
    outputs: tuple[OutputAxis, ...]
    values: bytes
    increment_mm: float = DEFAULT_INCREMENT_MM
    valid_s: int = 0
    thermal: tuple[ThermalRecord, ...] = ()
    """Thermal records the machine applies (format version 3 when any; each names an
    output axis)."""

    def __post_init__(self) -> None:
        check.name("map machine", self.machine, MAX_NAME_BYTES)
        check.uint("map version", self.version, 32, minimum=1)
        check.member("map encoding", self.encoding, MapEncoding)
        if self.encoding not in (MapEncoding.INT32_INCREMENTS, MapEncoding.FLOAT32_MM):
            raise ValueError(f"map encoding must be exactly one MapEncoding, "
                             f"got {self.encoding!r}")
        check.finite("map increment_mm", self.increment_mm)
        if self.encoding is MapEncoding.INT32_INCREMENTS and not 0 < self.increment_mm <= 1:
            raise ValueError(f"int32 map increment_mm must be in (0, 1] mm, "
                             f"got {self.increment_mm}")
        if self.encoding is MapEncoding.FLOAT32_MM and self.increment_mm != 0:
            raise ValueError(f"float32 map increment_mm must be 0, got {self.increment_mm}")
        check.uint("map valid_s", self.valid_s, 32)
        if not isinstance(self.grid, tuple) or not 1 <= len(self.grid) <= MAX_GRID_DIMS:
            raise ValueError(f"map grid must be a tuple of 1 to {MAX_GRID_DIMS} GridAxis")
        if not isinstance(self.outputs, tuple) or not 1 <= len(self.outputs) <= MAX_OUTPUTS:
            raise ValueError(f"map outputs must be a tuple of 1 to {MAX_OUTPUTS} OutputAxis")
        if not all(isinstance(g, GridAxis) for g in self.grid):
            raise ValueError("map grid must hold GridAxis objects")
        if not all(isinstance(o, OutputAxis) for o in self.outputs):
            raise ValueError("map outputs must hold OutputAxis objects")
        check.unique("map grid", [g.name for g in self.grid])
        check.unique("map outputs", [o.name for o in self.outputs])
        outputs = tuple(self._checked_output(o) for o in self.outputs)
        object.__setattr__(self, "outputs", outputs)
        if not isinstance(self.thermal, tuple) or len(self.thermal) > MAX_THERMAL:
            raise ValueError(f"map thermal must be a tuple of at most {MAX_THERMAL} "
                             f"ThermalRecord")
        for r in self.thermal:
            if not isinstance(r, ThermalRecord):
                raise ValueError("map thermal must hold ThermalRecord objects")
            if r.axis not in [o.name for o in outputs]:  # its correction goes there
                raise ValueError(f"thermal record {r.sensor}: axis {r.axis} is not an "
                                 f"output axis")
        if not isinstance(self.values, bytes):
            raise ValueError(f"map values must be bytes, got {type(self.values).__name__}")
        if self.size > MAX_MAP_BYTES:
            raise ValueError(f"map of shape {self.shape} needs {self.size} bytes, "
                             f"limit {MAX_MAP_BYTES}")
        want = 4 * math.prod(self.shape)
        if len(self.values) != want:
            raise ValueError(f"map values are {len(self.values)} bytes, shape {self.shape} "
                             f"needs {want}")
        if self.encoding is MapEncoding.FLOAT32_MM:
            bad = _first_non_finite(self.values)
            if bad is not None:
                raise ValueError(f"map value {bad} (flat index) is not finite")

    def _checked_output(self, o: OutputAxis) -> OutputAxis:
        return checked_output(self.encoding, o)

    @property
    def shape(self) -> tuple[int, ...]:
        """``(count_1, ..., count_D, K)``."""
        return (*(g.count for g in self.grid), len(self.outputs))

    @property
    def dtype(self) -> str:
        """NumPy dtype string of ``values``: ``"<i4"`` or ``"<f4"``."""
        return "<i4" if self.encoding is MapEncoding.INT32_INCREMENTS else "<f4"

    @property
    def size(self) -> int:
        """Length of the encoded payload in bytes."""
        trailer = _COUNT.size + _THERMAL.size * len(self.thermal) if self.thermal else 0
        return (_HEAD.size + _GRID.size * len(self.grid) + _OUT.size * len(self.outputs)
                + 4 * math.prod(self.shape) + trailer)

    @property
    def format_version(self) -> int:
        """1, or 3 when the map carries thermal records."""
        return GRID_THERMAL_FORMAT_VERSION if self.thermal else MAP_FORMAT_VERSION

    def value_array(self) -> array.array[int] | array.array[float]:
        """The values as a flat ``array.array`` in native byte order."""
        return _unpack_values(self.encoding, self.values)


def _unpack_values(encoding: MapEncoding, raw: bytes) -> array.array[int] | array.array[float]:
    arr: array.array[int] | array.array[float]
    arr = array.array("i") if encoding is MapEncoding.INT32_INCREMENTS else array.array("f")
    arr.frombytes(raw)
    if sys.byteorder == "big":
        arr.byteswap()
    return arr


def _first_non_finite(raw: bytes) -> int | None:
    arr = _unpack_values(MapEncoding.FLOAT32_MM, raw)
    for i, v in enumerate(arr):
        if not math.isfinite(v):
            return i
    return None


def pack_values(encoding: MapEncoding, values: Iterable[float]) -> bytes:
    """Pack a flat sequence (ints for int32, mm for float32) as little-endian map values.

    NumPy callers can use ``arr.astype(payload.dtype).tobytes()`` instead.
    """
    arr: array.array[int] | array.array[float]
    if encoding is MapEncoding.INT32_INCREMENTS:
        ints = list(values)
        if bad := [v for v in ints if v != int(v)]:
            raise ValueError(f"int32 map values must be whole counts, got {bad[0]}")
        try:
            arr = array.array("i", (int(v) for v in ints))
        except OverflowError:
            raise ValueError("int32 map values must lie in [-2**31, 2**31 - 1]") from None
    else:
        arr = array.array("f", values)
    if sys.byteorder == "big":
        arr.byteswap()
    return arr.tobytes()


def _name_field(name: str, size: int) -> bytes:
    return name.encode("ascii").ljust(size, b"\0")


def encode_map(payload: ErrorMapPayload) -> bytes:
    """The wire bytes of ``payload`` (layout in the module docstring)."""
    int32 = payload.encoding is MapEncoding.INT32_INCREMENTS
    parts = [_HEAD.pack(MAP_MAGIC, payload.format_version, payload.encoding, len(payload.grid),
                        len(payload.outputs), bytes(7), _name_field(payload.machine, 32),
                        payload.version, payload.valid_s, float(payload.increment_mm))]
    parts += [_GRID.pack(_name_field(g.name, 4), g.count, float(g.start), float(g.step))
              for g in payload.grid]
    for o in payload.outputs:
        r = 0 if o.reversal is None else o.reversal
        raw = struct.pack("<i", int(r)) if int32 else struct.pack("<f", r)
        parts.append(_OUT.pack(_name_field(o.name, 4), o.reversal is not None, bytes(3), raw))
    parts.append(payload.values)
    if payload.thermal:
        parts.append(_COUNT.pack(len(payload.thermal)))
        parts += [pack_thermal(th) for th in payload.thermal]
    return b"".join(parts)


def _name_from(raw: bytes, what: str, offset: int) -> str:
    text, _, pad = raw.partition(b"\0")
    if pad.strip(b"\0"):
        raise MapFormatError(f"{what} at offset {offset} has bytes after its NUL padding")
    try:
        return text.decode("ascii")
    except UnicodeDecodeError:
        raise MapFormatError(f"{what} at offset {offset} is not ASCII: {text!r}") from None


def decode_map(data: bytes) -> ErrorMapPayload:
    """Parse and check an error-map payload.

    Raises
    ------
    MapFormatError
        Any deviation from the layout: wrong magic or version, unknown encoding, reserved
        bytes set, a bad name, a length that does not match the header, non-finite
        values; the text says which field and where.
    """
    if len(data) < _HEAD.size:
        raise MapFormatError(f"map payload is {len(data)} bytes, shorter than the "
                             f"{_HEAD.size}-byte header")
    (magic, fmt, enc, n_dims, n_out, reserved, machine_raw, version, valid_s,
     increment) = _HEAD.unpack_from(data, 0)
    if magic != MAP_MAGIC:
        raise MapFormatError(f"map magic is {magic!r}, expected {MAP_MAGIC!r}")
    if fmt not in (MAP_FORMAT_VERSION, GRID_THERMAL_FORMAT_VERSION):
        raise MapFormatError(f"map format version {fmt} at offset 4, a grid map is version "
                             f"{MAP_FORMAT_VERSION} or {GRID_THERMAL_FORMAT_VERSION}")
    if enc not in (MapEncoding.INT32_INCREMENTS, MapEncoding.FLOAT32_MM):
        raise MapFormatError(f"map value encoding {enc} at offset 6 is unknown (1 or 2)")
    encoding = MapEncoding(enc)
    if not 1 <= n_dims <= MAX_GRID_DIMS:
        raise MapFormatError(f"map has {n_dims} grid dimensions, 1 to {MAX_GRID_DIMS} allowed")
    if not 1 <= n_out <= MAX_OUTPUTS:
        raise MapFormatError(f"map has {n_out} output axes, 1 to {MAX_OUTPUTS} allowed")
    if any(reserved):
        raise MapFormatError("map header reserved bytes 9..15 are not zero")
    machine = _name_from(machine_raw, "machine name", 16)
    grid_at = _HEAD.size
    out_at = grid_at + _GRID.size * n_dims
    values_at = out_at + _OUT.size * n_out
    if len(data) < values_at:
        raise MapFormatError(f"map payload is {len(data)} bytes, its axis tables need "
                             f"{values_at}")
    try:
        grid = []
        for i in range(n_dims):
            at = grid_at + _GRID.size * i
            raw_name, count, start, step = _GRID.unpack_from(data, at)
            grid.append(GridAxis(_name_from(raw_name, f"grid axis {i} name", at),
                                 start, step, count))
        outputs = []
        for k in range(n_out):
            at = out_at + _OUT.size * k
            raw_name, flags, pad, raw = _OUT.unpack_from(data, at)
            if flags & ~1 or any(pad):
                raise MapFormatError(f"output axis {k} at offset {at} has unknown flags "
                                     f"0x{flags:02x} or non-zero reserved bytes")
            if not flags & 1 and any(raw):  # "0 when absent": one encoding per map
                raise MapFormatError(f"output axis {k} at offset {at + 8}: reversal is not "
                                     f"0 though flagged absent")
            value: float = struct.unpack("<i" if enc == 1 else "<f", raw)[0]
            outputs.append(OutputAxis(_name_from(raw_name, f"output axis {k} name", at),
                                      value if flags & 1 else None))
        nodes = math.prod(g.count for g in grid)
        values_end = values_at + 4 * nodes * n_out
        thermal = (_trailer(data, values_end, [o.name for o in outputs])
                   if fmt == GRID_THERMAL_FORMAT_VERSION else [])
        want = values_end + (_COUNT.size + _THERMAL.size * len(thermal) if thermal else 0)
        if len(data) != want:
            raise MapFormatError(f"map payload is {len(data)} bytes, its header describes "
                                 f"{want} ({nodes} nodes x {n_out} axes x 4 bytes + "
                                 f"{values_at} header"
                                 f"{f' + {len(thermal)} thermal records' if thermal else ''})")
        return ErrorMapPayload(machine, version, encoding, tuple(grid), tuple(outputs),
                               bytes(data[values_at:values_end]), increment, valid_s,
                               tuple(thermal))
    except MapFormatError:
        raise
    except ValueError as exc:
        raise MapFormatError(f"map payload: {exc}") from None


def _trailer(data: bytes, at: int, outputs: list[str]) -> list[ThermalRecord]:
    """The thermal records of a version-3 grid map, whose trailer starts at ``at``."""
    if len(data) < at + _COUNT.size:
        raise MapFormatError(f"map payload is {len(data)} bytes, a version-3 map needs its "
                             f"thermal record count at offset {at}")
    (count,) = _COUNT.unpack_from(data, at)
    if not 1 <= count <= MAX_THERMAL:
        raise MapFormatError(f"map has {count} thermal records (offset {at}), 1 to "
                             f"{MAX_THERMAL} in a version-3 map")
    first = at + _COUNT.size
    if len(data) < first + _THERMAL.size * count:
        raise MapFormatError(f"map payload is {len(data)} bytes, its {count} thermal records "
                             f"need {first + _THERMAL.size * count}")
    records = []
    for i in range(count):
        rec = thermal_at(data, first + _THERMAL.size * i, i)
        if rec.axis not in outputs:
            raise MapFormatError(f"thermal record {i} at offset {first + _THERMAL.size * i + 16}"
                                 f": axis {rec.axis} is not an output axis "
                                 f"({' '.join(outputs)})")
        records.append(rec)
    return records
