"""Run an IEC 61131-3 Structured Text program compiled by a real compiler.

MATIEC's ``iec2c`` (third_party/matiec, built by ``python3 tasks.py matiec``) turns the
Structured Text into C; gcc compiles that C with MATIEC's C library headers and a small
shim into a shared library; :class:`StProgram` loads it with ctypes and runs it scan by
scan, reading and writing the program's variables in place (the window bytes, the
positions, the corrections). Builds are cached by the hash of everything that goes into
them, under ``build/iec/``.

One :class:`StProgram` is one PLC: each loads its own copy of the library, so several
machines in one process share no variable.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = ["ROOT", "StBuildError", "StProgram", "StVar", "build_program", "iec2c"]

ROOT = Path(__file__).resolve().parent.parent
BUILD = ROOT / "build" / "iec"
IEC2C = ROOT / "build" / "matiec" / "src" / "iec2c"
LIB = ROOT / "third_party" / "matiec" / "lib"


class StBuildError(RuntimeError):
    """iec2c or gcc refused the program (the message carries their output)."""


@dataclass(frozen=True)
class StVar:
    """A variable of the PROGRAM the harness reads and writes: its IEC name, the ctypes
    type of one element and how many elements (1 for a scalar, the length of an array)."""

    name: str
    ctype: type[ctypes._SimpleCData]  # type: ignore[type-arg]
    length: int = 1


def iec2c() -> Path:
    """The compiler, built first when missing or stale (``python3 tasks.py matiec``)."""
    subprocess.run([sys.executable, str(ROOT / "tasks.py"), "matiec"], check=True,
                   cwd=ROOT, stdout=subprocess.DEVNULL)
    return IEC2C


_SHIM = """
#include "iec_std_lib.h"
TIME __CURRENT_TIME;
BOOL __DEBUG;
#include "accessor.h"
#include "POUS.h"
extern %(prog)s RES__INST;
void config_init__(void);
void config_run__(unsigned long tick);
static unsigned long tick__;
void plc_init(void) { tick__ = 0; config_init__(); }
void plc_scan(void) { config_run__(tick__++); }
%(accessors)s
"""


def _config(program: str) -> str:
    return ("\nCONFIGURATION CFG\n  RESOURCE RES ON PLC\n"
            "    TASK T(INTERVAL := T#8ms, PRIORITY := 0);\n"
            f"    PROGRAM INST WITH T : {program};\n  END_RESOURCE\nEND_CONFIGURATION\n")


def build_program(sources: Sequence[Path], program: str, variables: Sequence[StVar]) -> Path:
    """Compile the Structured Text files ``sources`` (in order) with the PROGRAM
    ``program`` as the one task of a configuration, into a shared library exporting
    ``plc_init``, ``plc_scan`` and ``plc_var_<NAME>`` (the address of each variable).

    Raises
    ------
    StBuildError
        iec2c or gcc failed.
    """
    text = "".join(Path(s).read_text() + "\n" for s in sources) + _config(program)
    accessors = "\n".join(f"void *plc_var_{v.name.upper()}(void) {{ return "
                          f"(void *)&RES__INST.{v.name.upper()}.value; }}"
                          for v in variables)
    shim = _SHIM % {"prog": program.upper(), "accessors": accessors}
    compiler = iec2c()
    key = hashlib.sha256("\0".join([text, shim, str(compiler.stat().st_size),
                                    str(compiler.stat().st_mtime_ns)]).encode()).hexdigest()
    out = BUILD / key[:24]
    so = out / "libplc.so"
    if so.exists():
        return so
    BUILD.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="tmp-"))
    try:
        (work / "program.st").write_text(text)
        (work / "shim.c").write_text(shim)
        r = subprocess.run([str(compiler), "-I", str(LIB), "-T", str(work), "program.st"],
                           cwd=work, capture_output=True, text=True)
        if r.returncode != 0:
            raise StBuildError(f"iec2c: {r.stdout}{r.stderr}")
        # the resource and configuration files (the resource includes POUS.c);
        # -ffp-contract=off: no fused multiply-add may change the exact two-product
        # (plc/ednc_f64.st), as no IEC 61131-3 target fuses them either
        generated = sorted(f.name for f in work.glob("*.c")
                           if f.name not in ("POUS.c", "shim.c"))
        r = subprocess.run(["gcc", "-shared", "-fPIC", "-O2", "-ffp-contract=off", "-w",
                            "-I", str(LIB / "C"),
                            "-I", str(work), "-o", "libplc.so", *generated, "shim.c", "-lm"],
                           cwd=work, capture_output=True, text=True)
        if r.returncode != 0:
            raise StBuildError(f"gcc: {r.stdout}{r.stderr}")
        try:
            work.rename(out)
        except OSError:  # another process built it meanwhile
            shutil.rmtree(work, ignore_errors=True)
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    return so


class StProgram:
    """One PLC running a compiled program: :meth:`init` (a cold start: every variable
    to its initial value), :meth:`scan` (one cycle of the task), and the variables as
    ctypes arrays over the program's own memory (:meth:`var`)."""

    def __init__(self, library: Path, variables: Sequence[StVar]) -> None:
        fd, name = tempfile.mkstemp(suffix=".so", dir=library.parent)
        os.close(fd)
        shutil.copyfile(library, name)  # its own copy: its own variables
        try:
            self._lib = ctypes.CDLL(name)
        finally:
            os.unlink(name)
        self._lib.plc_init.restype = None
        self._lib.plc_scan.restype = None
        self._vars: dict[str, Any] = {}
        for v in variables:
            f = getattr(self._lib, f"plc_var_{v.name.upper()}")
            f.restype = ctypes.c_void_p
            self._vars[v.name] = (v.ctype * v.length).from_address(f())
        self.scans = 0

    def init(self) -> None:
        """Cold start: every variable takes its initial value."""
        self._lib.plc_init()

    def scan(self) -> None:
        """One cycle of the program."""
        self._lib.plc_scan()
        self.scans += 1

    def var(self, name: str) -> Any:
        """The variable ``name`` as a ctypes array over the program's memory (items are
        Python ints)."""
        return self._vars[name]
