#!/usr/bin/env python3
"""The project's two entry points, on a fresh machine with only Python 3.11 and pip.

    python3 tasks.py demo   # create .venv, install the project, run the demo
    python3 tasks.py test   # create .venv, install the project, run ruff, mypy and pytest

Extra arguments after ``test`` go to pytest; after ``demo`` to ``ednc demo``.
The virtual environment is rebuilt only when ``pyproject.toml`` or ``constraints.txt``
changes; ``constraints.txt`` pins the version of every package installed.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / "bin"


def run(*cmd: str | os.PathLike[str]) -> None:
    print("+", " ".join(str(c) for c in cmd), flush=True)
    proc = subprocess.Popen([str(c) for c in cmd], cwd=ROOT)
    try:
        code = proc.wait()
    except KeyboardInterrupt:
        # Ctrl-C reached the command too (one process group): let it stop in its own
        # words, then end quietly with the shell's code for SIGINT, no traceback
        try:
            code = proc.wait(timeout=30)
        except (KeyboardInterrupt, subprocess.TimeoutExpired):
            proc.kill()
            code = 130
        sys.exit(code if code >= 0 else 130)
    if code != 0:
        sys.exit(code)


def ensure_env() -> None:
    if sys.version_info < (3, 11):  # noqa: UP036 - tasks.py runs under any python3
        sys.exit(f"Python 3.11 or newer is needed, this is {sys.version.split()[0]}")
    stamp = VENV / ".installed"
    want = hashlib.sha256((ROOT / "pyproject.toml").read_bytes()
                          + (ROOT / "constraints.txt").read_bytes()).hexdigest()
    if stamp.exists() and stamp.read_text() == want and (BIN / "ednc").exists():
        return
    if not (BIN / "python").exists():
        print(f"creating {VENV}", flush=True)
        venv.create(VENV, with_pip=True)
    run(BIN / "python", "-m", "pip", "install", "--quiet", "--upgrade", "pip==26.3")
    # constraints.txt pins every package to the versions the README's figures were
    # measured with: a newer pymodbus or asyncua changes timings and behaviour
    run(BIN / "python", "-m", "pip", "install", "--quiet", "-c", "constraints.txt",
        "-e", ".[dev]")
    stamp.write_text(want)


def main(argv: list[str]) -> None:
    if not argv or argv[0] not in {"demo", "test"}:
        sys.exit(__doc__)
    ensure_env()
    if argv[0] == "demo":
        run(BIN / "ednc", "demo", *argv[1:])
    else:
        run(BIN / "ruff", "check", ".")
        run(BIN / "mypy")
        run(BIN / "python", "-m", "pytest", *(argv[1:] or ["-q"]))


if __name__ == "__main__":
    main(sys.argv[1:])
