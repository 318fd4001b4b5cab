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
    # Siemens-style endpoints evaluate tables, Fanuc PMCs factored maps (smaller than grids)
    kinds = {"vmc-01": "tables", "gantry-02": "factored", "hmc-03": "factored",
             "5ax-04": "tables", "arch-05": "factored"}
    # gantry-02 over Modbus/TCP and 5ax-04 over OPC UA: the center writes into their
    # controllers' memory; the others connect with the EDNC protocol
    served = {"gantry-02", "5ax-04"}
    for name, kind in kinds.items():
        how = "written into controller memory" if name in served else "received"
        assert re.search(rf"{name} \(127\.0\.2\.\d\): {kind} map version \d+ {how}",
                         text), name
    assert re.search(r"│ gantry-02\s+│ fanuc\s+│ modbus ", text)
    assert re.search(r"│ 5ax-04\s+│ siemens\s+│ opcua ", text)
    # the numeric loop says, per machine, the kind, bytes and worst error of its map
    assert len(re.findall(r"map: (tables|grid|factored), [\d,]+ bytes, worst tool-tip "
                          r"error \d+\.\d+ µm", text)) == 5
    assert "diagnosis: thermal_drift z T_spindle_C" in text
    assert "diagnosis: backlash y" in text
    # ISO 230-6 with the maps the machines received: at least 90 % better each
    received = text.split("ISO 230-6 with the map each machine received")[1]
    gains = [int(g) for g in re.findall(r"│ (\d+) %\s+│", received.split("thermal")[0])]
    assert len(gains) >= 4 and min(gains) >= 90, gains
    # the warm-up: the spindle heats, the map version stays, the compensation follows
    rows = re.findall(r"^\s+(\d+\.\d+) °C\s+drift\s+([-+]\d+\.\d+) µm\s+map v(\d+)\s+"
                      r"z correction\s+([-+]\d+\.\d+) µm\s+left\s+([-+]\d+\.\d+) µm",
                      text, re.M)
    assert len(rows) >= 5, text[-2000:]
    temps = [float(r[0]) for r in rows]
    assert temps[-1] - temps[0] >= 2.0, temps  # warming up, several K
    assert len({r[2] for r in rows}) == 1  # one map: no rebuild for a temperature change
    drift = max(abs(float(r[1])) for r in rows)
    left = max(abs(float(r[4])) for r in rows)
    assert drift >= 5.0 and left <= 0.2 * drift, rows
    assert f"dashboard: http://127.0.0.1:{port}/" in text
    # the run's own API key, and how to register a machine into the running demo
    key = re.search(r"API key of this demo: ([0-9a-f]{32})", text)
    assert key is not None, text[-2000:]
    assert (f"ednc machine register --machine M.json --secret SECRET --api "
            f"http://127.0.0.1:{port} --api-key {key.group(1)}") in text
