"""The measurement CSV of ``shared/spec/formats.md`` section 2: reader, writer and container.

One row is one reading: commanded machine coordinates, the direction each axis last moved,
the sensing direction ``u`` and the reading ``value`` (µm for a displacement, µrad for an
angle), plus any number of ``T_<sensor>_C`` temperature columns and free extra columns.

Choices this module makes where the format leaves room (all documented on the functions):

- Required columns: ``test run time_s x_mm y_mm z_mm dir_x dir_y dir_z tool_mm quantity
  ux uy uz value``. Optional: ``a_deg b_deg c_deg`` (absent = 0.0), ``spindle``,
  ``T_<sensor>_C``, anything else (kept in :attr:`Measurements.extra`).
- ``u`` must be a unit vector within ``U_NORM_TOL`` (| |u| - 1 | <= 1e-3): loose enough for
  vectors written with four decimals (1/sqrt(3) as 0.5774 is 8e-5 off), tight enough to catch a
  vector in the wrong unit or a missing component. ``u`` is stored as read, not renormalised,
  so a file round-trips bit for bit.
- ``run`` must hold integers (``3`` or ``3.0``); ``dir_*`` must be -1, 0 or +1.
- Temperatures and every required numeric column must be finite (``nan``/``inf`` rejected).
  Extra columns are not judged: a column whose every cell parses as a float is kept as
  float64 (``nan`` included), any other as strings.
- A blank line is an error unless only blank lines follow it (a trailing newline or two is a
  common editor artefact, not a reading). A header without readings is an error.

Reading goes block by block (:mod:`volumetric.measure.csvblocks`, a few MB each): pyarrow's
CSV parser turns a block into typed columns at C speed (about 3 s for 2 million readings of
20 columns, 500 MB); a block it refuses, a block with quotes, or one whose row count
disagrees with its lines goes the careful way (about 1.2 s per 100 000 rows): the
:mod:`csv` module cell by cell, which finds and names the line and column of the problem.
Both paths end in the same validation, so they cannot disagree on what a file means.
:func:`read_measurement_blocks` hands the validated blocks out one at a time, for
identification that accumulates its normal equations (memory follows the block, not the
file); :func:`read_measurements` joins them.
"""

from __future__ import annotations

import contextlib
import csv
import io
import itertools
import queue
import re
import threading
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, BinaryIO, TextIO, TypeVar

import numpy as np
from numpy.typing import NDArray

from volumetric.measure.csvblocks import RawText, TextBlock, parse_block, text_blocks

__all__ = [
    "OPTIONAL_ROTARY",
    "REQUIRED_COLUMNS",
    "U_NORM_TOL",
    "MeasurementFormatError",
    "Measurements",
    "Progress",
    "read_measurement_blocks",
    "read_measurements",
    "subsample",
    "write_measurements",
]

REQUIRED_COLUMNS: tuple[str, ...] = (
    "test", "run", "time_s", "x_mm", "y_mm", "z_mm", "dir_x", "dir_y", "dir_z",
    "tool_mm", "quantity", "ux", "uy", "uz", "value",
)  # fmt: skip
OPTIONAL_ROTARY: tuple[str, str, str] = ("a_deg", "b_deg", "c_deg")
U_NORM_TOL = 1e-3
"""Largest accepted | |u| - 1 | of a row's sensing direction."""

_TEXT_COLUMNS = frozenset({"test", "quantity", "spindle"})
_NUMERIC_REQUIRED = tuple(c for c in REQUIRED_COLUMNS if c not in _TEXT_COLUMNS)
_TEMPERATURE = re.compile(r"^T_(.+)_C$")
_QUANTITIES = ("displacement", "angle")


class MeasurementFormatError(ValueError):
    """A measurement file that does not follow the format; names the line and column.

    Attributes
    ----------
    line : int or None
        1-based line number in the file (the header is line 1), when one line is at fault.
    column : str or None
        The column name, when one column is at fault.
    """

    def __init__(self, source: str, message: str, *, line: int | None = None,
                 column: str | None = None) -> None:
        where = source
        if line is not None:
            where += f", line {line}"
        if column is not None:
            where += f", column {column!r}"
        super().__init__(f"{where}: {message}")
        self.line = line
        self.column = column


FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False, slots=True)
class Measurements:
    """Readings of a measurement campaign, column-wise; every array has length N.

    Attributes
    ----------
    test : ndarray of str, shape (N,)
        Test label, e.g. ``X-positioning`` or ``diag-PPP``.
    run : ndarray of int64, shape (N,)
        Run (cycle) number within the test.
    time_s : ndarray of float64, shape (N,)
        Seconds since the campaign started.
    q : ndarray of float64, shape (N, 6)
        Commanded x, y, z (mm) and a, b, c (degrees); rotary columns absent from the file
        are 0.0.
    direction : ndarray of int8, shape (N, 3)
        ``dir_x, dir_y, dir_z``: -1, 0 or +1, the direction each linear axis last moved.
    tool_mm : ndarray of float64, shape (N,)
        Tool length (mm).
    is_angle : ndarray of bool, shape (N,)
        True where ``quantity`` is ``angle`` (value in µrad), False for ``displacement`` (µm).
    u : ndarray of float64, shape (N, 3)
        Sensing direction (displacement) or rotation axis (angle), unit length within
        :data:`U_NORM_TOL`, stored as given.
    value : ndarray of float64, shape (N,)
        The reading: µm for a displacement, µrad for an angle.
    has_rotary : tuple of 3 bool
        Whether ``a_deg``, ``b_deg``, ``c_deg`` were present.
    temperatures : dict of str to ndarray of float64, shape (N,)
        °C, keyed by the *sensor name*: column ``T_t1_C`` is sensor ``t1``.
    temperature_columns : dict of str to str
        Sensor name to its column name (``"t1" -> "T_t1_C"``), in file order. Reports that
        name "the temperature column" (the ``sensor`` key of ``ednc diagnose``) can use
        either; this mapping makes both available.
    spindle : ndarray of str, shape (N,), or None
        Which tool tip, on a multi-spindle machine; None when the column is absent.
    extra : dict of str to ndarray, shape (N,)
        Every other column: float64 when all its cells are numbers, str otherwise.
    """

    test: NDArray[np.str_]
    run: NDArray[np.int64]
    time_s: FloatArray
    q: FloatArray
    direction: NDArray[np.int8]
    tool_mm: FloatArray
    is_angle: NDArray[np.bool_]
    u: FloatArray
    value: FloatArray
    has_rotary: tuple[bool, bool, bool] = (False, False, False)
    temperatures: dict[str, FloatArray] = field(default_factory=dict)
    temperature_columns: dict[str, str] = field(default_factory=dict)
    spindle: NDArray[np.str_] | None = None
    extra: dict[str, NDArray[Any]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n = self.test.shape[0]
        shapes: dict[str, tuple[int, ...]] = {
            "test": (n,), "run": (n,), "time_s": (n,), "q": (n, 6), "direction": (n, 3),
            "tool_mm": (n,), "is_angle": (n,), "u": (n, 3), "value": (n,),
        }  # fmt: skip
        for name, shape in shapes.items():
            got = getattr(self, name).shape
            if got != shape:
                raise ValueError(f"Measurements.{name} has shape {got}, expected {shape}")
        columns: list[tuple[str, str, NDArray[Any]]] = [
            ("temperatures", k, v) for k, v in self.temperatures.items()]
        columns += [("extra", k, v) for k, v in self.extra.items()]
        if self.spindle is not None:
            columns.append(("spindle", "", self.spindle))
        for group, key, arr in columns:
            if arr.shape != (n,):
                raise ValueError(f"Measurements.{group}[{key!r}] has shape {arr.shape}, "
                                 f"expected {(n,)}")
        if set(self.temperature_columns) != set(self.temperatures):
            raise ValueError("Measurements.temperature_columns must name exactly the sensors "
                             "of Measurements.temperatures")

    def __len__(self) -> int:
        return int(self.test.shape[0])

    @property
    def xyz(self) -> FloatArray:
        """Commanded linear coordinates (mm), shape (N, 3): a view of ``q[:, :3]``."""
        return self.q[:, :3]

    def select(self, rows: NDArray[np.bool_] | NDArray[np.integer[Any]] | Sequence[int]
               ) -> Measurements:
        """The readings picked by a boolean mask of shape (N,) or by integer indices.

        Raises
        ------
        ValueError
            A boolean mask whose length is not N.
        """
        idx = np.asarray(rows)
        if idx.dtype == np.bool_ and idx.shape != (len(self),):
            raise ValueError(f"mask has shape {idx.shape}, expected {(len(self),)}")
        if idx.dtype != np.bool_ and idx.size == 0:
            idx = idx.astype(np.intp)  # an empty list would otherwise index as float
        return Measurements(
            test=self.test[idx], run=self.run[idx], time_s=self.time_s[idx], q=self.q[idx],
            direction=self.direction[idx], tool_mm=self.tool_mm[idx],
            is_angle=self.is_angle[idx], u=self.u[idx], value=self.value[idx],
            has_rotary=self.has_rotary,
            temperatures={k: v[idx] for k, v in self.temperatures.items()},
            temperature_columns=dict(self.temperature_columns),
            spindle=None if self.spindle is None else self.spindle[idx],
            extra={k: v[idx] for k, v in self.extra.items()},
        )

    @staticmethod
    def concat(parts: Sequence[Measurements]) -> Measurements:
        """Readings of several campaigns one after the other.

        All parts must carry the same temperature sensors, the same extra columns (of the
        same kind, numeric or text) and either all or none a ``spindle`` column; a rotary
        column present in any part is kept (its 0.0 stands for the parts without it).

        Raises
        ------
        ValueError
            No parts, or parts whose optional columns differ.
        """
        if not parts:
            raise ValueError("Measurements.concat needs at least one part")
        first = parts[0]
        for k, p in enumerate(parts[1:], start=1):
            if p.temperature_columns != first.temperature_columns:
                raise ValueError(f"part {k} has temperature columns "
                                 f"{sorted(p.temperature_columns.values())}, part 0 has "
                                 f"{sorted(first.temperature_columns.values())}")
            if set(p.extra) != set(first.extra) or any(
                    (p.extra[c].dtype.kind == "f") != (first.extra[c].dtype.kind == "f")
                    for c in first.extra):
                raise ValueError(f"part {k} has extra columns {sorted(p.extra)} that differ "
                                 f"from part 0's {sorted(first.extra)} (or in kind)")
            if (p.spindle is None) != (first.spindle is None):
                raise ValueError(f"part {k} and part 0 differ in having a spindle column")

        def cat(get: Any) -> Any:
            return np.concatenate([get(p) for p in parts])

        rotary = tuple(any(p.has_rotary[j] for p in parts) for j in range(3))
        return Measurements(
            test=cat(lambda p: p.test), run=cat(lambda p: p.run),
            time_s=cat(lambda p: p.time_s), q=cat(lambda p: p.q),
            direction=cat(lambda p: p.direction), tool_mm=cat(lambda p: p.tool_mm),
            is_angle=cat(lambda p: p.is_angle), u=cat(lambda p: p.u),
            value=cat(lambda p: p.value),
            has_rotary=(rotary[0], rotary[1], rotary[2]),
            temperatures={s: cat(lambda p, s=s: p.temperatures[s]) for s in first.temperatures},
            temperature_columns=dict(first.temperature_columns),
            spindle=None if first.spindle is None else cat(lambda p: p.spindle),
            extra={c: cat(lambda p, c=c: p.extra[c]) for c in first.extra},
        )


# --------------------------------------------------------------------------- reading

Progress = Callable[[int], None]
"""Called with the count of the source's bytes read so far."""


def read_measurements(source: str | Path | TextIO, *, progress: Progress | None = None
                      ) -> Measurements:
    """Read a measurement CSV (formats.md section 2).

    Parameters
    ----------
    source : str, Path or text stream
        A file path, or an open text stream positioned at the header line.
    progress : callable, optional
        Called after every block with the bytes of the source read so far.

    Returns
    -------
    Measurements
        One entry per data row, in file order.

    Raises
    ------
    MeasurementFormatError
        Anything that does not follow the format, naming the line and column: empty file, a
        missing, duplicate or unnamed column, a row with the wrong number of cells, a blank
        line between readings, a non-numeric or non-finite number, a ``run`` that is not an
        integer, a direction not in {-1, 0, +1}, a ``quantity`` other than ``displacement``
        or ``angle``, a ``u`` that is not a unit vector.
    OSError
        The file cannot be read.
    UnicodeDecodeError
        The file is not UTF-8.
    """
    parts: list[Measurements] = []
    raw: list[dict[str, RawText]] = []
    name = _name(source)
    for m, extras in _parsed_blocks(name, source, progress):
        parts.append(m)
        raw.append(extras)
    if not parts:
        raise MeasurementFormatError(name, "the file has a header but no readings", line=2)
    whole = parts[0] if len(parts) == 1 else Measurements.concat(parts)
    parts.clear()  # the blocks' arrays go as soon as the whole exists
    extra = {c: RawText.concat([r[c] for r in raw]).numbers_or_text() for c in raw[0]}
    return replace(whole, extra=_extra_kinds(extra))


def read_measurement_blocks(source: str | Path | TextIO, *, progress: Progress | None = None,
                            read_ahead: int = 2) -> Iterator[Measurements]:
    """Read a measurement CSV block by block: memory follows the block, not the file.

    Every block is validated as :func:`read_measurements` validates the file, and an
    error names the file's line. One difference: an extra column (one the format does not
    name) is judged numeric or text per block, not over the file.

    Parameters
    ----------
    source, progress
        As for :func:`read_measurements`.
    read_ahead : int
        Blocks read and parsed in a background thread ahead of the one handed out (0:
        none, everything in the caller's thread).

    Yields
    ------
    Measurements
        Consecutive readings of the file (a few tens of thousands per block).

    Raises
    ------
    MeasurementFormatError, OSError, UnicodeDecodeError
        As :func:`read_measurements`, when the block that holds the problem is reached.
    """
    name = _name(source)
    empty = True
    parsed = _parsed_blocks(name, source, progress)
    for m, extras in _read_ahead(parsed, read_ahead) if read_ahead > 0 else parsed:
        empty = False
        yield replace(m, extra=_extra_kinds({c: r.numbers_or_text() for c, r in extras.items()}))
    if empty:
        raise MeasurementFormatError(name, "the file has a header but no readings", line=2)


_T = TypeVar("_T")


def _read_ahead(items: Iterator[_T], depth: int) -> Iterator[_T]:
    """``items`` produced by a worker thread up to ``depth`` ahead of the consumer.

    Parsing (pyarrow, numpy) releases the GIL, so the next blocks are read while the
    caller works on this one: on two cores reading and identification overlap. An
    exception in the worker is raised here, in order; a consumer that stops early stops
    the worker (which closes the file).
    """
    box: queue.Queue[tuple[bool, Any]] = queue.Queue(maxsize=depth)
    stop = threading.Event()
    done = object()

    def work() -> None:
        try:
            for item in items:
                while not stop.is_set():
                    try:
                        box.put((True, item), timeout=0.1)
                        break
                    except queue.Full:
                        continue
                if stop.is_set():
                    return
            box.put((True, done))
        except BaseException as exc:  # handed to the consumer, raised there
            box.put((False, exc))
        finally:
            if stop.is_set():
                closer = getattr(items, "close", None)
                if closer is not None:
                    closer()

    worker = threading.Thread(target=work, name="measurement-read-ahead", daemon=True)
    worker.start()
    try:
        while True:
            ok, item = box.get()
            if not ok:
                raise item
            if item is done:
                return
            yield item
    finally:
        stop.set()
        while worker.is_alive():  # unblock a worker waiting to put
            with contextlib.suppress(queue.Empty):
                box.get(timeout=0.1)
        worker.join()


def _extra_kinds(extra: dict[str, NDArray[Any]]) -> dict[str, NDArray[Any]]:
    """Extra columns as the container keeps them: float64 or str."""
    return {c: a if a.dtype == np.float64 else a.astype(str) for c, a in extra.items()}


def _name(source: str | Path | TextIO) -> str:
    """What an error calls the source: its path, a stream's name, or ``<stream>``."""
    if isinstance(source, (str, Path)):
        return str(source)
    label = getattr(source, "name", "<stream>")
    return label if isinstance(label, str) else "<stream>"


def _binary(source: str | Path | TextIO) -> BinaryIO:
    if isinstance(source, (str, Path)):
        return Path(source).open("rb")
    return io.BytesIO(source.read().encode("utf-8"))


def _split_header(name: str, blocks: Iterator[TextBlock]) -> tuple[list[str], TextBlock]:
    """Header cells, and the first block of readings (the rest of the header's block)."""
    head: TextBlock | None = None
    for block in blocks:
        head = block if head is None else TextBlock(head.data + block.data, head.first_line,
                                                    block.last, block.consumed)
        if head.data.strip():
            break
    if head is None or not head.data.strip():
        raise MeasurementFormatError(name, "empty file: no header line")
    if head.data.startswith(b"\n"):
        raise MeasurementFormatError(name, "blank line before the header", line=1)
    first, _, body = head.data.partition(b"\n")
    try:
        header = [c.strip() for c in next(csv.reader([first.decode("utf-8")]))]
    except csv.Error as exc:
        raise MeasurementFormatError(name, f"unreadable header: {exc}", line=1) from None
    return header, TextBlock(body, 2, head.last, head.consumed)


def _check_header(name: str, header: list[str]) -> None:
    seen: set[str] = set()
    for k, col in enumerate(header, start=1):
        if not col:
            raise MeasurementFormatError(name, f"header cell {k} is empty", line=1)
        if col in seen:
            raise MeasurementFormatError(name, "duplicate column", line=1, column=col)
        seen.add(col)
    for col in REQUIRED_COLUMNS:
        if col not in seen:
            raise MeasurementFormatError(name, "required column is missing", line=1,
                                         column=col)


@dataclass
class _BlankLine:
    """The first blank line seen, carried from block to block: blank lines may end the
    file, never stand between readings."""

    line: int | None = None


def _parsed_blocks(name: str, source: str | Path | TextIO, progress: Progress | None
                   ) -> Iterator[tuple[Measurements, dict[str, RawText]]]:
    """The source's blocks, each parsed (pyarrow first, the careful parser when it cannot
    be sure) and validated: the readings and the extra columns' cells as written."""
    with _binary(source) as fh:
        blocks = text_blocks(fh)
        header, first = _split_header(name, blocks)
        _check_header(name, header)
        numeric = frozenset(c for c in header if _strictly_numeric(c))
        blank = _BlankLine()
        for block in itertools.chain([first], blocks):
            parsed = _parse(name, header, numeric, block, blank)
            if parsed is not None:
                columns, texts, lines = parsed
                extras = {c: texts.pop(c) for c in list(texts) if c not in _TEXT_COLUMNS}
                columns.update({c: t.text() for c, t in texts.items()})
                yield _build(name, header, columns, lines), extras
            if progress is not None:
                progress(block.consumed)


def _parse(name: str, header: list[str], numeric: frozenset[str], block: TextBlock,
           blank: _BlankLine
           ) -> tuple[dict[str, NDArray[Any]], dict[str, RawText], NDArray[np.int64] | int
                      ] | None:
    """One block's columns and the line of each row (an array, or the first row's line when
    the rows are consecutive lines); None for a block without readings."""
    data = block.data
    # trailing blank lines end a file harmlessly; the fast parser must not count them
    trimmed = data.rstrip() if block.last else data
    if blank.line is None and b'"' not in data and trimmed:
        fast = parse_block(trimmed, header, numeric)
        if fast is not None:
            numbers, texts = fast
            return dict(numbers), texts, block.first_line
    return _careful_columns(name, header, numeric, data, block.first_line, blank)


def _strictly_numeric(col: str) -> bool:
    """Columns of the format that must hold finite numbers in every row."""
    return col in _NUMERIC_REQUIRED or col in OPTIONAL_ROTARY or bool(_TEMPERATURE.match(col))


def _careful_columns(name: str, header: list[str], numeric: frozenset[str], data: bytes,
                     first_line: int, blank: _BlankLine
                     ) -> tuple[dict[str, NDArray[Any]], dict[str, RawText], NDArray[np.int64]
                                ] | None:
    """A block's columns cell by cell with the :mod:`csv` module; raises at the first cell
    that is wrong, naming its line and column."""
    reader = csv.reader(io.StringIO(data.decode("utf-8")))
    rows: list[list[str]] = []
    lines: list[int] = []
    width = len(header)
    while True:
        try:
            row = next(reader)
        except StopIteration:
            break
        except csv.Error as exc:
            raise MeasurementFormatError(name, f"unreadable CSV: {exc}",
                                         line=reader.line_num + first_line - 1) from None
        line = reader.line_num + first_line - 1
        if not row or (len(row) == 1 and not row[0].strip()):
            blank.line = line if blank.line is None else blank.line
            continue
        if blank.line is not None:
            raise MeasurementFormatError(name, "blank line between readings", line=blank.line)
        if len(row) != width:
            raise MeasurementFormatError(name, f"row has {len(row)} cells, the header has "
                                         f"{width}", line=line)
        rows.append(row)
        lines.append(line)
    if not rows:
        return None
    line_arr = np.asarray(lines, dtype=np.int64)
    columns: dict[str, NDArray[Any]] = {}
    texts: dict[str, RawText] = {}
    for k, col in enumerate(header):
        cells = [r[k] for r in rows]
        if col not in numeric:
            texts[col] = RawText.of(cells)
            continue
        try:
            columns[col] = np.asarray([float(c) for c in cells], dtype=np.float64)
        except ValueError:
            bad = next(i for i, c in enumerate(cells) if not _is_float(c))
            raise MeasurementFormatError(name, f"not a number: {cells[bad]!r}",
                                         line=int(line_arr[bad]), column=col) from None
    return columns, texts, line_arr


def _is_float(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


def _build(name: str, header: list[str], columns: dict[str, NDArray[Any]],
           lines: NDArray[np.int64] | int) -> Measurements:
    """Validate parsed columns and assemble the container (without the extra columns).

    ``lines`` is each row's line in the file, or the first row's when rows are
    consecutive lines.
    """
    n = columns["test"].shape[0]

    def line_of(i: int) -> int:
        return int(lines[i]) if isinstance(lines, np.ndarray) else lines + i

    def fail_at(mask: NDArray[np.bool_], col: str, what: str) -> None:
        bad = np.flatnonzero(mask)
        if bad.size:
            i = int(bad[0])
            cell = columns[col][i]
            cell = cell.item() if isinstance(cell, np.generic) else cell
            raise MeasurementFormatError(name, f"{what} (got {cell!r})", line=line_of(i),
                                         column=col)

    temperature_columns: dict[str, str] = {}
    for col in header:
        match = _TEMPERATURE.match(col)
        if match:
            temperature_columns[match.group(1)] = col
    finite_required = [*_NUMERIC_REQUIRED, *temperature_columns.values(),
                       *(c for c in OPTIONAL_ROTARY if c in columns)]
    for col in finite_required:
        fail_at(~np.isfinite(columns[col]), col, "not a finite number")

    run = columns["run"]
    fail_at(run != np.round(run), "run", "run must be an integer")
    fail_at(np.abs(run) > 2**53, "run", "run is out of range")
    for col in ("dir_x", "dir_y", "dir_z"):
        d = columns[col]
        fail_at((d != -1) & (d != 0) & (d != 1), col, "direction must be -1, 0 or +1")

    test = np.char.strip(columns["test"].astype(str))
    fail_at(test == "", "test", "the test label is empty")
    quantity = np.char.strip(columns["quantity"].astype(str))
    is_angle = quantity == "angle"
    fail_at(~is_angle & (quantity != "displacement"), "quantity",
            "quantity must be 'displacement' or 'angle'")

    u = np.column_stack([columns["ux"], columns["uy"], columns["uz"]])
    norm = np.sqrt(np.einsum("ij,ij->i", u, u))
    bad_u = np.flatnonzero(np.abs(norm - 1.0) > U_NORM_TOL)
    if bad_u.size:
        i = int(bad_u[0])
        raise MeasurementFormatError(
            name, f"u = {tuple(float(c) for c in u[i])} is not a unit vector "
            f"(|u| = {norm[i]:.6g}, tolerance {U_NORM_TOL:g})", line=line_of(i),
            column="ux, uy, uz")

    q = np.zeros((n, 6), dtype=np.float64)
    for j, col in enumerate(("x_mm", "y_mm", "z_mm", *OPTIONAL_ROTARY)):
        if col in columns:
            q[:, j] = columns[col]
    has = tuple(c in columns for c in OPTIONAL_ROTARY)
    return Measurements(
        test=test,
        run=run.astype(np.int64),
        time_s=columns["time_s"],
        q=q,
        direction=np.column_stack([columns["dir_x"], columns["dir_y"], columns["dir_z"]]
                                  ).astype(np.int8),
        tool_mm=columns["tool_mm"],
        is_angle=is_angle,
        u=u,
        value=columns["value"],
        has_rotary=(has[0], has[1], has[2]),
        temperatures={s: columns[c] for s, c in temperature_columns.items()},
        temperature_columns=temperature_columns,
        spindle=columns["spindle"].astype(str) if "spindle" in columns else None,
    )


def subsample(m: Measurements, limit: int, *, per_test: int = 2000, seed: int = 0
              ) -> Measurements:
    """About ``limit`` of the readings, drawn at random (seeded) within each test, in file
    order; ``m`` itself when it has no more than ``limit``.

    Every test keeps the same share of its readings, and at least ``per_test`` of them (or
    all it has): a short fine test among millions of readings keeps what makes it useful
    (the positions that resolve a ballscrew's period, a reversal). A random draw, not a
    stride, so no pattern in the order of the readings (targets visited in turn) is
    aliased. Runs, times and temperatures stay with their readings, so folds of runs and
    blocks of time are formed from the draw as from the file.

    Parameters
    ----------
    m : Measurements
    limit : int
        Readings wanted (0 or less: all).
    per_test : int
        Fewest readings a test keeps.
    seed : int
        Seed of the draw: the same file gives the same readings every time.
    """
    n = len(m)
    if limit <= 0 or n <= limit:
        return m
    rng = np.random.default_rng(seed)
    share = limit / n
    _, inverse, counts = np.unique(m.test, return_inverse=True, return_counts=True)
    by_test = np.split(np.argsort(inverse, kind="stable"), np.cumsum(counts)[:-1])
    keep = np.zeros(n, dtype=bool)
    for rows in by_test:
        take = min(rows.size, max(round(share * rows.size), per_test))
        keep[rng.choice(rows, take, replace=False)] = True
    return m.select(keep)


# --------------------------------------------------------------------------- writing


def write_measurements(target: str | Path | TextIO, m: Measurements) -> None:
    """Write readings as a measurement CSV that :func:`read_measurements` reads back equal.

    Columns come in the order of formats.md section 2 (rotary columns only where
    ``has_rotary`` says so), then ``spindle``, the extra columns, the temperature columns.
    Floats are written with :func:`repr` (the shortest text that reads back bit for bit).

    Parameters
    ----------
    target : str, Path or text stream
        File path (overwritten) or an open text stream.
    m : Measurements
        The readings.
    """
    header: list[str] = ["test", "run", "time_s", "x_mm", "y_mm", "z_mm"]
    cols: list[list[str]] = [m.test.tolist(), _ints(m.run), _floats(m.time_s)]
    cols += [_floats(m.q[:, j]) for j in range(3)]
    for j, col in enumerate(OPTIONAL_ROTARY):
        if m.has_rotary[j]:
            header.append(col)
            cols.append(_floats(m.q[:, 3 + j]))
    header += ["dir_x", "dir_y", "dir_z", "tool_mm", "quantity", "ux", "uy", "uz", "value"]
    cols += [_ints(m.direction[:, j]) for j in range(3)]
    cols += [_floats(m.tool_mm),
             np.where(m.is_angle, "angle", "displacement").tolist()]
    cols += [_floats(m.u[:, j]) for j in range(3)]
    cols.append(_floats(m.value))
    if m.spindle is not None:
        header.append("spindle")
        cols.append(m.spindle.tolist())
    for col, arr in m.extra.items():
        header.append(col)
        cols.append(_floats(arr) if arr.dtype == np.float64 else [str(v) for v in arr])
    for sensor, col in m.temperature_columns.items():
        header.append(col)
        cols.append(_floats(m.temperatures[sensor]))
    if isinstance(target, (str, Path)):
        with Path(target).open("w", encoding="utf-8", newline="") as fh:
            _write_rows(fh, header, cols)
    else:
        _write_rows(target, header, cols)


def _floats(arr: NDArray[Any]) -> list[str]:
    return [repr(v) for v in np.asarray(arr, dtype=np.float64).tolist()]


def _ints(arr: NDArray[Any]) -> list[str]:
    return [str(v) for v in np.asarray(arr).tolist()]


def _write_rows(fh: TextIO, header: list[str], cols: list[list[str]]) -> None:
    writer = csv.writer(fh, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(zip(*cols, strict=True))

