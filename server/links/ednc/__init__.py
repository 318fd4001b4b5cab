"""The machine link: the TCP server the machines connect to and its per-connection sessions."""

from server.links.ednc.server import LinkTiming, MachineServer, Refused, telemetry_fields
from server.links.ednc.session import LinkClosed, MachineSession, Verdict

__all__ = ["LinkClosed", "LinkTiming", "MachineServer", "MachineSession", "Refused",
           "Verdict", "telemetry_fields"]
