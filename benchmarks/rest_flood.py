"""What unauthenticated 60 MB request bodies cost the REST API, with and without the guard.

    .venv/bin/python benchmarks/rest_flood.py [--parallel 16] [--mb 60] [--rounds 2]

Runs the control center's app under uvicorn (the options ``ednc serve`` uses) in a child
process twice in the same run: as built (``server.api.guard.Guard`` in front: the key is
checked before the body is read) and with the guard taken out (the behaviour before issue
12: FastAPI reads and parses the body, then the route's dependency says 401). Each time,
``--parallel`` clients POST ``--mb`` MB of JSON to ``/api/machines`` without a key,
``--rounds`` times; the child's RSS is sampled every 20 ms. Prints the peak RSS growth,
the answers and how long a round took, for both, and their ratio.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import os
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def serve(port: int, db: str, mode: str) -> None:
    """The child: the app under uvicorn, guarded or bare."""
    sys.path.insert(0, str(ROOT))
    import uvicorn

    from server.api.guard import Guard
    from server.api.http import uvicorn_options
    from server.app import create_app
    from server.settings import load_settings

    app = create_app(load_settings(database_url=f"sqlite:///{db}", api_key="bench-key-0123"))
    if mode == "bare":
        app.user_middleware[:] = [m for m in app.user_middleware
                                  if getattr(m, "cls", None) is not Guard]
    uvicorn.run(app, host="127.0.0.1", port=port, log_level="error", **uvicorn_options())


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


async def post(port: int, size: int) -> str:
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    chunk = b"[" + b"1," * 65535 + b"1]"
    try:
        writer.write(f"POST /api/machines HTTP/1.1\r\nhost: x\r\ncontent-type: "
                     f"application/json\r\ncontent-length: {size}\r\n\r\n".encode())
        answer = asyncio.create_task(reader.read(200))
        sent = 0
        while sent < size and not answer.done():
            piece = chunk[: size - sent]
            writer.write(piece)
            sent += len(piece)
            await writer.drain()
        reply = await answer
        return reply.split(b" ", 2)[1].decode() if reply else "closed"
    except ConnectionError:
        return "reset"
    finally:
        writer.close()


async def flood(mode: str, parallel: int, size: int, rounds: int) -> dict[str, object]:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = int(s.getsockname()[1])
    with tempfile.TemporaryDirectory() as tmp:
        child = subprocess.Popen([sys.executable, __file__, "--serve", str(port),
                                  str(Path(tmp) / "c.db"), mode])
        try:
            for _ in range(300):
                with contextlib.suppress(OSError), socket.create_connection(
                        ("127.0.0.1", port), 0.2):
                    break
                time.sleep(0.1)
            await asyncio.sleep(0.5)
            base = peak = rss_mb(child.pid)
            done = asyncio.Event()

            async def sample() -> None:
                nonlocal peak
                while not done.is_set():
                    peak = max(peak, rss_mb(child.pid))
                    await asyncio.sleep(0.02)

            sampler = asyncio.create_task(sample())
            answers: dict[str, int] = {}
            t0 = time.monotonic()
            for _ in range(rounds):
                for a in await asyncio.gather(*(post(port, size) for _ in range(parallel))):
                    answers[a] = answers.get(a, 0) + 1
            took = (time.monotonic() - t0) / rounds
            done.set()
            await sampler
            return {"mode": mode, "base_mb": base, "growth_mb": peak - base,
                    "answers": answers, "round_s": took}
        finally:
            child.terminate()
            child.wait(30)


async def main(args: argparse.Namespace) -> None:
    size = int(args.mb * 1_000_000)
    results = [await flood(mode, args.parallel, size, args.rounds)
               for mode in ("guarded", "bare")]
    print(f"{args.parallel} parallel {args.mb:g} MB POST /api/machines without a key, "
          f"{args.rounds} rounds (pid {os.getpid()})")
    print("| app | RSS before | peak RSS growth | answers | one round |")
    print("|---|---:|---:|---|---:|")
    for r in results:
        print(f"| {r['mode']} | {r['base_mb']:.0f} MB | {r['growth_mb']:.1f} MB | "
              f"{r['answers']} | {r['round_s']:.2f} s |")
    guarded, bare = (float(str(r["growth_mb"])) for r in results)
    print(f"growth without the guard / with it: {bare / max(guarded, 0.1):.0f}x")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--parallel", type=int, default=16)
    ap.add_argument("--mb", type=float, default=60.0)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--serve", nargs=3, help=argparse.SUPPRESS)
    arguments = ap.parse_args()
    if arguments.serve:  # the child: uvicorn runs its own event loop
        serve(int(arguments.serve[0]), arguments.serve[1], arguments.serve[2])
    else:
        asyncio.run(main(arguments))
