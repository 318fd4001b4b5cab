"""The golden table of ``tests/support/protocol.py`` covers every message type."""

from __future__ import annotations

from protocol import MessageType
from tests.support.protocol import GOLDEN


def test_golden_table_covers_every_message_type() -> None:
    assert {code for _, code, _ in GOLDEN} == {int(t) for t in MessageType}
