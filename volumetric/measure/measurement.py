"""The measurement CSV of ``shared/spec/formats.md`` section 2: reader and writer (the
container, :class:`Measurements`, lives in :mod:`volumetric.measure.readings`).

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
- Temperatures and every required numeric column must be finite (``nan``/``inf`` rejected)
  and of a plausible size for its quantity (:mod:`volumetric.measure.plausible`: a reading
  within 10 mm or 0.1 rad, a temperature within -100..300 °C, ...).
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
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, BinaryIO, TextIO, TypeVar

import numpy as np
from numpy.typing import NDArray

from volumetric.measure.csvblocks import RawText, TextBlock, parse_block, text_blocks
from volumetric.measure.plausible import implausible
from volumetric.measure.readings import (
    _NUMERIC_REQUIRED,
    _TEMPERATURE,
    _TEXT_COLUMNS,
    OPTIONAL_ROTARY,
    REQUIRED_COLUMNS,
    U_NORM_TOL,
    MeasurementFormatError,
    Measurements,
    subsample,
)
from volumetric.plausible.columns import unit_column_problem
from volumetric.plausible.files import dialect_problem, utf8_stream, wrong_file

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


def _binary(name: str, source: str | Path | TextIO) -> BinaryIO:
    """The source as UTF-8 bytes (a UTF-16 file with its mark recoded on the fly)."""
    if isinstance(source, (str, Path)):
        fh = Path(source).open("rb")  # noqa: SIM115 - returned open, closed by the caller
        try:
            return utf8_stream(fh, name)
        except ValueError as exc:
            fh.close()
            raise MeasurementFormatError(name, str(exc).removeprefix(f"{name}: ")) from None
    return io.BytesIO(source.read().encode("utf-8"))


WANTED_UNITS = {"x": "mm", "y": "mm", "z": "mm", "a": "deg", "b": "deg", "c": "deg",
                "tool": "mm", "time": "s", "value": "um", "T": "C"}
"""The format's columns that carry a unit, by stem (formats.md section 2)."""


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
        first_text = first.decode("utf-8")
        header = [c.strip() for c in next(csv.reader([first_text]))]
    except UnicodeDecodeError as exc:
        raise MeasurementFormatError(name, f"not UTF-8 text (byte {exc.start} of the header: "
                                     f"{first[exc.start:exc.start + 1]!r}); save it as "
                                     "UTF-8", line=1) from None
    except csv.Error as exc:
        raise MeasurementFormatError(name, f"unreadable header: {exc}", line=1) from None
    other = wrong_file(head.data[:4096], name, "measurements")
    if other is not None:
        raise MeasurementFormatError(name, other.removeprefix(f"{name}: "))
    row = body.partition(b"\n")[0].decode("utf-8", errors="replace")
    dialect = dialect_problem(first_text, row, name)
    if dialect is not None:
        raise MeasurementFormatError(name, dialect.removeprefix(f"{name}: "), line=1)
    return header, TextBlock(body, 2, head.last, head.consumed)


def _check_header(name: str, header: list[str]) -> None:
    slip = unit_column_problem(header, WANTED_UNITS)
    if slip is not None:
        raise MeasurementFormatError(name, slip, line=1)
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
    with _binary(name, source) as fh:
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
    try:
        data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = block.first_line + data[:exc.start].count(b"\n")
        raise MeasurementFormatError(
            name, f"not UTF-8 text ({data[exc.start:exc.start + 1]!r}, e.g. a '°' or 'µ' "
            "saved as Latin-1 or Windows-1252); save the file as UTF-8", line=line) from None
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

    wrong = implausible(columns, is_angle, list(temperature_columns.values()), line_of)
    if wrong is not None:
        raise MeasurementFormatError(name, wrong[2], line=wrong[0], column=wrong[1])

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

