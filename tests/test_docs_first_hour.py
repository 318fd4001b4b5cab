"""docs/first-hour.md, run exactly as written: start the center, register a machine,
fit and upload its model, and see a simulated machine apply the map (issue 25: "a
newcomer following only the README and docs/ ... sees its map applied").

The document's ``sh`` blocks are joined into one bash script, run in a scratch directory
with the project's ``ednc`` first on the PATH; only the ports differ (free ones, through
the EDNC_* variables the document names), so the test does not collide with a center
already running on 8080/7878.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import socket
import subprocess
import sys
from pathlib import Path

DOC = Path(__file__).resolve().parents[1] / "docs" / "first-hour.md"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def documented_commands() -> str:
    return "\n".join(re.findall(r"```sh\n(.*?)```", DOC.read_text(), flags=re.S))


def test_the_first_hour_runs_as_documented(tmp_path: Path) -> None:
    script = documented_commands()
    assert "ednc serve" in script and "ednc model upload" in script
    http, machines = free_port(), free_port()
    env = {k: v for k, v in os.environ.items() if not k.startswith("EDNC_")}
    env.update(PATH=f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}",
               EDNC_HTTP_PORT=str(http), EDNC_MACHINE_PORT=str(machines),
               EDNC_MACHINE_HOST="127.0.0.1", EDNC_API=f"http://127.0.0.1:{http}",
               COLUMNS="200")
    pid_file = tmp_path / "first-hour" / "serve.pid"
    try:
        r = subprocess.run(["bash", "-e", "-c", script], cwd=tmp_path, env=env,
                           capture_output=True, text=True, timeout=240)
    finally:
        if pid_file.exists():  # the script's last step kills it; a failed run may not
            with contextlib.suppress(ProcessLookupError):
                os.kill(int(pid_file.read_text()), signal.SIGTERM)
    assert r.returncode == 0, (r.stdout, r.stderr)
    assert "registered vmc-01" in r.stdout
    assert "model v1 of vmc-01 stored" in r.stdout
    assert '"welcomes": 1' in r.stdout and '"maps_acked": 1' in r.stdout
    assert "vmc-01: not connected; map built v1, sent v1, applied v1" in r.stdout
    log = (tmp_path / "first-hour" / "serve.log").read_text()
    opened = next(line for line in log.splitlines() if line.startswith("ednc serve:"))
    assert f"HTTP http://127.0.0.1:{http}" in opened
    assert f"machines TCP 127.0.0.1:{machines}" in opened and "MQTT off" in opened
