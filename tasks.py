#!/usr/bin/env python3
"""The project's two entry points, on a fresh machine with only Python 3.11 and pip.

    python3 tasks.py demo   # create .venv, install the project, run the demo
    python3 tasks.py test   # create .venv, install the project, run ruff, mypy and pytest
    python3 tasks.py matiec # build the IEC 61131-3 compiler the PLC tests use (test does it)

Extra arguments after ``test`` go to pytest; after ``demo`` to ``ednc demo``.
The virtual environment is rebuilt only when ``pyproject.toml`` or ``constraints.txt``
changes; ``constraints.txt`` pins the version of every package installed.
"""

from __future__ import annotations

import hashlib
import os
import shutil
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


MATIEC_SRC = ROOT / "third_party" / "matiec"
MATIEC_MK = ROOT / "third_party" / "matiec.mk"
MATIEC_BUILD = ROOT / "build" / "matiec"
# Debian packages that build MATIEC's iec2c and compile what it generates
MATIEC_TOOLS = {"flex": "flex", "bison": "bison", "g++": "g++", "gcc": "gcc", "make": "make"}


def _matiec_stamp() -> str:
    h = hashlib.sha256(MATIEC_MK.read_bytes())
    for f in sorted(MATIEC_SRC.rglob("*")):
        if f.is_file():
            h.update(str(f.relative_to(MATIEC_SRC)).encode() + b"\0" + f.read_bytes())
    return h.hexdigest()


def ensure_matiec() -> Path:
    """Build MATIEC's iec2c (third_party/matiec) into build/matiec when it is missing or
    its sources changed; install flex, bison and g++ with apt-get when missing and root.
    Returns the compiler's path."""
    iec2c = MATIEC_BUILD / "src" / "iec2c"
    stamp = MATIEC_BUILD / ".built"
    want = _matiec_stamp()
    if iec2c.exists() and stamp.exists() and stamp.read_text() == want:
        return iec2c
    missing = sorted({pkg for tool, pkg in MATIEC_TOOLS.items() if not shutil.which(tool)})
    if missing and hasattr(os, "geteuid") and os.geteuid() == 0 and shutil.which("apt-get"):
        run("apt-get", "update", "-qq")
        run("apt-get", "install", "-y", "-qq", *missing)
    elif missing:
        sys.exit(f"building the IEC 61131-3 compiler needs {', '.join(missing)}: install "
                 f"them (Debian: apt-get install {' '.join(missing)}) and run again")
    print(f"building MATIEC iec2c into {MATIEC_BUILD} (about 2 minutes, once)", flush=True)
    shutil.rmtree(MATIEC_BUILD, ignore_errors=True)
    shutil.copytree(MATIEC_SRC, MATIEC_BUILD / "src")
    run("make", "-s", "-f", MATIEC_MK, "-C", MATIEC_BUILD / "src", "-j2", "iec2c")
    stamp.write_text(want)
    return iec2c


def main(argv: list[str]) -> None:
    if argv[:1] == ["matiec"]:
        print(ensure_matiec())
        return
    if not argv or argv[0] not in {"demo", "test"}:
        sys.exit(__doc__)
    ensure_env()
    if argv[0] == "demo":
        run(BIN / "ednc", "demo", *argv[1:])
    else:
        ensure_matiec()  # the PLC program's tests compile Structured Text with it
        run(BIN / "ruff", "check", ".")
        run(BIN / "mypy")
        run(BIN / "python", "-m", "pytest", *(argv[1:] or ["-q"]))


if __name__ == "__main__":
    main(sys.argv[1:])
