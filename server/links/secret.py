"""Secrets a link's settings point at (never the secrets themselves: a registration's
description is returned by the API), and the OPC UA backend's entry in the registry."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from server.links.window.memory import LinkError, MemoryClient

__all__ = ["opcua_memory_for_link", "read_secret"]


def read_secret(ref: str) -> str:
    """The text a secret reference points at: ``env:NAME`` or ``file:/path``.

    Raises
    ------
    LinkError
        The variable is unset or the file cannot be read (the text says which).
    """
    kind, _, where = ref.partition(":")
    if kind == "env":
        value = os.environ.get(where)
        if value is None:
            raise LinkError(f"the password reference {ref!r}: variable {where} is not set",
                            state="refused", reason="password_ref")
        return value
    if kind == "file":
        try:
            return Path(where).read_text(encoding="utf-8").strip()
        except OSError as exc:
            raise LinkError(f"the password reference {ref!r}: {exc.strerror}",
                            state="refused", reason="password_ref") from None
    raise LinkError(f"the password reference {ref!r}: env:NAME or file:/path",
                    state="refused", reason="password_ref")


def opcua_memory_for_link(spec: Any, ip: str) -> MemoryClient:
    """An OPC UA link's memory client (asyncua imported here, on first use only)."""
    from server.links.opcua import OpcuaMemory

    memory: MemoryClient = OpcuaMemory.from_spec(spec, password=read_secret(spec.password_ref))
    return memory
