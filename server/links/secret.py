"""Secrets a link's settings point at (never the secrets themselves: a registration's
description is returned by the API)."""

from __future__ import annotations

import os
from pathlib import Path

from server.links.window.memory import LinkError

__all__ = ["read_secret"]


def read_secret(ref: str, whose: str = "the link") -> str:
    """The text a secret reference points at: ``env:NAME`` or ``file:/path``.

    A file's trailing line break is dropped, nothing else: a password may begin or end
    with a space.

    Parameters
    ----------
    ref : str
        ``env:NAME`` or ``file:/path``.
    whose : str
        Whose secret it is, for the message (e.g. ``"OPC UA user 'ednc'"``).

    Raises
    ------
    LinkError
        The variable is unset or the file cannot be read (the text says which).
    """
    kind, _, where = ref.partition(":")
    if kind == "env":
        value = os.environ.get(where)
        if value is None:
            raise LinkError(f"password of {whose}: environment variable {where} is not set",
                            state="refused", reason="password_ref")
        return value
    if kind == "file":
        try:
            return Path(where).read_text(encoding="utf-8").rstrip("\r\n")
        except (OSError, UnicodeDecodeError) as exc:
            raise LinkError(f"password of {whose}: cannot read {where} "
                            f"({exc.__class__.__name__})", state="refused",
                            reason="password_ref") from None
    raise LinkError(f"password of {whose}: reference {ref!r} is neither env:NAME nor "
                    "file:/path", state="refused", reason="password_ref")
