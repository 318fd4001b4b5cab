"""How the center reaches a machine: the ``link`` of its registration.

* ``ednc`` (the default): the machine runs the EDNC protocol's client itself
  (protocol/README.md §1-12) and connects to the center;
* ``modbus``: a Fanuc PMC behind the controller's Modbus/TCP Server function; the center
  is the Modbus client and writes the map into the holding-register window the ladder
  reads (protocol/README.md §13);
* ``opcua``: a SINUMERIK behind its OPC UA server; the center logs in as a user with
  write rights on the PLC data block that holds the window.
* ``sinumerik_sd``: a SINUMERIK with nothing of ours in its PLC: the geometry is loaded as
  CEC tables (``ednc export --format cec``) and the center writes the NC's temperature
  compensation SD43900/43910/43920 over OPC UA (a user with SeaWrite;
  :mod:`server.links.sinumerik_sd`).

The link is kept in the machine's description under ``link`` (formats.md §1 allows
extra keys), so a fleet file and the REST API carry it the same way.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

__all__ = ["EdncLink", "LinkSpec", "ModbusLink", "OpcuaLink", "OpcuaLogin", "SinumerikSdLink"]

Host = Annotated[str, Field(min_length=1, max_length=253, pattern=r"^[A-Za-z0-9.\-:\[\]]+$")]


class EdncLink(BaseModel):
    """The machine connects to the center with the EDNC protocol."""

    model_config = ConfigDict(extra="forbid")
    kind: Literal["ednc"] = "ednc"


class ModbusLink(BaseModel):
    """A Fanuc PMC reached through the Modbus/TCP Server function (option R968).

    The window (protocol/README.md §13) starts at holding register ``start_register``; the
    controller's Modbus area setting maps it onto PMC memory from ``pmc`` (for the
    operator's reference: the ladder reads the same bytes there).
    """

    model_config = ConfigDict(extra="forbid")
    kind: Literal["modbus"]
    host: Host | None = Field(default=None, description="default: the machine's ip")
    port: int = Field(default=502, ge=1, le=65535)
    unit_id: int = Field(default=1, ge=0, le=255,
                         description="Modbus unit id the controller answers to; controllers "
                         "behind one gateway (one host and port) differ by it")
    block_registers: int = Field(default=123, ge=1, le=123,
                                 description="largest write, registers (123: the Modbus "
                                 "limit; fewer for a gateway or PMC that takes less)")
    start_register: int = Field(default=0, ge=0, le=65535,
                          description="first holding register of the window")
    pmc: str = Field(default="D0000", pattern=r"^[RDE][0-9]{4,5}$",
                     description="PMC address the window's first register is mapped onto")
    byte_order: Literal["little", "big"] = Field(
        default="little", description="how the controller puts a register's two bytes into "
        "PMC memory: little = low byte at the even address (a PMC word)")
    poll_ms: int = Field(default=100, ge=10, le=10_000,
                         description="how often the center reads the PLC's status, ms")
    pipeline: bool = Field(
        default=True, description="send a push's payload blocks without waiting for each "
        "answer (Modbus/TCP matches answers by transaction id); false: one request at a "
        "time, for a server or gateway that answers only the first of several (the center "
        "also falls back by itself when it sees that)")


class OpcuaLogin(BaseModel):
    """Where and how the center logs in to a SINUMERIK's OPC UA server: what every OPC UA
    link has (the window link and the native one log in alike:
    server/links/opcualogin.py)."""

    model_config = ConfigDict(extra="forbid")
    endpoint: Annotated[str, Field(pattern=r"^opc\.tcp://[^\s]+$", max_length=300)]
    security_policy: Literal["None", "Basic256Sha256"] = Field(
        default="Basic256Sha256", description="None (either field) only if asked: the "
        "password then crosses the network in clear, with a warning event")
    security_mode: Literal["None", "Sign", "SignAndEncrypt"] = "SignAndEncrypt"
    trust: Literal["first_use", "list"] = Field(
        default="first_use", description="the controller's certificate: kept on first use, "
        "or only those in the center's trust list (server/links/opcuapki.py)")
    password_ref: Annotated[str, Field(
        pattern=r"^(env:[A-Za-z_][A-Za-z0-9_]*|file:/.+)$",
        description="where the center reads the user's password: env:NAME or file:/path "
                    "(never the password itself: the description is returned by the API)")]
    client_certificate: str | None = Field(
        default=None, min_length=1, max_length=500,
        description="path of another application certificate (PEM or DER) than the "
                    "center's own (made on first start)")
    client_private_key: str | None = Field(
        default=None, min_length=1, max_length=500,
        description="path of that certificate's private key")


class OpcuaLink(OpcuaLogin):
    """A SINUMERIK reached through its OPC UA server (option; login required)."""

    kind: Literal["opcua"]
    plc_class: Literal["s7-300", "s7-1500"] = Field(
        default="s7-300", description="the PLC's class: its PDU sets the write block (240 "
        "bytes for an S7-300 class, the 840D sl's; 960 for an S7-1500, SINUMERIK ONE)")
    user: Annotated[str, Field(min_length=1, max_length=64)]
    window_node: Annotated[str, Field(
        min_length=1, max_length=200,
        description="node id of the PLC data block that holds the window")] = \
        "ns=2;s=/Plc/DB900"
    sd_nodes: dict[str, str] = Field(
        default_factory=dict,
        description="node ids of SD43900/43910/43920 the center reads back, keyed "
                    "'<AXIS>.<number>' (e.g. 'X.43900'); the rest default to the SINUMERIK "
                    "paths of machine axis k, /NC/_N_AX_SEA_ACX/$SA_TEMP_COMP_...[uk]")
    block_bytes: int | None = Field(
        default=None, ge=4, le=16_384, multiple_of=4,
        description="largest window write per request, bytes (default: by plc_class)")
    poll_ms: int = Field(default=200, ge=100, le=10_000,
                         description="status reads, ms (the server samples no faster than "
                                     "100 ms)")


class SinumerikSdLink(OpcuaLogin):
    """A SINUMERIK whose NC temperature compensation the center writes itself (issue 31):
    SD43900/43910/43920 per axis from the model's drift and expansion terms, within the
    NC's limits and at most once per ``min_interval_ms`` per axis."""

    kind: Literal["sinumerik_sd"]
    user: Annotated[str, Field(min_length=1, max_length=64,
                               description="an OPC UA user with SeaWrite and SinuReadAll")]
    sd_nodes: dict[str, str] = Field(
        default_factory=dict,
        description="node ids of SD43900/43910/43920 keyed '<AXIS>.<number>'; the rest "
                    "default to /NC/_N_AX_SEA_ACX/$SA_TEMP_COMP_...[uk], machine axis k")
    max_offset_mm: float = Field(default=0.5, gt=0, le=10.0,
                                 description="largest |SD43900| the NC takes, mm")
    max_slope: float = Field(default=0.01, gt=0, le=1.0,
                             description="largest |SD43910|: the axis's MD32760 "
                                         "COMP_ADD_VELO_FACTOR (K3: it limits tan beta)")
    min_interval_ms: int = Field(default=100, ge=100, le=60_000,
                                 description="least time between two writes of one axis")


LinkSpec = Annotated[EdncLink | ModbusLink | OpcuaLink | SinumerikSdLink,
                     Field(discriminator="kind")]
