"""Live status of the machines and of the service."""

from __future__ import annotations

import datetime as dt
from typing import Any

from pydantic import BaseModel, Field


class MachineStatus(BaseModel):
    """One machine: its link (live, in memory) and its maps (from the database)."""

    name: str
    connected: bool
    address: str | None = Field(description="Peer address of the current or last session.")
    link_state: str = Field(
        default="offline", description="What the link is doing: connected, connecting, "
        "plc_stopped, refused, unreachable, failed or offline (server/links/state.py).")
    link_reason: str = Field(default="", description="Why, as a stable label "
                             "(identity_name, byte_order, magic, no_answer, exception_02...).")
    link_text: str = Field(default="", description="Why, for the operator.")
    connected_since: dt.datetime | None
    last_seen: dt.datetime | None
    telemetry: dict[str, Any] = Field(description="The machine's last telemetry, as sent.")
    owner: str | None = Field(
        default=None,
        description="The node (EDNC_NODE_ID) serving the machine now; null when offline.")
    map_version_latest: int | None = Field(description="Newest map built for the machine.")
    map_version_sent: int | None = Field(description="Newest map sent to the machine.")
    map_version_applied: int | None = Field(description="Newest map the machine applied.")
    last_reject_reason: str | None = Field(
        description="Why the machine rejected the newest map sent, if it did."
    )


class ServiceStatus(BaseModel):
    """The service as a whole."""

    version: str
    node_id: str
    started_at: dt.datetime
    writes_enabled: bool
    mqtt_enabled: bool
    machines: int
    connected: int = Field(description="Machines some node of the plant serves now.")
    machine_status: list[MachineStatus]
