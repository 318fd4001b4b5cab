"""Every link between the center and a machine, side by side.

* :mod:`server.links.ednc`: the TCP server that machines running the EDNC client log in
  to (protocol/README.md sections 1-12);
* :mod:`server.links.window`: the center's session over a window of controller memory
  (protocol/README.md section 13), on a memory client per controller interface:
  :mod:`server.links.modbus` (Fanuc PMC through Modbus/TCP), :mod:`server.links.opcua`
  (SINUMERIK PLC through OPC UA);
* :mod:`server.links.sinumerik_sd`: a SINUMERIK with nothing of ours in its PLC, whose
  temperature compensation setting data the center writes (planner
  :mod:`server.links.sdwrites`, service :mod:`server.links.sdservice`);
* :mod:`server.links.discover`: the probes of ``ednc discover``.
"""
