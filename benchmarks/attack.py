"""Replay issue 12's attacks against a started center and print what they cost it.

    .venv/bin/python benchmarks/attack.py [--seconds 15] [--quick]

The attacker is written from protocol/README.md alone: no project imports. It starts
``ednc serve`` (SQLite in a temporary directory, an API key, a machines file with one
legitimate machine at 127.0.0.1 and 300 machines at 127.0.2.1-300 whose addresses the
holders use) and, for each attack, runs a legitimate machine logging in again and again
from its own address (a try counts when Welcome comes within 1 s), samples the center's
RSS every 50 ms and counts the ``refused`` rows the ``events`` table gained (a legit
login adds its own connected/disconnected rows, not counted). The legitimate machine runs
in a process of its own, so the attacker's load on its own event loop does not count
against the center. Prints one table: attack, attempts, legit logins during the attack,
peak RSS growth, new refusal rows, outcome.

Loopback addresses stand in for the plant network (127.0.0.0/8 is all loopback on Linux).
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import hashlib
import hmac
import json
import os
import random
import resource
import socket
import sqlite3
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EDNC = Path(sys.executable).parent / "ednc"
API_KEY = "attack-bench-api-key"
SECRET = "legit-machine-secret-0001"
HOLDERS = 300
BYSTANDER = "127.0.5.1"
"""A registered machine's address no other attack uses: its refusals start a fresh window."""

# -- the wire protocol, from protocol/README.md (sections 2, 3, 5, 7)

HELLO, CHALLENGE, AUTH, WELCOME, REJECT, ERROR = 0x01, 0x02, 0x03, 0x04, 0x05, 0x7F
CODES = {1: "PROTOCOL_ERROR", 2: "UNKNOWN_MACHINE", 3: "ADDRESS_MISMATCH", 4: "AUTH_FAILED",
         5: "DUPLICATE_SESSION", 6: "UNSUPPORTED", 7: "TIMEOUT", 8: "SHUTDOWN", 9: "INTERNAL"}


def frame(kind: int, payload: bytes, seq: int) -> bytes:
    head = b"EDNC" + struct.pack(">BBHII", 1, kind, 0, seq, len(payload))
    return head + payload + struct.pack(">I", zlib.crc32(head + payload))


def text(s: str) -> bytes:
    raw = s.encode()
    return bytes([len(raw)]) + raw


def hello(name: str, ip: str) -> bytes:
    payload = (text(name) + text(ip) + bytes([1, 1]) + text("atk-1.0") + text("w X Y b Z t")
               + bytes([0, 0]))
    return frame(HELLO, payload, 0)


async def read_frame(reader: asyncio.StreamReader) -> tuple[int, bytes]:
    head = await reader.readexactly(16)
    if head[:4] != b"EDNC":
        raise ValueError("bad magic")
    kind, length = head[5], struct.unpack(">I", head[12:16])[0]
    body = await reader.readexactly(length + 4)
    return kind, body[:length]


async def login(port: int, name: str, ip: str, secret: str, *,
                local: str | None = None) -> str:
    """One login; returns "welcome" or what ended it."""
    reader, writer = await asyncio.open_connection(
        "127.0.0.1", port, local_addr=(local, 0) if local else None)
    try:
        writer.write(hello(name, ip))
        kind, body = await read_frame(reader)
        if kind != CHALLENGE:
            return CODES.get(struct.unpack(">H", body[:2])[0], "?") if body else f"type {kind}"
        mac = hmac.new(secret.encode(), body[:32] + name.encode(), hashlib.sha256).digest()
        writer.write(frame(AUTH, mac, 1))
        kind, body = await read_frame(reader)
        if kind == WELCOME:
            return "welcome"
        return CODES.get(struct.unpack(">H", body[:2])[0], "?")
    except (asyncio.IncompleteReadError, ConnectionError) as exc:
        return f"closed ({type(exc).__name__})"
    finally:
        writer.close()
        with contextlib.suppress(Exception):
            await writer.wait_closed()


# -- the center under attack

