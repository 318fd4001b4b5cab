"""The README tells a newcomer only what is true: its two set-up commands exist and do what
it says, every ``ednc`` command line it shows names a real command with real options, and
the files it points to are in the repository."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import typer.main

from ednc.cli import _load_commands, app

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
_load_commands()  # once: the CLI discovers its sub-commands at start-up

# Paths the README names that are not in the repository, known and owned by the README's
# authors (reported): the modules moved into volumetric/model/ with the regrouping, and the
# formats document lives beside the repository, not in it. Remove an entry when fixed.
KNOWN_MISSING = {"shared/spec/formats.md"}


def ednc_command_lines(text: str) -> list[str]:
    """Every ``ednc ...`` invocation the README shows: code-block lines and inline code."""
    lines = re.findall(r"^\s+(?:\w+=\S+\s+|\\\n\s*)*\.venv/bin/ednc ([^\n#]*)", text, re.M)
    lines += re.findall(r"`\.venv/bin/ednc ([^`]*)`", text)
    return [line.strip() for line in lines]


def expand(line: str) -> list[list[str]]:
    """The words of a command line, one list per alternative (``export|import``)."""
    words = line.replace("[", " ").replace("]", " ").split()
    out: list[list[str]] = [[]]
    for w in words:
        if "|" in w and not w.startswith("-"):
            out = [[*o, alt] for o in out for alt in w.split("|")]
        else:
            out = [[*o, w] for o in out]
    return out


def resolve(words: list[str]) -> tuple[Any, list[str]]:
    """The (sub-)command the words name, and the options they use."""
    command: Any = typer.main.get_command(app)
    rest = list(words)
    # duck-typed: typer may bring its own copy of click, whose Group is not click.Group
    while hasattr(command, "commands") and rest and not rest[0].startswith("-"):
        name = rest.pop(0)
        sub = command.commands.get(name)
        assert sub is not None, f"README: no command {name!r} (have {sorted(command.commands)})"
        command = sub
    return command, [w for w in rest if w.startswith("--")]


def test_the_two_setup_commands_exist_and_do_what_the_readme_says() -> None:
    assert "python3 tasks.py demo" in README and "python3 tasks.py test" in README
    r = subprocess.run([sys.executable, str(ROOT / "tasks.py"), "no-such-task"],
                       capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert r.returncode != 0
    assert "tasks.py demo" in r.stderr and "tasks.py test" in r.stderr
    tasks = (ROOT / "tasks.py").read_text(encoding="utf-8")
    assert re.search(r'argv\[0\] not in \{"demo", "test"\}', tasks)
    # "set up .venv and run ruff, mypy and the whole test suite"
    for tool in ('"ruff", "check", "."', '"mypy"', '"pytest"', '"ednc", "demo"'):
        assert tool in tasks, tool


def test_the_readme_shows_ednc_command_lines() -> None:
    lines = ednc_command_lines(README)
    assert len(lines) >= 8, lines  # the parse finds the "Using it" block, not nothing
    assert any(line.startswith("sim --campaign") for line in lines)


@pytest.mark.parametrize("words", [w for line in ednc_command_lines(README)
                                   for w in expand(line)], ids=" ".join)
def test_every_ednc_command_line_in_the_readme_is_real(words: list[str]) -> None:
    command, options = resolve(words)
    known = {o for p in command.params for o in (*p.opts, *p.secondary_opts)}
    unknown = [o for o in options if o not in known]
    assert not unknown, f"README: ednc {' '.join(words)}: no option {unknown}"


def test_the_paths_the_readme_names_exist() -> None:
    named = set(re.findall(r"`([\w./-]+\.(?:py|md|yml|yaml|toml|json|csv|txt))`", README))
    named |= set(re.findall(r"`((?:[\w-]+/)+)`", README))
    assert len(named) > 10, named
    missing = {p for p in named if not (ROOT / p).exists()}
    assert missing <= KNOWN_MISSING, f"README names files that are not there: " \
                                     f"{sorted(missing - KNOWN_MISSING)}"


def test_the_checks_can_fail() -> None:
    with pytest.raises(AssertionError, match="no command 'fitt'"):
        resolve(["fitt", "--machine", "m.json"])
    command, options = resolve(["tables", "export", "--machine", "m", "--bogus"])
    assert command.name == "export" and options == ["--machine", "--bogus"]
    assert expand("tables export|import ...") == [["tables", "export", "..."],
                                                  ["tables", "import", "..."]]
