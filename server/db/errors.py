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
    why : str
        Why the value cannot be shared, when that is not obvious (appended to the message).
    """

    def __init__(self, what: str, field: str, value: str, why: str = "") -> None:
        super().__init__(f"a {what} with {field} {value!r} already exists"
                         + (f": {why}" if why else ""))
        self.field = field
        self.value = value
