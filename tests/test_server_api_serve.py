"""``ednc serve``: the service as a process, over real HTTP."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

EDNC = Path(sys.executable).parent / "ednc"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def environment(**values: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("EDNC_")}
    return {**env, **values}


@pytest.fixture
def served(tmp_path: Path) -> Iterator[str]:
    port = free_port()
    # Port 0 for the machine TCP server too: a fixed port could collide with other tests.
    env = environment(EDNC_DATABASE_URL=f"sqlite:///{tmp_path / 'ednc.db'}",
                      EDNC_API_KEY="serve-key-123", EDNC_MACHINE_PORT="0")
    proc = subprocess.Popen([str(EDNC), "serve", "--port", str(port)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 30.0  # waiting for start-up, not measuring it
        while True:
            try:
                httpx.get(f"{base}/api/status", timeout=1.0)
                break
            except httpx.TransportError:
                if proc.poll() is not None or time.monotonic() > deadline:
                    output = proc.stdout.read().decode() if proc.stdout else ""
                    pytest.fail(f"ednc serve did not come up:\n{output}")
                time.sleep(0.1)
        yield base
    finally:
        proc.terminate()
        proc.wait(timeout=30)
        if proc.stdout:
            proc.stdout.close()


def test_serve_answers_over_http(served: str) -> None:
    status = httpx.get(f"{served}/api/status").json()
    assert status["writes_enabled"] is True and status["machines"] == 0
    r = httpx.post(f"{served}/api/machines", headers={"X-API-Key": "serve-key-123"}, json={
        "name": "vmc-01", "controller": "fanuc", "ip": "10.0.0.21", "chain": "w X Y b Z t",
        "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]},
        "secret": "s3cret-s3cret-s3cret"})
    assert r.status_code == 201, r.text
    assert "ednc_machines_connected" in httpx.get(f"{served}/metrics").text


def test_bad_settings_are_one_line_and_exit_2() -> None:
    out = subprocess.run([str(EDNC), "serve"], capture_output=True, text=True, timeout=60,
                         env=environment(EDNC_HTTP_PORT="99999", EDNC_API_KEY="x"))
    assert out.returncode == 2
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    assert "EDNC_HTTP_PORT" in lines[0] and "EDNC_API_KEY" in lines[0]


def test_unreachable_database_is_one_line_and_exit_2(tmp_path: Path) -> None:
    url = f"sqlite:///{tmp_path / 'missing-dir' / 'ednc.db'}"
    out = subprocess.run([str(EDNC), "serve"], capture_output=True, text=True, timeout=60,
                         env=environment(EDNC_DATABASE_URL=url))
    assert out.returncode == 2
    assert out.stderr.strip().splitlines() == [
        f"ednc: error: cannot open database {url}: unable to open database file"]
