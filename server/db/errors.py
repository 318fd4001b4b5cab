"""Errors the repository layer raises; the API turns them into HTTP statuses."""

from __future__ import annotations


class DuplicateError(ValueError):
    """A row would repeat a value that must be unique (HTTP 409 in the API).

    Attributes
    ----------
    field : str
        The unique field, e.g. ``"name"`` or ``"ip"``.
    value : str
        The value that is already taken.
    """

    def __init__(self, what: str, field: str, value: str) -> None:
        super().__init__(f"a {what} with {field} {value!r} already exists")
        self.field = field
        self.value = value
