"""A CSV file as blocks of whole lines, and a block's cells as typed columns (pyarrow).

The measurement reader (:mod:`volumetric.measure.measurement`) reads a file block by block
so that memory follows the block, not the file: a 500 MB campaign is read in blocks of
``BLOCK_BYTES`` and each block is parsed by pyarrow's C++ CSV parser straight into typed
columns (float64 for the format's numbers, strings for the rest), at 100-200 MB/s on one
core where the :mod:`csv` module manages about 10.

This module is the only one that imports pyarrow (which ships no complete type stubs): it
hands out numpy arrays and :class:`RawText`, an opaque column of cells as written.

Why pyarrow and not polars (both measured on the 2 M-reading benchmark file, see
``benchmarks/identification.py``): both parse at C speed; pyarrow's ``read_csv`` takes the
column types and the exact null handling this format needs (no cell is ever read as
missing, ``null_values=[]``), and returns columns that convert to numpy without a copy for
floats; it is also the smaller dependency of the two for what is used here.
"""

from __future__ import annotations

import io
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any, BinaryIO

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv
from numpy.typing import NDArray

__all__ = ["BLOCK_BYTES", "RawText", "TextBlock", "parse_block", "text_blocks"]

BLOCK_BYTES = 8 * 2**20
"""Bytes read per block (whole lines are added up to the next line break): about 30 000
readings of the format's 20 columns, a few MB of columns in memory per block."""

_BOM = b"\xef\xbb\xbf"


@dataclass(frozen=True, slots=True)
class TextBlock:
    """Whole lines of a CSV file.

    Attributes
    ----------
    data : bytes
        The lines, each ending in ``\\n`` (CR LF and a lone CR turned into LF), except the
        file's last line when the file does not end in a line break.
    first_line : int
        1-based line number of the block's first line in the file.
    last : bool
        True for the file's last block.
    consumed : int
        Bytes of the source read up to and including this block (for progress).
    """

    data: bytes
    first_line: int
    last: bool
    consumed: int


def text_blocks(fh: BinaryIO, block_bytes: int | None = None) -> Iterator[TextBlock]:
    """The file as consecutive blocks of whole lines, about ``block_bytes`` each
    (:data:`BLOCK_BYTES` by default, read when called).

    A block ends at a line break outside quotes (an even count of ``"`` before it), so a
    quoted cell with a line break in it stays in one block. A UTF-8 byte-order mark at the
    start is dropped.
    """
    block_bytes = BLOCK_BYTES if block_bytes is None else block_bytes
    carry = b""
    line = 1
    consumed = 0
    first = True
    pending: bytes | None = None
    while True:
        data = fh.read(block_bytes)
        consumed += len(data)
        if first:
            data = data.removeprefix(_BOM)
            first = False
        if not data:
            tail = carry
            carry = b""
        else:
            buf = carry + data
            cut = _cut(buf)
            if cut == 0:
                carry = buf
                continue
            tail, carry = buf[:cut], buf[cut:]
        if pending is not None:
            yield TextBlock(pending, line, False, consumed)
            line += pending.count(b"\n")
            pending = None
        if not data:
            yield TextBlock(_newlines(tail), line, True, consumed)
            return
        pending = _newlines(tail)


def _newlines(data: bytes) -> bytes:
    if b"\r" in data:
        data = data.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
    return data


def _cut(buf: bytes) -> int:
    """Index just past the last line break of ``buf`` that lies outside quotes (0: none).

    A lone CR counts as a line break only at the end of the file (:func:`_newlines`), so
    a block never ends between a CR and its LF.
    """
    end = buf.rfind(b"\n")
    if end < 0:
        return 0
    if b'"' not in buf:
        return end + 1
    odd = buf.count(b'"', 0, end) % 2
    while odd:
        prev = buf.rfind(b"\n", 0, end)
        if prev < 0:
            return 0
        odd ^= buf.count(b'"', prev, end) % 2
        end = prev
    return end + 1


