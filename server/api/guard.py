"""A pure ASGI guard in front of the REST app: who may send a body, how big, how slowly.

FastAPI reads and parses a request body before any dependency runs, so a key checked by a
dependency (``deps.require_api_key``) is checked only after the whole body sits in memory:
sixteen parallel 60 MB POSTs without a key once took the service to 2.5 GB. This guard
runs first, on the request line and headers alone:

1. a request that writes (any method but GET, HEAD, OPTIONS) without the right
   ``X-API-Key`` is answered 401 (403 when the service is read-only) before one byte of its
   body is read; a read of models, maps or measurements wants the read key when one is set
   (``EDNC_READ_KEY``; the API key also opens them);
2. the body is limited per route (:data:`BODY_LIMITS`): a declared Content-Length above the
   limit is answered 413 at once, a chunked body is counted while it streams and cut at
   the limit with 413;
3. a body that stalls (nothing for ``idle_s``, or not complete within ``total_s``) is
   answered 408.

The dependency stays on the routes (defence in depth, and the OpenAPI document shows it).
Header read timeouts are uvicorn's business (:mod:`server.api.http`).
"""

from __future__ import annotations

import asyncio
import json
import re
import secrets
from collections.abc import Awaitable, Callable, MutableMapping
from typing import Any, Final

from server.api.routes.measurements import MAX_UPLOAD_BYTES
from server.schemas.common import MAX_JSON_BYTES

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]
ASGIApp = Callable[[Scope, Receive, Send], Awaitable[None]]

READ_METHODS: Final = frozenset({"GET", "HEAD", "OPTIONS"})

KiB: Final = 1024
MiB: Final = 1024 * KiB

BODY_LIMITS: Final[tuple[tuple[str, re.Pattern[str], int], ...]] = (
    # (method, path, largest body in bytes); the first match wins
    ("POST", re.compile(r"^/api/machines/[^/]+/measurements/?$"), MAX_UPLOAD_BYTES + MiB),
    ("POST", re.compile(r"^/api/machines/[^/]+/models/fit/?$"), 64 * KiB),
    ("POST", re.compile(r"^/api/machines/[^/]+/diagnoses/run/?$"), 64 * KiB),
    # stored JSON documents: bounded like every stored JSON object (schemas.common)
    ("POST", re.compile(r"^/api/machines/[^/]+/(models|diagnoses|verifications)/?$"),
     MAX_JSON_BYTES + 64 * KiB),
    # a machine description: a few hundred bytes, a multi-spindle one a few kB
    ("*", re.compile(r"^/api/machines(/[^/]+)?/?$"), 256 * KiB),
)
DEFAULT_BODY_LIMIT: Final = 64 * KiB
"""Any other request: reads carry no body, and no other route takes a large one."""

PROTECTED_READS: Final = re.compile(r"^/api/machines/[^/]+/(models|maps|measurements)(/|$)")
"""What the read key protects: a model, a map or a measurement tells a competitor how a
machine is built and where it errs."""


def body_limit(method: str, path: str) -> int:
    """The largest body a request to ``path`` may carry, bytes."""
    for m, pattern, limit in BODY_LIMITS:
        if (m == "*" or m == method) and pattern.match(path):
            return limit
    return DEFAULT_BODY_LIMIT


def _same(given: bytes, expected: str) -> bool:
    return secrets.compare_digest(given, expected.encode())


class Guard:
    """The ASGI middleware; ``keys()`` gives (api key, read key) at each request, so the
    guard follows the settings of the app it wraps."""

    def __init__(self, app: ASGIApp, keys: Callable[[], tuple[str | None, str | None]], *,
                 idle_s: float = 10.0, total_s: float = 120.0) -> None:
        self.app = app
        self.keys = keys
        self.idle_s = idle_s
        self.total_s = total_s

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        method = str(scope["method"]).upper()
        path = str(scope["path"])
        headers = dict(scope.get("headers") or ())
        refusal = self._refusal(method, path, headers.get(b"x-api-key"))
        if refusal is not None:
            await _answer(send, *refusal)
            return
        limit = body_limit(method, path)
        declared = headers.get(b"content-length", b"")
        if declared.isdigit() and int(declared) > limit:
            await _answer(send, 413, f"request body larger than {limit} bytes")
            return
        await self._guarded(scope, receive, send, limit)

    def _refusal(self, method: str, path: str,
                 key: bytes | None) -> tuple[int, str, dict[str, str]] | None:
        api_key, read_key = self.keys()
        challenge = {"www-authenticate": "APIKey"}
        if method not in READ_METHODS:
            if api_key is None:
                return 403, "writes are disabled: the service has no API key (set EDNC_API_KEY)", {}
            if key is None:
                return (401, "this request changes data: send the API key in the X-API-Key "
                        "header", challenge)
            if not _same(key, api_key):
                return 401, "wrong API key", challenge
            return None
        if read_key is not None and PROTECTED_READS.match(path) and not (
                key is not None and (_same(key, read_key)
                                     or (api_key is not None and _same(key, api_key)))):
            return 401, "reading models, maps and measurements needs the read key in " \
                        "the X-API-Key header", challenge
        return None

    async def _guarded(self, scope: Scope, receive: Receive, send: Send, limit: int) -> None:
        loop = asyncio.get_running_loop()
        deadline = loop.time() + self.total_s
        received = 0
        body_done = False
        started = False
        answered = False  # the guard answered; what the app sends after is dropped

        async def guarded_receive() -> Message:
            nonlocal received, body_done
            if body_done:  # after the body: waits for a disconnect, as long as it likes
                return await receive()
            try:
                async with asyncio.timeout(min(self.idle_s, max(0.0, deadline - loop.time()))):
                    message = await receive()
            except TimeoutError:
                return await stop(408, "the request body came too slowly")
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > limit:
                    return await stop(413, f"request body larger than {limit} bytes")
                body_done = not message.get("more_body", False)
            else:
                body_done = True
            return message

        async def watched_send(message: Message) -> None:
            nonlocal started
            if answered:
                return
            if message["type"] == "http.response.start":
                started = True
            await send(message)

        async def stop(status: int, text: str) -> Message:
            # Answer, then tell the app the client is gone: it stops reading the way it
            # stops for a real disconnect, without a traceback, and what it still sends
            # is dropped.
            nonlocal answered, body_done
            if not started:
                await _answer(send, status, text, {"connection": "close"})
            answered = body_done = True
            return {"type": "http.disconnect"}

        try:
            await self.app(scope, guarded_receive, watched_send)
        except Exception:
            if not answered:
                raise


async def _answer(send: Send, status: int, text: str,
                  headers: dict[str, str] | None = None) -> None:
    body = json.dumps({"detail": text}).encode()
    raw = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
    raw += [(k.encode(), v.encode()) for k, v in (headers or {}).items()]
    await send({"type": "http.response.start", "status": status, "headers": raw})
    await send({"type": "http.response.body", "body": body})
