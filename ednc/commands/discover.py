"""``ednc discover``: find Modbus/TCP, OPC UA and EDNC endpoints on a network and print
what each is, with the ``link`` its registration would take (server/links/discover.py).
"""

from __future__ import annotations

import asyncio
import json
from dataclasses import asdict
from typing import Annotated

import typer

from ednc.cli import UserError


def register(app: typer.Typer) -> None:
    @app.command("discover")
    def discover_cmd(
        subnet: Annotated[str, typer.Option(
            "--subnet", help="The network to search, CIDR (e.g. 10.0.3.0/24; at most a "
                             "/20, 4096 hosts, at a time).")],
        modbus_port: Annotated[int, typer.Option(
            "--modbus-port", help="Modbus/TCP port; 0 skips Modbus.")] = 502,
        opcua_port: Annotated[int, typer.Option(
            "--opcua-port", help="OPC UA port; 0 skips OPC UA.")] = 4840,
        ednc_port: Annotated[int, typer.Option(
            "--ednc-port", help="EDNC center machine port; 0 skips it.")] = 7878,
        register_: Annotated[int, typer.Option(
            "--register", help="First holding register of the EDNC window to look at.")
        ] = 0,
        unit_id: Annotated[list[int] | None, typer.Option(
            "--unit-id", help="Modbus unit id to ask (repeat for the controllers behind a "
                              "gateway; default 1).")] = None,
        timeout_ms: Annotated[float, typer.Option(
            "--timeout-ms", help="Deadline of each probe, ms.")] = 500.0,
        as_json: Annotated[bool, typer.Option("--json", help="One JSON list.")] = False,
    ) -> None:
        """Search a network for controllers the center can reach, ready to register."""
        import logging

        from ednc.inputs import float_option, int_option
        from server.links.discover import discover, hosts_of

        # a refused connection is an answer here, not a warning
        logging.getLogger("pymodbus").setLevel(logging.CRITICAL)
        logging.getLogger("asyncua").setLevel(logging.CRITICAL)

        for value, name in ((modbus_port, "--modbus-port"), (opcua_port, "--opcua-port"),
                            (ednc_port, "--ednc-port")):
            int_option(value, name, 0, 65535)
        int_option(register_, "--register", 0, 65535)
        units = list(dict.fromkeys(unit_id or [1]))
        for unit in units:
            int_option(unit, "--unit-id", 0, 255)
        float_option(timeout_ms, "--timeout-ms", 1.0, 60_000.0, unit=" ms")
        try:
            hosts = hosts_of(subnet)
        except ValueError as exc:
            raise UserError(f"--subnet {subnet!r}: {exc}") from None
        found = asyncio.run(discover(
            hosts, modbus_port=modbus_port or None, opcua_port=opcua_port or None,
            ednc_port=ednc_port or None, register=register_, timeout_s=timeout_ms / 1000,
            unit_ids=units))
        if as_json:
            typer.echo(json.dumps([asdict(f) for f in found]))
            return
        typer.echo(f"searched {len(hosts)} hosts of {subnet}: {len(found)} endpoints")
        for f in found:
            typer.echo(f"{f.host}:{f.port}  {f.kind:6s}  {f.detail}")
            if f.link:
                typer.echo(f"    link: {json.dumps(f.link)}")
