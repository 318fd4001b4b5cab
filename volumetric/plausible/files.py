"""What a file is, when it is not what a command expects: its encoding, its separators,
and the other formats people hand over by mistake.

* **UTF-16** (Excel's "Unicode text", Windows tools) is read: with a byte-order mark the
  encoding is certain, so :func:`decode_text` and :func:`utf8_stream` recode it to UTF-8.
  Without a mark, text whose every other byte is NUL is refused with the file's name.
* **A German (or French, ...) spreadsheet CSV** (``;`` between cells, ``,`` as the
  decimal mark) is refused, naming both, not read: the same locale writes ``1.234,5`` for
  1234.5, so a ``.`` in a cell could be a thousands separator or a decimal point, and a
  guess would read some numbers 1000 times off without a word. Tabs are refused alike.
* **Another format**: a Siemens CEC program (``$AN_CEC``), a Fanuc parameter or
  pitch-error file (``N10000 P..`` records, ``G10 L50``), an EDNC map payload, a model
  JSON, a machine description or a measurement CSV, given where another is expected, is
  named as what it is (:func:`what_is`).
"""

from __future__ import annotations

import codecs
import re
from typing import BinaryIO

__all__ = ["KINDS", "UTF16_BOMS", "decode_text", "dialect_problem", "utf8_stream", "what_is",
           "wrong_file"]

UTF16_BOMS = (codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)


def _utf16(head: bytes) -> bool:
    return head.startswith(UTF16_BOMS)


def _nul_text(head: bytes) -> bool:
    """Text of two-byte units without a mark: NUL at every other byte of ASCII (not a
    map payload, which has NULs of its own and is named as what it is)."""
    if head.startswith(b"EDMP"):
        return False
    sample = head[:200]
    return len(sample) >= 4 and (sample[1::2].count(0) > 0.9 * len(sample[1::2]) or
                                 sample[0::2].count(0) > 0.9 * len(sample[0::2]))


def decode_text(data: bytes, name: str) -> str:
    """``data`` as text: UTF-8 (a mark dropped) or UTF-16 with its mark.

    Raises
    ------
    ValueError
        Naming ``name``: UTF-16 without a mark, or bytes that are no UTF-8 (with the
        line and byte of the first bad one).
    """
    if _utf16(data):
        try:
            return data.decode("utf-16")
        except UnicodeDecodeError as exc:
            raise ValueError(f"{name}: UTF-16 text that cannot be decoded (byte {exc.start})"
                             ) from None
    if _nul_text(data):
        raise ValueError(f"{name}: looks like UTF-16 text without a byte-order mark; save "
                         "it as UTF-8 (in Excel: 'CSV UTF-8 (comma delimited)')")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise ValueError(f"{name}, line {line}: not UTF-8 text (byte {exc.start}: "
                         f"{data[exc.start:exc.start + 1]!r}); save it as UTF-8") from None


def utf8_stream(fh: BinaryIO, name: str) -> BinaryIO:
    """``fh`` as UTF-8 bytes: as it is, or recoded on the fly from UTF-16 with a mark
    (memory follows the read size, not the file).

    Raises
    ------
    ValueError
        UTF-16 without a mark (:func:`decode_text`).
    """
    head = fh.peek(256)[:256] if hasattr(fh, "peek") else b""
    if _utf16(head):
        recoder = codecs.StreamRecoder(fh, codecs.getencoder("utf-8"),
                                       codecs.getdecoder("utf-8"),
                                       codecs.getreader("utf-16"), codecs.getwriter("utf-16"))
        return recoder
    if _nul_text(head):
        raise ValueError(f"{name}: looks like UTF-16 text without a byte-order mark; save "
                         "it as UTF-8 (in Excel: 'CSV UTF-8 (comma delimited)')")
    return fh


_DECIMAL_COMMA = re.compile(r"(?:^|;)\s*-?\d+,\d+\s*(?:;|$)")


def dialect_problem(header: str, row: str | None, name: str) -> str | None:
    """Why a CSV is not comma-separated as the format is, or None.

    Parameters
    ----------
    header : str
        The first line.
    row : str or None
        The first line after it, to spot decimal commas.
    name : str
        The file, for the message.
    """
    if header.count(",") >= 2:
        return None
    for sep, said in ((";", "semicolons"), ("\t", "tabs")):
        if header.count(sep) >= 2:
            commas = row is not None and sep == ";" and bool(_DECIMAL_COMMA.search(row))
            locale = (" and decimal commas (a spreadsheet saved in a German, French or "
                      "similar locale)" if commas else "")
            return (f"{name}: cells are separated by {said}{locale}; the format is "
                    "comma-separated with decimal points. Not read: such a locale writes "
                    "1.234,5 for 1234.5, so a guess could read numbers 1000 times off. Save "
                    "it as 'CSV UTF-8 (comma delimited)' with '.' as the decimal separator "
                    "(or export it with 'ednc sim --campaign' / your laser software's "
                    "English locale)")
    return None


_CEC = re.compile(r"\$AN_CEC|\$MA_|\$SN_|CHANDATA\(|%_N_\w+_(MPF|INI|SPF)", re.I)
_FANUC = re.compile(r"^\s*N\d{4,5}\s*[PAQRLS]-?\d|G10\s*L5[02]", re.M)

KINDS = {
    "map": "an EDNC map payload (what 'ednc map --out' writes)",
    "siemens": "a Siemens SINUMERIK file (CEC tables or machine data: $AN_CEC, %_N_)",
    "fanuc": "a Fanuc parameter or pitch-error compensation file (N.... P.. records, "
             "G10 L50)",
    "model": "a model JSON (what 'ednc fit --out' writes)",
    "machine": "a machine description (JSON)",
    "fleet": "a fleet file",
    "measurements": "a measurement CSV",
    "tables": "a component-error table ('ednc tables export', 'ednc export --format "
              "iso230-1')",
}
"""The formats :func:`what_is` tells apart, by key."""


def what_is(head: bytes) -> str | None:
    """The key in :data:`KINDS` of a file whose first bytes are ``head``, when it is one
    of the formats people give in place of another; None when it is none of them."""
    if head.startswith(b"EDMP"):
        return "map"
    text = head.decode("utf-16" if _utf16(head) else "utf-8", errors="replace")
    if _CEC.search(text):
        return "siemens"
    if _FANUC.search(text):
        return "fanuc"
    stripped = text.lstrip()
    if stripped.startswith("{"):
        if '"ednc-model/' in text or '"components"' in text:
            return "model"
        if '"machines"' in text:
            return "fleet"
        if '"travel_mm"' in text or '"chain"' in text:
            return "machine"
        return None
    first = stripped.splitlines()[0] if stripped else ""
    if first.startswith("test") and "quantity" in first:
        return "measurements"
    if "EXX_um" in text or ("_um," in first and first.split(",")[0].endswith(("_mm", "_deg"))):
        return "tables"
    return None


def wrong_file(head: bytes, name: str, expected: str) -> str | None:
    """``"NAME: this is X, not Y"`` when ``head`` is a known format other than
    ``expected`` (a key of :data:`KINDS`), else None."""
    kind = what_is(head)
    if kind is None or kind == expected:
        return None
    return f"{name}: this is {KINDS[kind]}, not {KINDS[expected]}"
