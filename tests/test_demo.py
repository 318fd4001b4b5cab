"""The README's main job, end to end: ``ednc demo --exit`` on a free port."""

from __future__ import annotations

import re
import socket
import subprocess
import sys
from pathlib import Path

EDNC = str(Path(sys.executable).parent / "ednc")


def test_the_demo_runs_the_whole_loop_and_says_where_the_dashboard_is() -> None:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    out = subprocess.run([EDNC, "demo", "--exit", "--port", str(port)], capture_output=True,
                         text=True, timeout=600, env={"COLUMNS": "200", "PATH": "/usr/bin:/bin"})
    assert out.returncode == 0, out.stderr[-3000:]
    text = out.stdout
    for name in ("vmc-01", "gantry-02", "hmc-03", "5ax-04", "arch-05"):
        assert re.search(rf"{name} \(127\.0\.2\.\d\): map version \d+ received", text), name
    assert "diagnosis: thermal_drift z T_spindle_C" in text
    assert "diagnosis: backlash y" in text
    # ISO 230-6 with the maps the machines received: at least 90 % better each
    received = text.split("ISO 230-6 with the map each machine received")[1]
    gains = [int(g) for g in re.findall(r"│ (\d+) %\s+│", received.split("thermal")[0])]
    assert len(gains) >= 4 and min(gains) >= 90, gains
    assert re.search(r"map v\d+\s+new z correction", text)  # the map follows the heat
    assert f"dashboard: http://127.0.0.1:{port}/" in text
