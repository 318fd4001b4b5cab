"""Running the ``ednc`` console command as a user would, and reading its one-line errors."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

EDNC = str(Path(sys.executable).parent / "ednc")


def ednc(*args: str, timeout: float = 300) -> subprocess.CompletedProcess[str]:
    """``ednc ARGS`` in a subprocess, without the environment's EDNC_* settings."""
    # A wide terminal so that rich does not wrap the help text mid-sentence.
    env = {**{k: v for k, v in os.environ.items() if not k.startswith("EDNC_")},
           "COLUMNS": "200", "TERM": "dumb"}
    return subprocess.run([EDNC, *args], capture_output=True, text=True, timeout=timeout,
                          env=env)


def one_line_error(r: subprocess.CompletedProcess[str]) -> str:
    """The user error of a failed command: exit 2, one line, no traceback."""
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert "Traceback" not in r.stderr, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    return lines[0]
