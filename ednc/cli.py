"""The ``ednc`` console command.

Sub-commands live in :mod:`ednc.commands`, one module each, discovered at start-up.
Errors the user can fix (bad input files, unreachable services) are printed as one
line on stderr with exit code 2, never as a traceback.
"""

from __future__ import annotations

import importlib
import logging
import os
import pkgutil
import sys
from typing import NoReturn

import typer
from typer.core import TyperOption

from ednc import commands

_type_label = TyperOption.display_type_rich


def _flag_label(self: TyperOption, ctx: typer.Context) -> str | None:
    """No type after a flag in the help: ``--json <bool>`` read as "give a value", and
    ``--json true`` then fails (a flag takes none)."""
    if self.is_flag:
        return None
    return _type_label(self, ctx)


TyperOption.display_type_rich = _flag_label  # type: ignore[method-assign,assignment]

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


def _load_commands(only: str | None = None) -> None:
    """Register the sub-commands: every module, or only the one named ``only``."""
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        if only is None or info.name == only:
            module = importlib.import_module(f"{commands.__name__}.{info.name}")
            module.register(app)


def command_module(argv: list[str]) -> str | None:
    """The module of the sub-command ``argv`` names (``iso230-2`` lives in ``iso230``),
    None for ``--help`` or anything unknown (then every command is loaded, so help and
    typer's own "no such command" list them all)."""
    if len(argv) < 2 or argv[1].startswith("-"):
        return None
    names = {info.name for info in pkgutil.iter_modules(commands.__path__)}
    for name in (argv[1], argv[1].split("-")[0]):
        if name in names:
            return name
    return None


def main() -> None:
    # only the command asked for is imported: the others' imports (the service, plotting)
    # cost a second before a 15 s fit of a big file even starts
    _load_commands(command_module(sys.argv))
    code: int | str | None = 0
    try:
        app()
    except UserError as exc:
        print(f"ednc: error: {error_line(exc)}", file=sys.stderr)
        code = 2
    except SystemExit as exc:
        code = exc.code
    leave(code)


def leave(code: int | str | None) -> NoReturn:
    """End the command with ``code`` (``sys.exit``'s meaning).

    A command that parsed a CSV with pyarrow ends without the interpreter's finalization,
    once its output and logs are flushed: pyarrow's C++ thread pool, torn down there, now
    and then aborts the process ("terminate called without an active exception", exit -6
    instead of the command's own; apache/arrow#34314, seen once in the suite on
    ``ednc diagnose`` refusing a file). Everything the command writes is closed by then.
    """
    if "pyarrow" not in sys.modules:
        sys.exit(code)
    if isinstance(code, str):
        print(code, file=sys.stderr)
    status = code if isinstance(code, int) else (0 if code is None else 1)
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)


def error_line(exc: UserError) -> str:
    """The error as one line: a line break inside it (a file name that holds one) is
    written as ``\\n``, so that the message stays the one line scripts read."""
    return str(exc).strip().replace("\r", "\\r").replace("\n", "\\n")