class RawText:
    """A column's cells as written (one string per row), kept compactly until it is known
    whether the whole column is numeric."""

    __slots__ = ("_array",)

    def __init__(self, array: Any) -> None:
        self._array = array

    @staticmethod
    def of(cells: Sequence[str]) -> RawText:
        """A column from Python strings (the careful path's cells)."""
        return RawText(pa.array(list(cells), type=pa.string()))

    @staticmethod
    def concat(parts: Sequence[RawText]) -> RawText:
        return RawText(pa.chunked_array([p._array for p in parts], type=pa.string()))

    def __len__(self) -> int:
        return len(self._array)

    def numbers_or_text(self) -> NDArray[Any]:
        """float64 when every cell is a number (as Python's :class:`float` reads it,
        ``nan`` included), else the cells as a numpy string array."""
        try:
            out: NDArray[Any] = np.asarray(pc.cast(self._array, pa.float64()).to_numpy(),
                                           dtype=np.float64)
            return out
        except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
            pass
        text = self.text()
        try:
            return text.astype(np.float64)  # what Python's float takes and arrow does not
        except ValueError:
            return text

    def text(self) -> NDArray[np.str_]:
        """The cells as a numpy string array (labels repeat: decoded once per distinct
        value)."""
        arr = self._array
        if isinstance(arr, pa.ChunkedArray):
            arr = arr.combine_chunks()
        if len(arr) == 0:
            return np.zeros(0, dtype=str)
        encoded = pc.dictionary_encode(arr)
        values = np.asarray(encoded.dictionary.to_pylist(), dtype=str)
        codes = np.asarray(encoded.indices.to_numpy(zero_copy_only=False), dtype=np.intp)
        out: NDArray[np.str_] = values[codes]
        return out


def parse_block(data: bytes, header: Sequence[str], numeric: frozenset[str]
                ) -> tuple[dict[str, NDArray[np.float64]], dict[str, RawText]] | None:
    """A block's cells as columns, or None when this fast parser cannot be sure.

    Parameters
    ----------
    data : bytes
        Whole lines (:class:`TextBlock`), none of them quoted, trailing blank lines
        already removed by the caller when they end the file.
    header : sequence of str
        Column names, in file order.
    numeric : frozenset of str
        Columns parsed as float64; every other column is kept as :class:`RawText`.

    Returns
    -------
    (numbers, texts) or None
        None when the parser refuses the block (a cell that is not a number, a row of the
        wrong width, bytes that are not UTF-8) or when its row count differs from the
        block's line count (a blank line, which this parser would skip): the caller's
        careful parser then finds and names the problem.
    """
    if not data:
        return None
    types = {c: (pa.float64() if c in numeric else pa.string()) for c in header}
    try:
        table = pacsv.read_csv(
            io.BytesIO(data),
            # 1 MB chunks: pyarrow parses them on every core
            read_options=pacsv.ReadOptions(column_names=list(header), use_threads=True,
                                           block_size=1 << 20),
            parse_options=pacsv.ParseOptions(delimiter=",", newlines_in_values=False,
                                             ignore_empty_lines=True),
            convert_options=pacsv.ConvertOptions(
                column_types=types, null_values=[], strings_can_be_null=False,
                quoted_strings_can_be_null=False, check_utf8=True),
        )
    except (pa.ArrowInvalid, pa.ArrowNotImplementedError, UnicodeDecodeError):
        return None
    lines = data.count(b"\n") + (0 if data.endswith(b"\n") else 1)
    if table.num_rows != lines:
        return None
    numbers: dict[str, NDArray[np.float64]] = {}
    texts: dict[str, RawText] = {}
    for name in header:
        col = table.column(name)
        if name in numeric:
            numbers[name] = np.asarray(col.combine_chunks().to_numpy(), dtype=np.float64)
        else:
            texts[name] = RawText(col.combine_chunks())
    return numbers, texts
