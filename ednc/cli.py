"""The ``ednc`` console command.

Sub-commands live in :mod:`ednc.commands`, one module each, discovered at start-up.
Errors the user can fix (bad input files, unreachable services) are printed as one
line on stderr with exit code 2, never as a traceback.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys

import typer

from ednc import commands

app = typer.Typer(
    name="ednc",
    help="EDNC control center: model, identify and compensate machine tools.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


@app.callback()
def _root() -> None:
    """EDNC control center: model, identify and compensate machine tools."""


class UserError(Exception):
    """An error in the user's input: printed as one line, exit code 2."""


def _load_commands() -> None:
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        module = importlib.import_module(f"{commands.__name__}.{info.name}")
        module.register(app)


def main() -> None:
    _load_commands()
    try:
        app()
    except UserError as exc:
        print(f"ednc: error: {exc}", file=sys.stderr)
        sys.exit(2)
