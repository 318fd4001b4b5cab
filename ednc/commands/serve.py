"""``ednc serve``: run the control center in one process: REST API and dashboard (uvicorn),
the machine TCP server, the push scheduler and the MQTT bridge (:mod:`server.services`)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer


def ports_line(settings: Any) -> str:
    """Every address the center opens, in one line at start (uvicorn logs only its own):
    HTTP (REST API and dashboard), the machines' TCP port, and MQTT (or that it is off)."""
    from sqlalchemy.engine import make_url

    def where(host: str, port: int) -> str:
        return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"

    mqtt = (f"MQTT broker {where(settings.mqtt_host, settings.mqtt_port)} (topics "
            f"{settings.mqtt_topic_prefix}/...)" if settings.mqtt_host is not None else
            "MQTT off (set EDNC_MQTT_HOST)")
    return (f"ednc serve: HTTP http://{where(settings.http_host, settings.http_port)} (REST "
            f"API /api, dashboard /); machines TCP "
            f"{where(settings.machine_host, settings.machine_port)}; {mqtt}; database "
            f"{make_url(settings.database_url).render_as_string(hide_password=True)}")


def taken(host: str, port: int) -> str | None:
    """Why ``host:port`` cannot be listened on now (taken, no such address), or None.
    Checked before anything starts: uvicorn would find out only after the lifespan (13 s
    later, the first line having announced the port)."""
    import socket

    if port == 0:
        return None
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
    except OSError as exc:
        return f"{host}: {exc.strerror or exc}"
    family, _, _, _, address = infos[0]
    with socket.socket(family, socket.SOCK_STREAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as uvicorn binds
        try:
            s.bind(address)
        except OSError as exc:
            return exc.strerror or str(exc)
    return None


def configure_logging(level: str) -> Any:
    """Print the center's own messages of ``level`` and above on stderr, with time and
    source: without a handler Python prints only bare warnings, and a plant engineer
    needs to see a refused link or a failed push without asking for it (uvicorn configures
    its own loggers, which do not propagate here). Returns the handler added."""
    import logging
    import sys

    from ednc.cli import UserError

    number = logging.getLevelName(level.upper())
    if not isinstance(number, int):
        raise UserError(f"--log-level {level!r}: debug, info, warning or error")
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s"))
    root = logging.getLogger()
    root.addHandler(handler)
    root.setLevel(number)
    return handler


def register(app: typer.Typer) -> None:
    @app.command()
    def serve(
        env_file: Annotated[Path | None, typer.Option(
            "--env-file", help="KEY=value file with EDNC_* settings (the environment wins).")]
        = None,
        host: Annotated[str | None, typer.Option(help="HTTP address (EDNC_HTTP_HOST).")] = None,
        port: Annotated[int | None, typer.Option(help="HTTP port (EDNC_HTTP_PORT).")] = None,
        log_level: Annotated[str, typer.Option(
            "--log-level", help="Least severe message of the center printed on stderr: "
            "warning (a link refused, a push failed), info or error.")] = "warning",
    ) -> None:
        """Run the control center service until interrupted (settings: EDNC_* variables)."""
        import uvicorn

        from ednc.cli import UserError
        from server.app import create_app
        from server.db import Database, DatabaseUnavailable, make_engine
        from server.services import machine_services
        from server.settings import SettingsError, load_settings

        overrides: dict[str, Any] = {}
        if host is not None:
            overrides["http_host"] = host
        if port is not None:
            overrides["http_port"] = port
        try:
            settings = load_settings(env_file, **overrides)
        except SettingsError as exc:
            raise UserError(str(exc).replace("\n  ", " ")) from None
        if settings.machines_file is not None:
            from server.bootstrap import MachinesFileError, read_machines_file

            try:
                read_machines_file(settings.machines_file)
            except MachinesFileError as exc:
                raise UserError(str(exc)) from None
        for what, env, h, p in (("HTTP", "EDNC_HTTP_PORT", settings.http_host,
                                 settings.http_port),
                                ("machines TCP", "EDNC_MACHINE_PORT", settings.machine_host,
                                 settings.machine_port)):
            problem = taken(h, p)
            if problem is not None:
                raise UserError(f"cannot serve {what} on {h}:{p}: {problem} (another "
                                "program listens there: a running demo or another 'ednc "
                                f"serve'?); give a free port ({env}"
                                + (" or --port" if what == "HTTP" else "") + ")")
        # Open the database (and create its tables) before serving, so that a wrong URL
        # or a stopped PostgreSQL is one clear line rather than a failed lifespan.
        db = Database(make_engine(settings.database_url))
        try:
            db.create_schema()
        except DatabaseUnavailable as exc:
            raise UserError(str(exc)) from None
        finally:
            db.engine.dispose()
        app = create_app(settings, services=[machine_services])
        configure_logging(log_level)
        typer.echo(ports_line(settings), err=True)
        from server.links.opcuapki import certificate_line, pki_at

        typer.echo(certificate_line(pki_at()), err=True)  # for the controllers' trust lists
        # a dashboard stream ends itself within 10 s; do not let it hold a shutdown longer
        from server.api.http import uvicorn_options  # header deadline (408), header size

        uvicorn.run(app, host=settings.http_host, port=settings.http_port, log_level="info",
                    timeout_graceful_shutdown=5, **uvicorn_options())
