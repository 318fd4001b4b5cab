"""The FastAPI application of the control center: :func:`create_app`.

The lifespan is the one place where long-lived services start and stop, in an
:class:`~contextlib.AsyncExitStack` (last started, first stopped):

1. the database (tables created if missing, machine secrets sealed with the settings'
   key) and the machines of ``EDNC_MACHINES_FILE``,
2. the :class:`~server.center.Center` stored as ``app.state.center``,
3. the built-in services (:class:`~server.retention.EventRetention`, the dashboard's
   :class:`~server.dashboard.sampler.CorrectionSampler`,
   :class:`~server.dashboard.rollup.TemperatureRollup` and
   :class:`~server.dashboard.mapcheck.MapChecks`), then each factory
   in ``services``, called with the Center; the machine TCP server, the push scheduler and
   the MQTT bridge plug in here as async context managers.
"""

from __future__ import annotations

import logging
import math
import secrets
from collections.abc import AsyncIterator, Callable, Sequence
from contextlib import AbstractAsyncContextManager, AsyncExitStack, asynccontextmanager
from pathlib import Path
from typing import Any

from fastapi import FastAPI, Request
from fastapi.encoders import jsonable_encoder
from fastapi.exceptions import RequestValidationError
from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html
from fastapi.responses import HTMLResponse, JSONResponse
from sqlalchemy.engine import make_url

from server.api.guard import Guard
from server.api.main import api_router, root_router
from server.api.routes.measurements import MAX_UPLOAD_BYTES
from server.bootstrap import read_machines_file, register_machines
from server.center import Center
from server.dashboard.mapcheck import MapChecks
from server.dashboard.rollup import TemperatureRollup
from server.dashboard.sampler import CorrectionSampler
from server.db import Database
from server.db.secretbox import SecretBox, seal_all
from server.retention import EventRetention
from server.settings import Settings, load_settings
from server.version import __version__

log = logging.getLogger(__name__)

ServiceFactory = Callable[[Center], AbstractAsyncContextManager[object]]
"""Builds one long-lived service around the Center; entered in the lifespan, in order."""


def _scrub(error: dict[str, Any]) -> dict[str, Any]:
    """One validation error without what could leak a secret or be unserializable.

    Pydantic echoes the offending ``input``; for a whole-body error that is the whole body,
    secret included. Keep ``input`` only for a scalar outside any secret field.
    """
    out = {k: v for k, v in error.items() if k not in ("input", "ctx", "url")}
    value = error.get("input")
    secret = any("secret" in str(part).lower() for part in error.get("loc", ()))
    scalar = isinstance(value, str | int | bool) or (
        isinstance(value, float) and math.isfinite(value)  # NaN would make the reply invalid
    )
    if scalar and not secret and len(str(value)) <= 200:
        out["input"] = value
    return out


async def _validation_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, RequestValidationError)
    errors = [_scrub(dict(e)) for e in exc.errors()]
    return JSONResponse(status_code=422, content=jsonable_encoder({"detail": errors}))


def secret_box(settings: Settings) -> SecretBox:
    """The box that seals machine secrets: ``EDNC_SECRET_KEY``, else a key file beside an
    SQLite database (a random key for an in-memory one), else none (clear text)."""
    if settings.secret_key is not None:
        return SecretBox.from_text(settings.secret_key.get_secret_value())
    url = make_url(settings.database_url)
    if url.get_backend_name() == "sqlite":
        if url.database in (None, "", ":memory:"):
            return SecretBox(secrets.token_bytes(32))  # the data dies with the process
        return SecretBox.from_key_file(Path(f"{url.database}.key"))
    log.warning("EDNC_SECRET_KEY is not set: machine secrets are stored in clear text in "
                "the database")
    return SecretBox(None)


