"""A fleet of simulated CNCs: the fleet file, generated fleets, and running them together.

Fleet file (JSON, or YAML when the name ends in ``.yaml``/``.yml``)::

    {
      "center": "127.0.0.1:7070",                 # optional, --center wins
      "mqtt": {"host": "127.0.0.1", "port": 1883, "prefix": "ednc"},   # optional
      "machines": [
        {"machine": "vmc-01.json", "secret": "at-least-16-bytes!", "seed": 1},
        {"machine": {... a machine description, formats.md section 1 ...},
         "secret": "another-16-byte-secret", "ip": "127.0.0.1"}
      ]
    }

``center`` may name several centers of one plant, as ``"HOST:PORT,HOST:PORT"`` or a list
of ``"HOST:PORT"``: each machine tries them in turn (the next after a refusal or a failed
connection, see :class:`~machine_sim.link.SimulatedCNC`).
``machine`` is a path (relative to the fleet file) or an inline description; a
description's ``link`` (``server/schemas/link.py``) says how the center reaches the
machine: without one, or ``{"kind": "ednc"}``, the machine runs the EDNC client and
connects to the center; with ``{"kind": "modbus", "port": 502, ...}`` it serves its PMC
window through a Modbus/TCP server at its own address (the center connects to it), with
``{"kind": "opcua", ...}`` through an OPC UA server. ``ip``
overrides the address announced in Hello; ``seed`` (default: the position in the list)
seeds motion and temperatures. A machine whose address is a loopback one (127.x.y.z)
connects from that address, so that several simulated machines on one host are told
apart by address as real ones are. Generated fleets (:func:`generated_fleet`) are vertical
machining centres ``sim-001``, ``sim-002``, ... alternating Fanuc and Siemens (or all of
one kind), at 127.0.1.1, 127.0.1.2, ..., all with the one given secret; over a modbus
link ``sim-pmc-001``, ... at 127.1.1.1, ..., over opcua ``sim-nc-001``, ... at 127.2.1.1,
..., so that fleets of different links run against one center side by side.
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import Any

import yaml

from protocol.auth import MIN_SECRET_BYTES
from volumetric.errors import MachineSpecError
from volumetric.model.machine import Machine, load_machine, parse_machine
from volumetric.plausible.files import decode_text

from .link import Backoff, MqttTarget, SimulatedCNC
from .windowcnc import ControllerServer, WindowCNC

__all__ = ["Fleet", "FleetEntry", "FleetSpecError", "generated_fleet", "load_fleet",
           "parse_center", "parse_centers"]


class FleetSpecError(ValueError):
    """A fleet file or option that cannot be right; the text says where."""


@dataclass(frozen=True)
class FleetEntry:
    """One simulated machine of a fleet."""

    machine: Machine
    secret: bytes
    seed: int = 0
    ip: str | None = None
    link: Mapping[str, Any] | None = None
    """The description's ``link`` (None: the EDNC protocol)."""

    @property
    def link_kind(self) -> str:
        return str((self.link or {}).get("kind", "ednc"))


def parse_center(text: str) -> tuple[str, int]:
    """``HOST:PORT`` (``[v6]:PORT`` for IPv6) to a (host, port) pair."""
    host, sep, port = text.rpartition(":")
    host = host.strip("[]")
    if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise FleetSpecError(f"center {text!r}: expected HOST:PORT such as 127.0.0.1:7070")
    return host, int(port)


def parse_centers(value: Any) -> list[tuple[str, int]]:
    """``HOST:PORT[,HOST:PORT...]`` or a list of ``HOST:PORT`` to (host, port) pairs."""
    if isinstance(value, str):
        parts = [p.strip() for p in value.split(",")]
    elif isinstance(value, list) and all(isinstance(p, str) for p in value):
        parts = [p.strip() for p in value]
    else:
        raise FleetSpecError(f"center {value!r}: expected 'HOST:PORT', 'HOST:PORT,HOST:PORT' "
                             "or a list of 'HOST:PORT'")
    if not parts or "" in parts:
        raise FleetSpecError(f"center {value!r}: an empty entry; expected HOST:PORT[,HOST:PORT]")
    return [parse_center(p) for p in parts]


def _secret(value: Any, where: str) -> bytes:
    if not isinstance(value, str) or len(value.encode()) < MIN_SECRET_BYTES:
        raise FleetSpecError(f"{where}: secret must be a string of at least "
                             f"{MIN_SECRET_BYTES} bytes")
    return value.encode()


