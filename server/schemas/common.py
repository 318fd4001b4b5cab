"""Field types shared by the API schemas."""

from __future__ import annotations

import json
from typing import Annotated, Any

from pydantic import AfterValidator, Field, StringConstraints

NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9._\-]{0,63}$"
"""Machine and measurement-set names: they appear in URLs, topics and file names."""

Name = Annotated[
    str,
    StringConstraints(pattern=NAME_PATTERN),
    Field(description="1-64 letters, digits, '.', '_' or '-', starting with a letter or digit",
          examples=["vmc-01"]),
]

MAX_JSON_BYTES = 16 * 1024 * 1024


def check_json_object(value: dict[str, Any]) -> dict[str, Any]:
    """Return ``value`` if it is strict JSON of bounded size, else raise ValueError."""
    # Python's json reads NaN and Infinity, but they are not JSON: PostgreSQL refuses them
    # and other clients cannot read them back.
    try:
        text = json.dumps(value, allow_nan=False)
    except ValueError:
        raise ValueError("NaN and Infinity are not JSON numbers; use null or a finite value") \
            from None
    if len(text) > MAX_JSON_BYTES:
        raise ValueError(f"JSON object larger than {MAX_JSON_BYTES} bytes")
    return value


JsonObject = Annotated[dict[str, Any], AfterValidator(check_json_object)]
"""A JSON object that survives a round trip through any database and any JSON client."""


def _no_nul(value: str) -> str:
    if "\x00" in value:
        raise ValueError("must not contain NUL characters")
    return value


Text = Annotated[str, AfterValidator(_no_nul)]
"""Free text that a database text column can store (no NUL)."""


def _distinct(names: list[str]) -> list[str]:
    if len(set(names)) != len(names):
        raise ValueError("a set is named twice")
    return names


SetNames = Annotated[
    list[Name],
    Field(min_length=1, max_length=50, description="Names of measurement sets, used together."),
    AfterValidator(_distinct),
]
