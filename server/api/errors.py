"""HTTP errors the routes raise beyond FastAPI's own."""

from __future__ import annotations

from typing import Any

from fastapi import HTTPException, status
from pydantic import BaseModel


def unprocessable(loc: list[str | int], message: str, kind: str) -> HTTPException:
    """A 422 shaped like FastAPI's validation errors, so that clients parse one format.

    Parameters
    ----------
    loc
        Where the problem is, e.g. ``["body", "measurement_sets", 0]``.
    message
        What is wrong (the numeric core's message, when it found the problem).
    kind
        A short machine-readable label, e.g. ``"measurement_format"``.
    """
    return HTTPException(
        status.HTTP_422_UNPROCESSABLE_CONTENT, [{"loc": loc, "msg": message, "type": kind}]
    )


class Problem(BaseModel):
    """The body of an error reply other than 422."""

    detail: str


_Responses = dict[int | str, dict[str, Any]]

NOT_FOUND: _Responses = {
    404: {"model": Problem, "description": "No such machine (or no such item of it)."}
}
"""Documented on every route under a machine's name."""

WRITE: _Responses = {
    400: {"model": Problem,
          "description": "A body that cannot be parsed (malformed JSON or multipart)."},
    401: {"model": Problem, "description": "API key missing or wrong (X-API-Key)."},
    403: {"model": Problem, "description": "The service runs read-only (no API key set)."},
}
"""Documented on every route that needs the API key."""