def load_fleet(path: str | Path) -> tuple[list[FleetEntry], dict[str, Any]]:
    """Read a fleet file; returns its machines and its other settings (center, mqtt).

    Raises
    ------
    FleetSpecError
        Unreadable file, bad JSON/YAML, a missing or bad field (named with its index).
    """
    p = Path(path)
    try:
        text = p.read_text()
    except OSError as exc:
        raise FleetSpecError(f"{p}: cannot read ({exc.strerror})") from None
    try:
        data = yaml.safe_load(text) if p.suffix in (".yaml", ".yml") else json.loads(text)
    except (json.JSONDecodeError, yaml.YAMLError) as exc:
        raise FleetSpecError(f"{p}: not valid {'YAML' if p.suffix != '.json' else 'JSON'}: "
                             f"{exc}") from None
    if not isinstance(data, Mapping) or not isinstance(data.get("machines"), list):
        raise FleetSpecError(f"{p}: expected an object with a 'machines' list")
    entries = []
    names: set[str] = set()
    for i, raw in enumerate(data["machines"]):
        where = f"{p}: machines[{i}]"
        if not isinstance(raw, Mapping) or "machine" not in raw:
            raise FleetSpecError(f"{where}: expected an object with 'machine' and 'secret'")
        spec = raw["machine"]
        try:
            if isinstance(spec, str):
                m = load_machine(p.parent / spec)
                # the description the file holds, link included (it says how the center
                # reaches the machine: without it an OPC UA machine would log in the
                # EDNC way, be refused, and nothing would say why)
                spec = _description_file(p.parent / spec)
            elif isinstance(spec, Mapping):
                m = parse_machine(spec)
            else:
                raise FleetSpecError(f"{where}.machine: expected a path or a description")
        except MachineSpecError as exc:
            raise FleetSpecError(f"{where}.machine: {exc}") from None
        if m.name in names:
            raise FleetSpecError(f"{where}: machine name {m.name!r} appears twice")
        names.add(m.name)
        seed = raw.get("seed", i)
        if not isinstance(seed, int):
            raise FleetSpecError(f"{where}.seed: expected an integer, got {seed!r}")
        ip = raw.get("ip")
        if ip is not None and not isinstance(ip, str):
            raise FleetSpecError(f"{where}.ip: expected a string")
        link = spec.get("link") if isinstance(spec, Mapping) else None
        if link is not None and (not isinstance(link, Mapping) or link.get("kind") not in
                                 ("ednc", "modbus", "opcua")):
            raise FleetSpecError(f"{where}.machine.link: expected an object with kind "
                                 "ednc, modbus or opcua")
        entries.append(FleetEntry(m, _secret(raw.get("secret"), where), seed, ip, link))
    if not entries:
        raise FleetSpecError(f"{p}: the fleet has no machines")
    settings = {k: v for k, v in data.items() if k != "machines"}
    return entries, settings


def _description_file(path: Path) -> Mapping[str, Any]:
    """The JSON object of a description file :func:`load_machine` has read."""
    data = json.loads(decode_text(path.read_bytes(), str(path)))
    if not isinstance(data, Mapping):  # pragma: no cover - load_machine refused it
        raise FleetSpecError(f"{path}: expected a JSON object")
    return data


LINK_PREFIX = {"ednc": "sim", "modbus": "sim-pmc", "opcua": "sim-nc"}
"""Names of generated machines by link: ``sim-001``, ``sim-pmc-001``, ``sim-nc-001``, so
that fleets of different links registered at one center do not collide."""
LINK_BLOCK = {"ednc": 0, "modbus": 1, "opcua": 2}
"""The second octet of their loopback addresses (the center knows a machine by its
address too): 127.0.x.y, 127.1.x.y, 127.2.x.y."""


def loopback_address(i: int, block: int = 0) -> str:
    """The ``i``-th distinct loopback address of ``block``, 127.block.1.1, 127.block.1.2,
    ... (64,000 of them): generated machines each connect from (or serve at) their own,
    as real CNCs have their own."""
    if not 0 <= i < 250 * 256:
        raise FleetSpecError(f"no distinct loopback address for machine {i}")
    return f"127.{block}.{1 + i // 250}.{1 + i % 250}"


