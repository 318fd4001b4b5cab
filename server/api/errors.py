"""HTTP errors the routes raise beyond FastAPI's own."""

from __future__ import annotations

from fastapi import HTTPException, status


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
