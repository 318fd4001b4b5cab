"""The service's settings: environment variables prefixed ``EDNC_``, or an env file.

Every field is validated when the service starts (:func:`load_settings`), so a typo in a
port or a database URL stops start-up with one line per problem instead of failing later
inside a request or a push.

==============================  =========================  ===============================
variable                        default                    meaning
==============================  =========================  ===============================
``EDNC_DATABASE_URL``           ``sqlite:///./ednc.db``    SQLite file or PostgreSQL URL
``EDNC_API_KEY``                unset (read-only API)      key for writes, ``X-API-Key``
``EDNC_READ_KEY``               unset (open reads)         key for reading models, maps and
                                                           measurements (required when the
                                                           HTTP host is not loopback)
``EDNC_SECRET_KEY``             a key file beside SQLite   encrypts machine secrets at rest
                                                           (unset on PostgreSQL: stored in
                                                           clear, with a warning)
``EDNC_HTTP_HOST/PORT``         ``127.0.0.1`` / 8080       REST API and dashboard
``EDNC_MACHINE_HOST/PORT``      ``0.0.0.0`` / 7878         machine TCP server
``EDNC_MQTT_HOST/PORT``         unset (MQTT off) / 1883    MQTT broker
``EDNC_MQTT_TOPIC_PREFIX``      ``ednc``                   first topic level
``EDNC_PUSH_PERIOD_S``          60                         error-map push period, s
``EDNC_HEARTBEAT_S``            5 (protocol/limits.py)     machine heartbeat period, s
``EDNC_NODE_ID``                ``<host>-<pid>``           this process, for leases
``EDNC_LEASE_TTL_S``            15                         machine lease life, s (renewed
                                                           every third of it)
``EDNC_MACHINES_FILE``          unset                      machines registered at start-up
``EDNC_LEASES``                 ``auto``                   leases: on PostgreSQL only
``EDNC_EVENT_RETENTION_DAYS``   30                         events older are deleted
``EDNC_TEMPERATURE_MAX_RATE``   1 K/s                      a temperature moving faster
                                                           (beyond the allowance) is refused
``EDNC_TEMPERATURE_JUMP``       10 K                       allowed on top of the rate
``EDNC_TEMPERATURE_STALE_S``    60                         a machine without a new
                                                           temperature this long is shown
                                                           stale (it holds the last good
                                                           value)
==============================  =========================  ===============================
"""

from __future__ import annotations

import ipaddress
import os
import re
import socket
from pathlib import Path
from typing import Annotated, Any, Final, Literal

from pydantic import Field, SecretStr, ValidationError, field_validator, model_validator
from pydantic_settings import BaseSettings, SettingsConfigDict
from sqlalchemy.engine import make_url
from sqlalchemy.exc import ArgumentError

from protocol.limits import HEARTBEAT_PERIOD_MS

ENV_PREFIX = "EDNC_"

TEMPERATURE_MAX_RATE: Final = 1.0
"""K/s. A machine's structure warms by hundredths of a kelvin per second, a spindle
bearing by a tenth at most; 1 K/s is a fault (the intake's default, server/intake.py)."""

TEMPERATURE_JUMP: Final = 10.0
"""K allowed on top of the rate: noise, quantisation, a step of coolant or a heater
switched on, a sensor read again after a pause, a test rig's set point; a unit mix-up (°F
for °C: tens of K) or a broken sensor (open circuit, -273 or +850 °C) jumps further."""

TEMPERATURE_STALE_S: Final = 60.0
"""s. A sensor publishes every few seconds; a minute without a reading is a sensor, a
gateway or a broker gone, not a slow sensor."""

Port = Annotated[int, Field(ge=0, le=65535)]
_HOST = re.compile(r"^[A-Za-z0-9.:\-\[\]]+$")
_NODE_ID = re.compile(r"^[A-Za-z0-9._:\-]{1,64}$")
_TOPIC_LEVEL = re.compile(r"^[^+#/\x00]+$")


class SettingsError(ValueError):
    """Settings that cannot work; the message has one line per problem, naming the variable."""


def _default_node_id() -> str:
    host = re.sub(r"[^A-Za-z0-9.\-]", "-", socket.gethostname())[:40] or "node"
    return f"{host}-{os.getpid()}"


