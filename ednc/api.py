"""Talking to a running center's REST API from the command line (``ednc machine ...``,
``ednc model upload``), so that registering a machine and uploading its model need no
browser on ``/docs``. Every problem (center unreachable, key refused, a description or
model the center refuses) is one :class:`~ednc.cli.UserError` line."""

from __future__ import annotations

from typing import Annotated, Any

import httpx
import typer

from ednc.cli import UserError

DEFAULT_API = "http://127.0.0.1:8080"


class Unreachable(UserError):
    """Nothing answered at the API's address (yet)."""

ApiOption = Annotated[str, typer.Option(
    "--api", envvar="EDNC_API", help="The center's REST API base URL (ednc serve's HTTP "
                                     "address).")]
KeyOption = Annotated[str | None, typer.Option(
    "--api-key", envvar="EDNC_API_KEY", help="The center's API key (its EDNC_API_KEY), "
                                             "which writes need.")]


def call(method: str, api: str, path: str, key: str | None, *,
         body: Any = None) -> httpx.Response:
    """One request to ``api`` + ``/api`` + ``path``; a transport failure or a refused key
    is a UserError, any other status is the caller's to read."""
    url = api.rstrip("/") + "/api" + path
    headers = {"X-API-Key": key} if key else {}
    try:
        r = httpx.request(method, url, json=body, headers=headers, timeout=30.0)
    except httpx.InvalidURL as exc:
        raise UserError(f"--api {api!r}: not a URL ({exc})") from None
    except httpx.ConnectError:
        raise Unreachable(f"nothing is listening at {api}: is 'ednc serve' running there "
                          "(it says its HTTP address in its first line; give it with "
                          "--api)?") from None
    except httpx.HTTPError as exc:
        raise Unreachable(f"cannot reach the center at {api}: {exc or type(exc).__name__}; "
                        "is 'ednc serve' running there (give its URL with --api)?") from None
    if r.status_code in (401, 403):
        what = ("no API key was given" if not key else
                "it refused the API key")
        raise UserError(f"the center at {api} answered {r.status_code}: {what}; give the "
                        "key of its EDNC_API_KEY with --api-key (or EDNC_API_KEY). If you "
                        "started a center yourself, check that it is the one at that "
                        "address (another center, e.g. a running demo, may hold the port)")
    return r


def detail(r: httpx.Response) -> str:
    """The center's reason for a refusal, one line."""
    try:
        body = r.json()
    except ValueError:
        return r.text.strip().replace("\n", " ")[:300]
    d = body.get("detail", body) if isinstance(body, dict) else body
    if isinstance(d, list):
        return "; ".join(_item(x) for x in d)
    return str(d).replace("\n", " ")[:300]


def _item(x: Any) -> str:
    """One validation error as ``field: message`` (the field the request's body names)."""
    if not isinstance(x, dict):
        return str(x)
    loc = [str(p) for p in x.get("loc", []) if p != "body"]
    msg = str(x.get("msg", x)).removeprefix("Value error, ")
    return f"{'.'.join(loc)}: {msg}" if loc else msg