OPCUA_SECURITY = {"sign-and-encrypt": ("Basic256Sha256", "SignAndEncrypt"),
                  "sign": ("Basic256Sha256", "Sign"), "none": ("None", "None")}
"""``ednc sim --opcua-security``: the (security_policy, security_mode) of the links."""


def generated_fleet(n: int, secret: str, *, controller: str = "mixed", seed: int = 0,
                    link: str = "ednc", port: int | None = None,
                    opcua_security: str = "sign-and-encrypt", plc_class: str = "s7-300"
                    ) -> list[FleetEntry]:
    """``n`` vertical machining centres (module docstring); ``link`` modbus or opcua:
    each serves its controller's window at its own address and ``port`` (502 Modbus,
    4840 OPC UA by default), and the controller follows the link (Fanuc-style over Modbus,
    Siemens-style over OPC UA). An opcua link gets ``opcua_security`` (a key of
    :data:`OPCUA_SECURITY`) and ``plc_class`` (``s7-300`` or ``s7-1500``)."""
    if link not in ("ednc", "modbus", "opcua"):
        raise FleetSpecError(f"link must be ednc, modbus or opcua, got {link!r}")
    if opcua_security not in OPCUA_SECURITY:
        raise FleetSpecError(f"OPC UA security must be {', '.join(OPCUA_SECURITY)}, got "
                             f"{opcua_security!r}")
    if plc_class not in ("s7-300", "s7-1500"):
        raise FleetSpecError(f"PLC class must be s7-300 or s7-1500, got {plc_class!r}")
    if link != "ednc":
        want = "fanuc" if link == "modbus" else "siemens"
        if controller not in ("mixed", want):
            raise FleetSpecError(f"a {link} link serves {want}-style machines, not "
                                 f"{controller}")
        controller = want
    if n < 1:
        raise FleetSpecError(f"--machines must be at least 1, got {n}")
    if controller not in ("mixed", "fanuc", "siemens"):
        raise FleetSpecError(f"controller must be mixed, fanuc or siemens, got {controller!r}")
    key = _secret(secret, "--secret")
    out = []
    for i in range(n):
        kind = controller if controller != "mixed" else ("fanuc", "siemens")[i % 2]
        m = parse_machine({"name": f"{LINK_PREFIX[link]}-{i + 1:03d}", "controller": kind,
                           "ip": loopback_address(i, LINK_BLOCK[link]),
                           "chain": "w X Y b Z t",
                           "travel_mm": {"x": [0, 600], "y": [0, 400], "z": [-400, 0]},
                           "tool_length_mm": 100.0})
        spec: dict[str, Any] | None = None
        if link == "modbus":
            spec = {"kind": "modbus", "host": m.ip, "port": port or 502}
        elif link == "opcua":
            policy, mode = OPCUA_SECURITY[opcua_security]
            spec = {"kind": "opcua", "endpoint": f"opc.tcp://{m.ip}:{port or 4840}",
                    "user": "ednc", "password_ref": "env:EDNC_OPCUA_PASSWORD",
                    "security_policy": policy, "security_mode": mode,
                    "plc_class": plc_class}
        out.append(FleetEntry(m, key, seed + i, link=spec))
    return out


