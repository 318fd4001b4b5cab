"""``ednc demo``: the whole loop on a mixed fleet of simulated machines."""

from __future__ import annotations

import typer
from rich.console import Console


def register(app: typer.Typer) -> None:
    @app.command("demo")
    def demo() -> None:
        """Measure, identify, diagnose, map and verify a mixed simulated fleet.

        Fanuc- and Siemens-style, three- and five-axis machines and the two-spindle arch
        machine; one hides a spindle growth that the diagnosis finds and the map follows.
        """
        from ednc.demo import run_numeric_demo

        console = Console()
        console.rule("EDNC control center demo")
        run_numeric_demo(console)
