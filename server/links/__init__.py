"""Every link between the center and a machine, side by side.

* :mod:`server.links.base`: the one interface the scheduler and the intake use
  (:class:`~server.links.base.Link`), whichever the link;
* :mod:`server.links.ednc`: the TCP server that machines running the EDNC client log in
  to (protocol/README.md sections 1-12);
* :mod:`server.links.window`: the center's session over a window of controller memory
  (protocol/README.md section 13), on a memory backend per controller interface, chosen
  by the link's name through :data:`BACKENDS` (python-can's ``interfaces`` registry is
  the model): :mod:`server.links.modbus` (Fanuc PMC through Modbus/TCP),
  :mod:`server.links.opcua` (SINUMERIK PLC through OPC UA);
* :mod:`server.links.state`, :mod:`server.links.pacing`: what a link is doing and why,
  and how often it is tried again;
* :mod:`server.links.sinumerik_sd`: a SINUMERIK with nothing of ours in its PLC, whose
  temperature compensation setting data the center writes (planner
  :mod:`server.links.sdwrites`, service :mod:`server.links.sdservice`);
* :mod:`server.links.discover`: the probes of ``ednc discover``.

A fourth link (an S7 data block through python-snap7, a Beckhoff ADS symbol) is one
module with a ``memory_for_link(spec, ip)`` function returning a
:class:`~server.links.window.memory.MemoryClient`, one line in :data:`BACKENDS` and its
settings' model in :mod:`server.schemas.link`.
"""

from __future__ import annotations

import importlib
from typing import Any, Final

from server.links.window.memory import LinkError, MemoryClient

__all__ = ["BACKENDS", "memory_for"]

BACKENDS: Final[dict[str, str]] = {
    "modbus": "server.links.modbus:memory_for_link",
    "opcua": "server.links.opcua:memory_for_link",
}
"""Link name (a registration's ``link.kind``) -> ``module:function`` making its memory
client from the link's settings and the machine's ip. Modules are imported on first use,
so a center without OPC UA machines never imports asyncua."""


def memory_for(spec: Any, ip: str) -> MemoryClient:
    """The memory client of a registration's link (the machine's ip where the link names
    no host).

    Raises
    ------
    LinkError
        No backend of that name, or the backend refuses the settings (a password
        reference not set...).
    """
    where = BACKENDS.get(getattr(spec, "kind", ""))
    if where is None:
        raise LinkError(f"no link backend {getattr(spec, 'kind', None)!r}; known: "
                        f"{', '.join(sorted(BACKENDS))}", state="refused", reason="backend")
    module, _, function = where.partition(":")
    factory = getattr(importlib.import_module(module), function)
    memory: MemoryClient = factory(spec, ip)
    return memory
