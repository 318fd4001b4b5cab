"""``ednc demo``: the whole loop on a mixed fleet of simulated machines."""

from __future__ import annotations

import asyncio
import sys
from typing import Annotated, Any, TextIO

import typer
from rich.console import Console

PIPE_WIDTH = 400
"""Columns a console has when the output is not a terminal: wide enough that no table of
the demo is wrapped or its cells cut ("mac…"), as rich does at its default of 80."""


def demo_console(file: TextIO | None = None) -> Console:
    """The demo's console: the terminal's width on a terminal; on a pipe or a file plain
    text (no colour, no control codes) at :data:`PIPE_WIDTH` columns, so every table is
    complete and each of its rows one line."""
    stream = file if file is not None else sys.stdout
    if stream.isatty():
        return Console(file=file)
    return _PipeConsole(file=stream, width=PIPE_WIDTH, no_color=True, color_system=None,
                        force_terminal=False, soft_wrap=True)


class _PipeConsole(Console):
    """A console for a pipe: a rule is its title on a line of its own, not a line of
    :data:`PIPE_WIDTH` box characters."""

    def rule(self, title: Any = "", *args: Any, **kwargs: Any) -> None:
        self.print(title if title else "")


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

        console = demo_console()
        try:
            console.rule("EDNC control center demo: measure, identify, diagnose, map")
            prepared = run_numeric_demo(console, warm=offline)
            if offline:
                return
            from ednc.live import _reachable, run_live

            if _reachable("127.0.0.1", port):
                raise UserError(f"port {port} is taken: pass --port with a free one")
            asyncio.run(run_live(console, prepared, http_port=port, exit_after=exit_after))
        except KeyboardInterrupt:  # Ctrl-C, the README's way to stop it: no traceback
            print("ednc demo: stopped (Ctrl-C)", file=sys.stderr)
