"""Events as the API shows them."""

from __future__ import annotations

import datetime as dt

from pydantic import BaseModel

from server.events import EventKind


class EventPublic(BaseModel):
    """Something that happened on a machine link."""

    id: int
    time: dt.datetime
    machine: str
    kind: EventKind
    detail: str
