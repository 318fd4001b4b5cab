"""``ednc version``: print the installed version."""

from __future__ import annotations

import typer

from ednc import __version__


def register(app: typer.Typer) -> None:
    @app.command()
    def version() -> None:
        """Print the version of the EDNC control center."""
        typer.echo(__version__)