def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def machines_file(path: Path) -> None:
    def entry(name: str, ip: str, secret: str) -> str:
        return (f"  - machine: {{name: {name}, controller: fanuc, ip: {ip}, "
                f"chain: 'w X Y b Z t', travel_mm: {{x: [0, 500], y: [0, 300], "
                f"z: [-300, 0]}}}}\n    secret: {secret}\n")
    lines = ["machines:\n", entry("legit-01", "127.0.0.1", SECRET),
             entry("bystander", BYSTANDER, "bystander-secret-0001")]
    for i in range(HOLDERS):
        lines.append(entry(f"held-{i:03d}", f"127.0.2.{i + 1}" if i < 254 else
                           f"127.0.4.{i - 253}", f"held-secret-{i:04d}-xxxxxx"))
    path.write_text("".join(lines))


def holder_ip(i: int) -> str:
    return f"127.0.2.{i + 1}" if i < 254 else f"127.0.4.{i - 253}"


@dataclass
class Center:
    process: subprocess.Popen[bytes]
    http: int
    machine: int
    db: Path

    def rss_mb(self) -> float:
        for line in Path(f"/proc/{self.process.pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
        return 0.0

    def event_rows(self) -> int:
        with contextlib.closing(sqlite3.connect(f"file:{self.db}?mode=ro", uri=True)) as c:
            return int(c.execute("SELECT count(*) FROM events WHERE kind = 'refused'"
                                 ).fetchone()[0])

    def metric(self, name: str) -> float:
        import urllib.request
        with urllib.request.urlopen(f"http://127.0.0.1:{self.http}/metrics") as r:
            total = 0.0
            for line in r.read().decode().splitlines():
                if line.startswith(name):
                    total += float(line.rsplit(" ", 1)[1])
            return total


def start_center(tmp: Path) -> Center:
    machines_file(tmp / "plant.yaml")
    http, machine = free_port(), free_port()
    env = {**os.environ, "EDNC_DATABASE_URL": f"sqlite:///{tmp / 'c.db'}",
           "EDNC_API_KEY": API_KEY, "EDNC_HTTP_PORT": str(http),
           "EDNC_MACHINE_HOST": "127.0.0.1", "EDNC_MACHINE_PORT": str(machine),
           "EDNC_MACHINES_FILE": str(tmp / "plant.yaml"), "EDNC_HEARTBEAT_S": "5"}
    env.pop("EDNC_MQTT_HOST", None)
    with open(tmp / "log", "wb") as log:  # the child keeps its own descriptor
        process = subprocess.Popen([str(EDNC), "serve"], env=env, cwd=tmp,
                                   stdout=subprocess.DEVNULL, stderr=log)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", machine), 0.2):
            return Center(process, http, machine, tmp / "c.db")
        if process.poll() is not None:
            raise SystemExit(f"ednc serve exited: {(tmp / 'log').read_text()[-2000:]}")
        time.sleep(0.2)
    raise SystemExit("ednc serve did not start")


# -- measuring one attack

@dataclass
class Row:
    attack: str
    attempts: int = 0
    legit_ok: int = 0
    legit_tries: int = 0
    legit_worst_s: float = 0.0
    rss_growth_mb: float = 0.0
    rows: int = 0
    outcome: str = ""
    notes: list[str] = field(default_factory=list)
    legit_failures: dict[str, int] = field(default_factory=dict)


async def legit_logins(port: int, seconds: float) -> dict[str, object]:
    """The legitimate machine: log in, close, again, for ``seconds`` (its own process)."""
    ok = tries = 0
    worst = 0.0
    failures: dict[str, int] = {}
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        t0 = time.monotonic()
        try:
            async with asyncio.timeout(1.0):
                result = await login(port, "legit-01", "127.0.0.1", SECRET)
        except TimeoutError:
            result = "no Welcome within 1 s"
        worst = max(worst, time.monotonic() - t0)
        tries += 1
        if result == "welcome":
            ok += 1
        else:
            failures[result] = failures.get(result, 0) + 1
        await asyncio.sleep(0.5)  # as a PLC would back off; the session's end reaches the center
    return {"ok": ok, "tries": tries, "worst_s": worst, "failures": failures}


async def legit_loop(center: Center, seconds: float, row: Row) -> None:
    process = await asyncio.create_subprocess_exec(
        sys.executable, __file__, "--legit", str(center.machine), str(seconds),
        stdout=asyncio.subprocess.PIPE)
    out, _ = await process.communicate()
    result = json.loads(out)
    row.legit_ok, row.legit_tries = int(result["ok"]), int(result["tries"])
    row.legit_worst_s = float(result["worst_s"])
    row.legit_failures = dict(result["failures"])


async def measure(center: Center, name: str, attack: Callable[[asyncio.Event, Row],
                  Awaitable[None]], seconds: float) -> Row:
    row = Row(name)
    rows_before = center.event_rows()
    rss0 = peak = center.rss_mb()
    stop = asyncio.Event()

    async def sample() -> None:
        nonlocal peak
        while not stop.is_set():
            peak = max(peak, center.rss_mb())
            await asyncio.sleep(0.05)

    tasks = [asyncio.ensure_future(attack(stop, row)), asyncio.create_task(sample())]
    await asyncio.sleep(0.5)  # the attack is under way before the machine tries
    await legit_loop(center, seconds, row)
    stop.set()
    await asyncio.gather(*tasks, return_exceptions=True)
    await asyncio.sleep(1.0)  # refusals still being stored
    row.rss_growth_mb = peak - rss0
    row.rows = center.event_rows() - rows_before
    return row


# -- the attacks

def reconnecting(center: Center, ips: list[str], per_ip: int, payload: bytes
                 ) -> Callable[[asyncio.Event, Row], Awaitable[None]]:
    """Peers that connect, send ``payload`` and hold; reconnect as soon as dropped."""
    async def peer(ip: str, stop: asyncio.Event, row: Row) -> None:
        while not stop.is_set():
            try:
                reader, writer = await asyncio.open_connection(
                    "127.0.0.1", center.machine, local_addr=(ip, 0))
            except OSError:
                await asyncio.sleep(0.05)
                continue
            row.attempts += 1
            try:
                writer.write(payload)
                with contextlib.suppress(TimeoutError):
                    async with asyncio.timeout(30):
                        while await reader.read(4096):
                            pass
            except ConnectionError:
                pass
            finally:
                writer.close()
            await asyncio.sleep(random.uniform(0.0, 0.02))

    async def run(stop: asyncio.Event, row: Row) -> None:
        await asyncio.gather(*(peer(ip, stop, row) for ip in ips for _ in range(per_ip)))
    return run


def refused_burst(center: Center, count: int, ip: str, name: str
                  ) -> Callable[[asyncio.Event, Row], Awaitable[None]]:
    """``count`` logins that are refused (a name unknown here), 50 at a time."""
    async def run(stop: asyncio.Event, row: Row) -> None:
        sem = asyncio.Semaphore(50)
        codes: dict[str, int] = {}

        async def one() -> None:
            async with sem:
                result = await login(center.machine, name, ip, "x" * 16, local=ip)
                result = "closed" if result.startswith("closed") else result
                codes[result] = codes.get(result, 0) + 1
                row.attempts += 1
        await asyncio.gather(*(one() for _ in range(count)))
        row.notes.append(", ".join(f"{k} x{v}" for k, v in sorted(codes.items())))
        await stop.wait()
    return run


def wrong_secrets(center: Center) -> Callable[[asyncio.Event, Row], Awaitable[None]]:
    """Guessing a registered machine's secret from its own address, as fast as answered."""
    async def run(stop: asyncio.Event, row: Row) -> None:
        ip = holder_ip(0)
        while not stop.is_set():
            await login(center.machine, "held-000", ip, f"guess-{random.random():.12f}",
                        local=ip)
            row.attempts += 1
    return run


def rest_bodies(center: Center, parallel: int, size: int
                ) -> Callable[[asyncio.Event, Row], Awaitable[None]]:
    """Unauthenticated POSTs of ``size`` bytes each, ``parallel`` at a time, repeated."""
    chunk = b"[" + b"1," * 32767 + b"1]"

    async def one(stop: asyncio.Event, row: Row) -> None:
        while not stop.is_set():
            reader, writer = await asyncio.open_connection("127.0.0.1", center.http)
            row.attempts += 1
            head = (f"POST /api/machines HTTP/1.1\r\nhost: x\r\ncontent-type: "
                    f"application/json\r\ncontent-length: {size}\r\n\r\n").encode()
            writer.write(head)
            answer = asyncio.create_task(reader.read(200))
            sent = 0
            try:
                while sent < size and not answer.done() and not stop.is_set():
                    writer.write(chunk[: size - sent])
                    sent += min(len(chunk), size - sent)
                    await writer.drain()
                status = (await answer).split(b" ", 2)[1:2]
                row.notes.append(status[0].decode() if status else "closed")
            except (ConnectionError, IndexError):
                row.notes.append("reset")
            finally:
                answer.cancel()
                writer.close()

    async def run(stop: asyncio.Event, row: Row) -> None:
        await asyncio.gather(*(one(stop, row) for _ in range(parallel)))
    return run


def summary(notes: list[str]) -> str:
    counts: dict[str, int] = {}
    for n in notes:
        counts[n] = counts.get(n, 0) + 1
    return ", ".join(f"{k} x{v}" for k, v in sorted(counts.items(), key=lambda kv: -kv[1]))


async def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=15.0, help="length of each attack")
    ap.add_argument("--quick", action="store_true", help="a smaller, shorter run")
    ap.add_argument("--legit", nargs=2, metavar=("PORT", "SECONDS"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.legit:
        print(json.dumps(await legit_logins(int(args.legit[0]), float(args.legit[1]))))
        return
    seconds = 5.0 if args.quick else args.seconds
    _, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))  # the center inherits it
    rows: list[Row] = []
    with tempfile.TemporaryDirectory() as tmp:
        center = start_center(Path(tmp))
        try:
            await asyncio.sleep(1.0)
            unregistered = [f"127.0.3.{i}" for i in range(1, 251)]  # 250 addresses x 4
            flood = reconnecting(center, unregistered, 4, b"E")
            holders = reconnecting(center, [holder_ip(i) for i in range(HOLDERS)], 1, b"E")

            async def both(stop: asyncio.Event, row: Row) -> None:
                await asyncio.gather(flood(stop, row), holders(stop, row))

            attacks: list[tuple[str, Callable[[asyncio.Event, Row], Awaitable[None]],
                                float]] = [
                ("1,000 unregistered peers reconnecting + 300 holders at registered "
                 "addresses", both, seconds),
                ("5,000 refused logins from an unregistered address",
                 refused_burst(center, 5000, "127.0.3.77", "nobody-01"), seconds),
                ("5,000 refused logins (unknown name) from a registered address",
                 refused_burst(center, 5000, BYSTANDER, "nobody-02"), seconds),
                ("wrong-secret guessing from the machine's own address",
                 wrong_secrets(center), seconds),
                ("16 parallel 60 MB REST bodies without a key",
                 rest_bodies(center, 16, 60_000_000), seconds),
            ]
            for name, attack, length in attacks:
                if args.quick and "5,000" in name:
                    attack = refused_burst(center, 1000, *(
                        ("127.0.3.77", "nobody-01") if "unregistered" in name
                        else (BYSTANDER, "nobody-02")))
                    name = name.replace("5,000", "1,000")
                print(f"... {name}", file=sys.stderr, flush=True)
                evicted0 = center.metric("ednc_handshake_evictions_total")
                row = await measure(center, name, attack, length)
                if "REST" in name:
                    row.outcome = "answers: " + summary(row.notes)
                elif "guessing" in name:
                    checked = center.metric('ednc_connections_refused_total{reason="auth"}')
                    throttled = center.metric("ednc_logins_throttled_total")
                    row.outcome = (f"{row.attempts / length:.0f} tries/s answered; secrets "
                                   f"checked {checked:.0f}, throttled {throttled:.0f}")
                elif "holders" in name:
                    evicted = center.metric("ednc_handshake_evictions_total") - evicted0
                    row.outcome = f"holder slots given to newcomers: {evicted:.0f}"
                else:
                    row.outcome = "; ".join(row.notes)
                if row.legit_failures:
                    row.outcome += "; legit failures: " + ", ".join(
                        f"{k} x{v}" for k, v in row.legit_failures.items())
                rows.append(row)
            unregistered_count = center.metric(
                'ednc_connections_refused_total{reason="unregistered"}')
        finally:
            center.process.terminate()
            center.process.wait(30)
    print()
    print("| attack | attempts | legit logins <= 1 s | worst legit login | peak RSS growth "
          "| new refusal rows | outcome |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for r in rows:
        pct = 100.0 * r.legit_ok / r.legit_tries if r.legit_tries else 0.0
        print(f"| {r.attack} | {r.attempts:,} | {r.legit_ok}/{r.legit_tries} ({pct:.1f} %) | "
              f"{r.legit_worst_s * 1000:.0f} ms | {r.rss_growth_mb:.1f} MB | {r.rows} | "
              f"{r.outcome} |")
    print(f"\nclosed at accept (unregistered address), all attacks: "
          f"{unregistered_count:,.0f}")


if __name__ == "__main__":
    asyncio.run(main())
