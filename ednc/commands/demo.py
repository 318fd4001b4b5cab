"""``ednc demo``: the whole loop on a mixed fleet of simulated machines."""

from __future__ import annotations

import asyncio
import contextlib
from typing import Annotated

import typer
from rich.console import Console


def register(app: typer.Typer) -> None:
    @app.command("demo")
    def demo(
        port: Annotated[int, typer.Option(help="HTTP port of the dashboard and REST API.")]
        = 8080,
        exit_after: Annotated[bool, typer.Option(
            "--exit", help="Exit after the summary instead of serving until Ctrl-C.")] = False,
        offline: Annotated[bool, typer.Option(
            "--offline", help="Only the numeric loop: no center, no network.")] = False,
    ) -> None:
        """Measure, identify, diagnose, map and compensate a mixed simulated fleet.

        Fanuc- and Siemens-style, three- and five-axis machines and the two-spindle arch
        machine. The control center (REST API, dashboard, machine TCP server, MQTT when a
        broker answers on 127.0.0.1:1883) pushes each machine its map; the ISO 230-6
        diagonals are measured before and with the map the machine received; one machine
        hides a spindle growth that the diagnosis finds and the live map follows.
        """
        from ednc.cli import UserError
        from ednc.demo import run_numeric_demo

        console = Console()
        console.rule("EDNC control center demo: measure, identify, diagnose, map")
        prepared = run_numeric_demo(console, warm=offline)
        if offline:
            return
        from ednc.live import _reachable, run_live

        if _reachable("127.0.0.1", port):
            raise UserError(f"port {port} is taken: pass --port with a free one")
        with contextlib.suppress(KeyboardInterrupt):
            asyncio.run(run_live(console, prepared, http_port=port, exit_after=exit_after))