def create_app(
    settings: Settings | None = None, *, services: Sequence[ServiceFactory] = ()
) -> FastAPI:
    """Build the control center's ASGI app.

    Parameters
    ----------
    settings
        The configuration; None reads and validates the environment
        (raises :class:`~server.settings.SettingsError` with one line per problem).
    services
        Factories of the long-lived services to run with the app (see the module docstring).
    """
    settings = settings if settings is not None else load_settings()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        async with AsyncExitStack() as stack:
            db = await stack.enter_async_context(Database.open(settings.database_url))
            db.secrets = secret_box(settings)
            sealed = await db.run(seal_all, db.secrets)  # a wrong key stops start-up here
            if sealed:
                log.info("sealed %d machine secrets stored in clear text", sealed)
            if settings.machines_file is not None:
                machines = read_machines_file(settings.machines_file)
                counts = await db.run(register_machines, machines, db.secrets)
                log.info("machines file %s: %s", settings.machines_file, counts)
            center = Center(settings=settings, db=db)
            app.state.center = center
            stack.callback(delattr, app.state, "center")
            builtin: tuple[ServiceFactory, ...] = (EventRetention, CorrectionSampler,
                                                   TemperatureRollup, MapChecks)
            for factory in (*builtin, *services):
                await stack.enter_async_context(factory(center))
            if not settings.writes_enabled:
                log.warning("EDNC_API_KEY is not set: the REST API is read-only")
            yield

    app = FastAPI(
        title="EDNC control center",
        version=__version__,
        summary="Machines, error models, measurements, error maps and their delivery.",
        description=(
            "Requests that change data need the service's API key in the `X-API-Key` "
            "header (401 without it, 403 when the service runs read-only), checked before "
            "the body is read; bodies are limited per route (413). Reads of models, maps "
            "and measurements need the read key (or the API key) when the service has one "
            "(`EDNC_READ_KEY`); other reads are open."
        ),
        lifespan=lifespan,
        # /docs and /redoc below load their scripts from the project's static files, not
        # from a CDN: a plant network often has no internet
        docs_url=None,
        redoc_url=None,
        # Bounds every request body, also chunked ones without a Content-Length: the
        # largest legitimate one is a measurement upload plus multipart overhead.
        max_body_size=MAX_UPLOAD_BYTES + 1024 * 1024,
    )
    api_key = settings.api_key.get_secret_value() if settings.api_key else None
    read_key = settings.read_key.get_secret_value() if settings.read_key else None
    app.add_middleware(Guard, keys=lambda: (api_key, read_key))
    app.add_exception_handler(RequestValidationError, _validation_error)
    app.include_router(api_router)
    app.include_router(root_router)
    _add_docs(app)
    return app


VENDOR = "/static/vendor"


def _add_docs(app: FastAPI) -> None:
    """``/docs`` (Swagger UI) and ``/redoc`` from the vendored assets
    (``server/static/vendor/README.md``): nothing is fetched from another host."""
    title = f"{app.title} - API"

    @app.get("/docs", include_in_schema=False)
    async def swagger_ui() -> HTMLResponse:
        return _own_assets_only(get_swagger_ui_html(
            openapi_url=app.openapi_url or "/openapi.json", title=title,
            swagger_js_url=f"{VENDOR}/swagger-ui/swagger-ui-bundle.js",
            swagger_css_url=f"{VENDOR}/swagger-ui/swagger-ui.css",
            swagger_favicon_url="/static/favicon.svg",
            # the default validator badge asks validator.swagger.io about the document
            swagger_ui_parameters={"validatorUrl": None}))

    @app.get("/redoc", include_in_schema=False)
    async def redoc() -> HTMLResponse:
        page = get_redoc_html(openapi_url=app.openapi_url or "/openapi.json", title=title,
                              redoc_js_url=f"{VENDOR}/redoc/redoc.standalone.js",
                              redoc_favicon_url="/static/favicon.svg", with_google_fonts=False)
        # Redoc's "API docs by Redocly" link shows a logo from its CDN: the policy below
        # keeps the browser from asking for it, and this keeps the link out of sight
        html = bytes(page.body).decode().replace(
            "</style>", "  a[href*='redocly.com'] { display: none; }\n    </style>", 1)
        return _own_assets_only(HTMLResponse(html))


DOCS_POLICY = ("default-src 'self'; script-src 'self' 'unsafe-inline' blob:; "
               "worker-src 'self' blob:; style-src 'self' 'unsafe-inline'; "
               "img-src 'self' data:; font-src 'self' data:; connect-src 'self'")
"""What the API doc pages may load: their scripts and styles are the app's (inline ones
are the pages' own set-up), workers from blobs (Redoc's search), nothing from elsewhere."""


def _own_assets_only(page: HTMLResponse) -> HTMLResponse:
    """The page with a Content-Security-Policy that keeps the browser on the app's host."""
    page.headers["Content-Security-Policy"] = DOCS_POLICY
    return page
