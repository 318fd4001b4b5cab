import subprocess
import sys
from pathlib import Path

from ednc import __version__


def test_console_command_prints_version() -> None:
    ednc = Path(sys.executable).parent / "ednc"
    out = subprocess.run([str(ednc), "version"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == __version__


def test_each_command_is_found_in_the_module_that_registers_it() -> None:
    """``ednc X`` imports only X's module: the lookup must find it for every command."""
    import importlib
    import pkgutil

    import typer

    from ednc import commands
    from ednc.cli import command_module

    seen = 0
    for info in pkgutil.iter_modules(commands.__path__):
        app = typer.Typer()
        importlib.import_module(f"ednc.commands.{info.name}").register(app)
        names = [c.name or (c.callback.__name__ if c.callback else "")
                 for c in app.registered_commands]
        names += [g.name or "" for g in app.registered_groups]
        for name in names:
            name = name.replace("_", "-")
            assert command_module(["ednc", name, "--help"]) == info.name, name
            seen += 1
    assert seen >= 12
    assert command_module(["ednc", "--help"]) is None
    assert command_module(["ednc"]) is None
    assert command_module(["ednc", "nosuch"]) is None