def normalize_database_url(url: str) -> str:
    """Check a database URL and pick the driver this project installs.

    ``postgresql://`` alone would make SQLAlchemy look for psycopg2, which is not a
    dependency; it becomes ``postgresql+psycopg://`` (psycopg 3).

    Raises
    ------
    ValueError
        When the URL does not parse or names a backend other than SQLite or PostgreSQL.
    """
    try:
        parsed = make_url(url)
    except ArgumentError:
        raise ValueError(
            f"{url!r} is not a database URL; expected e.g. 'sqlite:///./ednc.db' "
            "or 'postgresql+psycopg://user@127.0.0.1:5432/ednc'"
        ) from None
    backend, _, driver = parsed.drivername.partition("+")
    if backend == "sqlite" and driver in ("", "pysqlite"):
        return url
    if backend in ("postgresql", "postgres") and driver in ("", "psycopg"):
        return parsed.set(drivername="postgresql+psycopg").render_as_string(hide_password=False)
    raise ValueError(
        f"unsupported database {parsed.drivername!r}: use 'sqlite:///<file>' "
        "or 'postgresql+psycopg://...'"
    )


def is_loopback(host: str) -> bool:
    """Whether ``host`` is reachable from this machine only (``localhost``, 127/8, ::1)."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False  # a host name: it may resolve to anything


class Settings(BaseSettings):
    """The control center's configuration (see the module docstring for the variables)."""

    model_config = SettingsConfigDict(
        env_prefix=ENV_PREFIX,
        env_file=None,
        env_file_encoding="utf-8",
        extra="ignore",
        frozen=True,
    )

    database_url: str = "sqlite:///./ednc.db"
    api_key: SecretStr | None = Field(
        default=None,
        description="Key that write requests carry in the X-API-Key header; unset = read-only.",
    )
    read_key: SecretStr | None = Field(
        default=None,
        description="Key that reads of models, maps and measurements carry in X-API-Key "
                    "(the API key opens them too); unset = open reads, allowed only on a "
                    "loopback HTTP host.",
    )
    secret_key: SecretStr | None = Field(
        default=None,
        description="Encrypts the machines' secrets in the database (AES-256-GCM, key "
                    "derived by HKDF-SHA256); at least 16 characters. Unset on SQLite: a "
                    "random key in '<database file>.key' (mode 0600); unset on PostgreSQL: secrets "
                    "in clear text, with a warning at start-up.",
    )
    http_host: str = "127.0.0.1"
    http_port: Port = 8080
    machine_host: str = "0.0.0.0"
    machine_port: Port = 7878
    mqtt_host: str | None = None
    mqtt_port: Port = 1883
    mqtt_topic_prefix: str = "ednc"
    push_period_s: float = Field(default=60.0, gt=0.0, le=86400.0)
    controller_reconcile_s: float = Field(
        default=2.0, gt=0.0, le=3600.0,
        description="How often the center reads the registrations again for machines "
                    "with a modbus or opcua link (server/links/window/service.py), s.")
    heartbeat_s: float = Field(default=HEARTBEAT_PERIOD_MS / 1000, gt=0.0, le=3600.0)
    node_id: str = Field(default_factory=_default_node_id)
    lease_ttl_s: float = Field(
        default=15.0, ge=0.3, le=3600.0,
        description="How long a machine's lease outlives its node's last renewal; the "
                    "node renews every third of it (server/leasing.py).")
    event_retention_days: float = Field(default=30.0, gt=0.0, le=36500.0)
    temperature_max_rate: float = Field(
        default=TEMPERATURE_MAX_RATE, gt=0.0, le=1000.0,
        description="K/s: a temperature further from its sensor's last good reading than "
                    "this rate times the time between them, plus the jump allowance, is "
                    "refused (a sensor fault or a unit mix-up); server/intake.py.")
    temperature_jump: float = Field(
        default=TEMPERATURE_JUMP, ge=0.0, le=1000.0,
        description="K allowed on top of the rate (noise, a heater switched on).")
    temperature_stale_s: float = Field(
        default=TEMPERATURE_STALE_S, gt=0.0, le=86400.0,
        description="s: a temperature not renewed for this long is stale: the machine "
                    "holds its last good value, the dashboard and the MQTT status say so.")
    leases: Literal["auto", "on", "off"] = Field(
        default="auto",
        description="Machine leases for several nodes on one database: 'auto' takes them "
                    "on PostgreSQL only (an SQLite file serves one process, where a lease "
                    "per handshake and its renewals only cost database time).",
    )
    machines_file: Path | None = Field(
        default=None,
        description="JSON/YAML file of machines (descriptions and secrets) registered at "
                    "start-up; see server/bootstrap.py.",
    )

    @property
    def uses_leases(self) -> bool:
        """Whether this node takes machine leases (``leases`` setting)."""
        if self.leases == "auto":
            return self.database_url.startswith("postgresql")
        return self.leases == "on"

    @field_validator("machines_file")
    @classmethod
    def _machines_file(cls, value: Path | None) -> Path | None:
        if value is not None and not value.is_file():
            raise ValueError(f"{str(value)!r} is not a file")
        return value

    @field_validator("database_url")
    @classmethod
    def _database_url(cls, value: str) -> str:
        return normalize_database_url(value.strip())

    @field_validator("api_key")
    @classmethod
    def _api_key(cls, value: SecretStr | None) -> SecretStr | None:
        if value is None or value.get_secret_value() == "":
            return None  # an empty variable means "unset", i.e. read-only
        if len(value.get_secret_value()) < 8:
            raise ValueError("must be at least 8 characters (or unset for a read-only API)")
        return value

    @field_validator("read_key")
    @classmethod
    def _read_key(cls, value: SecretStr | None) -> SecretStr | None:
        if value is None or value.get_secret_value() == "":
            return None
        if len(value.get_secret_value()) < 8:
            raise ValueError("must be at least 8 characters (or unset for open reads)")
        return value

    @field_validator("secret_key")
    @classmethod
    def _secret_key(cls, value: SecretStr | None) -> SecretStr | None:
        if value is None or value.get_secret_value() == "":
            return None
        if len(value.get_secret_value().encode()) < 16:
            raise ValueError("must be at least 16 bytes (e.g. `openssl rand -base64 32`)")
        return value

    @model_validator(mode="after")
    def _keys_where_needed(self) -> Settings:
        # The API and the database may each be reachable from the plant network; what they
        # guard must not then be open (reads) or in clear text (secrets).
        if self.read_key is None and not is_loopback(self.http_host):
            raise ValueError(f"EDNC_READ_KEY is required when EDNC_HTTP_HOST "
                             f"({self.http_host}) is not a loopback address")
        return self

    @field_validator("http_host", "machine_host")
    @classmethod
    def _host(cls, value: str) -> str:
        if not _HOST.match(value):
            raise ValueError(f"{value!r} is not a host name or address")
        return value

    @field_validator("mqtt_host")
    @classmethod
    def _mqtt_host(cls, value: str | None) -> str | None:
        if value is None or value.strip() == "":
            return None  # empty = MQTT off
        if not _HOST.match(value):
            raise ValueError(f"{value!r} is not a host name or address")
        return value

    @field_validator("mqtt_topic_prefix")
    @classmethod
    def _topic_prefix(cls, value: str) -> str:
        levels = value.split("/")
        if not all(_TOPIC_LEVEL.match(level) for level in levels):
            raise ValueError(
                f"{value!r}: topic levels must be non-empty and free of '+', '#' and NUL"
            )
        return value

    @field_validator("node_id")
    @classmethod
    def _node_id(cls, value: str) -> str:
        if not _NODE_ID.match(value):
            raise ValueError(f"{value!r}: use 1-64 letters, digits, '.', '_', ':' or '-'")
        return value

    @property
    def mqtt_enabled(self) -> bool:
        return self.mqtt_host is not None

    @property
    def writes_enabled(self) -> bool:
        return self.api_key is not None


def load_settings(env_file: str | Path | None = None, **overrides: Any) -> Settings:
    """Read and validate the settings, turning pydantic's report into :class:`SettingsError`.

    Parameters
    ----------
    env_file
        Optional ``KEY=value`` file read before the environment (the environment wins).
    **overrides
        Field values that win over both (used by tests and the ``serve`` command).
    """
    if env_file is not None and not Path(env_file).is_file():
        # pydantic-settings skips a missing env file silently; a named one must exist.
        raise SettingsError(f"env file {str(env_file)!r} does not exist")
    try:
        return Settings(_env_file=env_file, **overrides)
    except ValidationError as exc:
        lines = []
        for err in exc.errors(include_url=False, include_input=False):
            field = ".".join(str(p) for p in err["loc"])
            if field:
                lines.append(f"{ENV_PREFIX}{field.upper()}: {err['msg']}")
            else:  # a rule over several variables names them itself
                lines.append(err["msg"].removeprefix("Value error, "))
        raise SettingsError("invalid settings:\n  " + "\n  ".join(lines)) from None
