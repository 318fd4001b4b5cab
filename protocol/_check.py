"""Field checks shared by the message and map dataclasses; each raises ValueError naming the
field and the rule it breaks, so a decoder can pass the text on unchanged."""

from __future__ import annotations

import math
import re
from enum import Enum
from typing import Any

_NAME_RE = re.compile(r"[A-Za-z0-9._-]+")


def uint(field: str, value: int, bits: int, minimum: int = 0) -> None:
    """``value`` is an int in ``[minimum, 2**bits - 1]``."""
    if not isinstance(value, int) or isinstance(value, bool):
        raise ValueError(f"{field} must be an int, got {type(value).__name__}")
    if not minimum <= value < 1 << bits:
        raise ValueError(f"{field} must be in [{minimum}, {(1 << bits) - 1}], got {value}")


def finite(field: str, value: float) -> None:
    """``value`` is a finite real number (int or float)."""
    if not isinstance(value, int | float) or isinstance(value, bool):
        raise ValueError(f"{field} must be a number, got {type(value).__name__}")
    if not math.isfinite(value):
        raise ValueError(f"{field} must be finite, got {value}")


def text(field: str, value: str, max_bytes: int, *, empty: bool = True) -> None:
    """Printable text whose UTF-8 form has at most ``max_bytes`` bytes."""
    if not isinstance(value, str):
        raise ValueError(f"{field} must be a str, got {type(value).__name__}")
    if not empty and not value:
        raise ValueError(f"{field} must not be empty")
    if not value.isprintable():
        raise ValueError(f"{field} must be printable text, got {value!r}")
    size = len(value.encode("utf-8"))
    if size > max_bytes:
        raise ValueError(f"{field} is {size} bytes of UTF-8, at most {max_bytes} allowed")


def name(field: str, value: str, max_bytes: int) -> None:
    """A machine name: 1..max_bytes ASCII letters, digits, ``.``, ``_`` or ``-``."""
    if not isinstance(value, str):
        raise ValueError(f"{field} must be a str, got {type(value).__name__}")
    if not _NAME_RE.fullmatch(value) or len(value) > max_bytes:
        raise ValueError(
            f"{field} must be 1 to {max_bytes} ASCII letters, digits, '.', '_' or '-', "
            f"got {value!r}"
        )


def exact_bytes(field: str, value: bytes, size: int) -> None:
    """``value`` is immutable ``bytes`` of exactly ``size`` bytes."""
    if not isinstance(value, bytes):
        raise ValueError(f"{field} must be bytes, got {type(value).__name__}")
    if len(value) != size:
        raise ValueError(f"{field} must be {size} bytes, got {len(value)}")


def member(field: str, value: Any, enum: type[Enum]) -> None:
    """``value`` is a member of ``enum`` (not a bare int)."""
    if not isinstance(value, enum):
        raise ValueError(f"{field} must be a {enum.__name__}, got {value!r}")


def unique(field: str, names: list[str]) -> None:
    """No name appears twice."""
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise ValueError(f"{field} names {n!r} twice")
        seen.add(n)