class Fleet:
    """Every machine of a fleet as one async context manager.

    Parameters
    ----------
    entries : sequence of FleetEntry
    center : (host, port) or sequence of them
        Several centers of one plant are tried in turn by every machine.
    mqtt : MqttTarget, optional
    cycle_s : float, optional
        Controller cycle for every machine (their own by default; a coarser one lets a
        large fleet run on one core).
    backoff : Backoff, optional
    state_dir : Path, optional
        Where the Modbus-served PMCs keep their windows across restarts (one
        ``<name>.pmc`` file each: the nonvolatile D area of protocol/README.md §13.1).
    """

    def __init__(self, entries: Sequence[FleetEntry],
                 center: tuple[str, int] | Sequence[tuple[str, int]] | None, *,
                 mqtt: MqttTarget | None = None, cycle_s: float | None = None,
                 backoff: Backoff | None = None, state_dir: Path | None = None) -> None:
        self.machines: list[SimulatedCNC] = []
        self.served: list[WindowCNC] = []
        for e in entries:
            if e.link_kind == "ednc":
                if center is None:
                    raise FleetSpecError(f"{e.machine.name} connects to a center: give "
                                         "--center HOST:PORT")
                self.machines.append(SimulatedCNC(e.machine, center, e.secret, ip=e.ip,
                                                  seed=e.seed, mqtt=mqtt, cycle_s=cycle_s,
                                                  backoff=backoff))
            else:
                self.served.append(served_machine(e, cycle_s, state_dir))
        self._stack = contextlib.AsyncExitStack()

    async def __aenter__(self) -> Fleet:
        async with contextlib.AsyncExitStack() as stack:
            for cnc in self.machines:
                await stack.enter_async_context(cnc)
            for served in self.served:
                await stack.enter_async_context(served)
            self._stack = stack.pop_all()
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        await self._stack.aclose()

    def summary(self) -> dict[str, int]:
        """Totals over the fleet: connected now, connects, maps acked and rejected, ..."""
        s = [c.stats for c in self.machines]
        w = [c.program for c in self.served]
        return {
            "machines": len(self.machines) + len(self.served),
            "served": len(self.served),
            "maps_applied_from_memory": sum(p.applied_switches for p in w),
            "maps_refused_from_memory": sum(p.rejected_switches for p in w),
            "ready": sum(c.ready.is_set() for c in self.machines),
            "connects": sum(x.connects for x in s),
            "welcomes": sum(x.welcomes for x in s),
            "maps_acked": sum(x.maps_acked for x in s),
            "maps_rejected": sum(x.maps_rejected for x in s),
            "releases": sum(x.releases for x in s),
            "telemetry_sent": sum(x.telemetry_sent for x in s),
            "mqtt_published": sum(x.mqtt_published for x in s),
            "refused": sum(len(x.rejects) for x in s),
        }


def served_machine(e: FleetEntry, cycle_s: float | None = None,
                   state_dir: Path | None = None) -> WindowCNC:
    """The simulated machine of an entry whose controller serves its window (a modbus or
    opcua link): it listens at its own address (the entry's ``ip`` or the machine's). A
    PMC keeps its window in ``state_dir/<name>.pmc`` when a directory is given."""
    link = dict(e.link or {})
    host = e.ip or e.machine.ip
    if e.link_kind == "modbus":
        from .modbus_server import PmcModbusServer

        port = int(link.get("port", 502))
        register = int(link.get("start_register", 0))
        order = str(link.get("byte_order", "little"))
        if order not in ("little", "big"):
            raise FleetSpecError(f"{e.machine.name}: byte_order little or big, got {order!r}")

        nonvolatile = None if state_dir is None else state_dir / f"{e.machine.name}.pmc"

        def modbus(cnc: WindowCNC) -> ControllerServer:
            return PmcModbusServer(cnc, host=host, port=port, register=register,
                                   byte_order=order,  # type: ignore[arg-type]
                                   nonvolatile=nonvolatile)

        return WindowCNC(e.machine, modbus, seed=e.seed, cycle_s=cycle_s)
    from .opcua_server import PLC_WRITER, OpcuaUser, sinumerik_server

    user = str(link.get("user", "ednc"))
    ref = str(link.get("password_ref", ""))
    kind, _, where = ref.partition(":")
    password = (os.environ.get(where) if kind == "env" else
                Path(where).read_text().strip() if kind == "file" and Path(where).exists()
                else None)
    if not password:
        raise FleetSpecError(f"{e.machine.name}: the simulated NC's user {user!r} needs the "
                             f"password its link names ({ref or 'password_ref'}): set it")
    endpoint = str(link.get("endpoint", f"opc.tcp://{host}:4840"))
    port = int(endpoint.rsplit(":", 1)[-1].split("/", 1)[0])
    # a link without security stands for a controller configured without it (only None
    # offered); otherwise the controller offers all three, as a SINUMERIK can
    insecure = "None" in (link.get("security_policy"), link.get("security_mode"))
    plc_class = str(link.get("plc_class", "s7-300"))
    if plc_class not in ("s7-300", "s7-1500"):
        raise FleetSpecError(f"{e.machine.name}: plc_class s7-300 or s7-1500, got "
                             f"{plc_class!r}")
    return WindowCNC(e.machine, sinumerik_server(
        {user: OpcuaUser(password, PLC_WRITER)}, host=host, port=port,
        security_modes=("None",) if insecure else ("None", "Sign", "SignAndEncrypt"),
        plc_class=plc_class), seed=e.seed, cycle_s=cycle_s)
