"""``ednc sim``: run simulated CNCs against a control center, or write a simulated campaign.

Two modes:

* ``ednc sim --center HOST:PORT --machines N --secret S`` (or ``--fleet FILE``): N
  simulated Fanuc/Siemens-style machines connect to the center, authenticate, take maps,
  send telemetry (and MQTT temperatures with ``--mqtt``) until Ctrl-C or ``--duration``.
  The center admits only machines it knows (name, address, secret): ``--register`` adds
  the generated ones through the REST API first (``POST /api/machines`` with the API key);
  without it, a run in which no machine is welcomed says so and how to fix it.
* ``ednc sim --campaign OUT.csv --machine M.json [--effect ...]``: a standard measurement
  campaign on a machine with a random true geometry, written as a measurement CSV
  (formats.md section 2); the truth goes to ``--truth TRUTH.json`` if asked.
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import json
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import httpx
import numpy as np
import typer

from ednc.cli import UserError

if TYPE_CHECKING:
    from machine_sim.fleet import FleetEntry
    from volumetric.model.machine import Machine

# A run in which no machine has been welcomed after this long says why that usually is.
UNWELCOMED_HINT_S = 10.0


def register(app: typer.Typer) -> None:
    @app.command("sim")
    def sim(
        center: Annotated[str | None, typer.Option(
            "--center", help="HOST:PORT of the center's machine port; several centers of "
                             "one plant as HOST:PORT,HOST:PORT (tried in turn).")] = None,
        machines: Annotated[int, typer.Option(
            "--machines", help="Generate this many machines (sim-001, ...; sim-pmc-001 "
                               "over --link modbus, sim-nc-001 over opcua).")] = 0,
        fleet: Annotated[Path | None, typer.Option(
            "--fleet", help="Fleet file (JSON/YAML) with machines and secrets.")] = None,
        secret: Annotated[str | None, typer.Option(
            "--secret", help="Secret of the generated machines (>= 16 bytes). The center "
                             "must know them with this secret: see --register.",
            envvar="EDNC_SIM_SECRET")] = None,
        register_: Annotated[bool, typer.Option(
            "--register", help="Before connecting, register the generated machines at the "
                               "center through its REST API (needs --api-key); machines "
                               "it already has are left as they are.")] = False,
        api: Annotated[str | None, typer.Option(
            "--api", help="For --register: the center's REST API base URL (default: "
                          "http://HOST:8080 with the host of --center).")] = None,
        api_key: Annotated[str | None, typer.Option(
            "--api-key", help="For --register: the center's API key (X-API-Key).",
            envvar="EDNC_API_KEY")] = None,
        controller: Annotated[str, typer.Option(
            "--controller", help="Generated machines: mixed, fanuc or siemens.")] = "mixed",
        mqtt: Annotated[str | None, typer.Option(
            "--mqtt", help="HOST:PORT of an MQTT broker for Fanuc-style temperatures.")
        ] = None,
        cycle_ms: Annotated[float | None, typer.Option(
            "--cycle-ms", help="Controller cycle (default: 8 ms Fanuc, 4 ms Siemens; "
                               "20-50 lets hundreds of machines share one core).")
        ] = None,
        duration: Annotated[float | None, typer.Option(
            "--duration", help="Stop after this many seconds (default: until Ctrl-C).")
        ] = None,
        campaign: Annotated[Path | None, typer.Option(
            "--campaign", help="Write a simulated measurement campaign CSV here.")] = None,
        machine: Annotated[Path | None, typer.Option(
            "--machine", help="Machine description for --campaign.")] = None,
        effect: Annotated[list[str] | None, typer.Option(
            "--effect", help="For --campaign, repeatable: backlash:AXIS:B_um, "
                             "periodic:AXIS:A_um:P_mm, expansion:AXIS:SENSOR:um_per_m_K, "
                             "drift:AXIS:SENSOR:um_per_K[:LAG_S], time:AXIS:um_per_h, "
                             "noise:UM[:URAD]. Default: no effects and no noise (noise 0 "
                             "µm, 0 µrad), so the readings are the exact geometric errors; "
                             "add noise:0.3 for a laser's.")] = None,
        truth: Annotated[Path | None, typer.Option(
            "--truth", help="For --campaign: write the true geometry and effects (JSON).")
        ] = None,
        seed: Annotated[int, typer.Option("--seed", help="Random seed.")] = 0,
        only: Annotated[list[str] | None, typer.Option(
            "--only", help="With --fleet, run only these machines (repeatable): one "
                           "container per machine, each with its own address.")] = None,
        link: Annotated[str, typer.Option(
            "--link", help="Generated machines: ednc (they connect to the center with the "
                           "EDNC protocol), modbus (Fanuc-style PMCs serving their window "
                           "through Modbus/TCP at their own address; the center connects "
                           "to them) or opcua (Siemens-style NCs behind an OPC UA server). "
                           "A fleet file says it per machine (its description's link).")
        ] = "ednc",
        port: Annotated[int | None, typer.Option(
            "--port", help="With --link modbus|opcua: the port each machine's server "
                           "listens on at its address (default 502 Modbus, 4840 OPC UA).")
        ] = None,
        opcua_security: Annotated[str, typer.Option(
            "--opcua-security", help="With --link opcua: the security of the generated "
                                     "links: sign-and-encrypt (Basic256Sha256, the "
                                     "default), sign, or none (the NCs then offer only "
                                     "None and the password travels in clear).")
        ] = "sign-and-encrypt",
        plc_class: Annotated[str, typer.Option(
            "--plc-class", help="With --link opcua: the NCs' PLC class, s7-300 (840D sl, "
                                "240 bytes per write, the default) or s7-1500 "
                                "(SINUMERIK ONE, 960).")] = "s7-300",
        state_dir: Annotated[Path | None, typer.Option(
            "--state-dir", help="With Modbus-served PMCs: keep each one's window (status, "
                                "buffers, the center's command) in DIR/<name>.pmc across "
                                "restarts, as a PMC's nonvolatile D area keeps it.")
        ] = None,
    ) -> None:
        """Run simulated machines against a center, or write a simulated campaign."""
        from ednc.inputs import check_output, float_option, int_option, warn
        from volumetric.plausible.counts import MAX_GENERATED_MACHINES
        from volumetric.plausible.times import duration_warning

        int_option(seed, "--seed", 0, 2**63 - 1)
        int_option(machines, "--machines", 0, MAX_GENERATED_MACHINES,
                   " (each needs a loopback address of its own)")
        if cycle_ms is not None:
            float_option(cycle_ms, "--cycle-ms", 0.0, 60_000.0, lo_open=True, unit=" ms")
        if duration is not None:
            float_option(duration, "--duration", 0.0, 1e9, lo_open=True, unit=" s")
            long = duration_warning(duration, "--duration", 60.0)
            if long is not None:  # 60000 meant as ms is 17 h of machines
                warn(long)
        if controller not in ("mixed", "fanuc", "siemens"):
            raise UserError(f"--controller {controller!r}: expected mixed, fanuc or siemens")
        if link not in ("ednc", "modbus", "opcua"):
            raise UserError(f"--link {link!r}: expected ednc, modbus or opcua")
        if port is not None:
            int_option(port, "--port", 1, 65535)
        if opcua_security not in ("sign-and-encrypt", "sign", "none"):
            raise UserError(f"--opcua-security {opcua_security!r}: expected "
                            "sign-and-encrypt, sign or none")
        if plc_class not in ("s7-300", "s7-1500"):
            raise UserError(f"--plc-class {plc_class!r}: expected s7-300 or s7-1500")
        check_output(campaign, "--campaign")
        check_output(truth, "--truth")
        if campaign is not None:
            if center is not None or machines or fleet is not None:
                raise UserError("--campaign writes a file; it does not take --center, "
                                "--machines or --fleet")
            write_campaign_file(campaign, machine, effect or [], truth, seed)
            return
        if register_ and not machines:
            raise UserError("--register registers the machines of --machines N; a fleet "
                            "file's machines go to the center's EDNC_MACHINES_FILE (or "
                            "POST /api/machines)")
        registration = None
        if register_:
            if api_key is None:
                raise UserError("--register needs --api-key KEY (or EDNC_API_KEY): the "
                                "center's API key, which writes need")
            registration = (api, api_key)
        run_fleet(center, machines, fleet, secret, controller, mqtt, cycle_ms, duration, seed,
                  only or [], registration, link=link, port=port,
                  opcua_security=opcua_security, plc_class=plc_class, state_dir=state_dir)


def run_fleet(center: str | None, machines: int, fleet_file: Path | None, secret: str | None,
              controller: str, mqtt: str | None, cycle_ms: float | None,
              duration: float | None, seed: int, only: list[str],
              registration: tuple[str | None, str] | None = None, *, link: str = "ednc",
              port: int | None = None, opcua_security: str = "sign-and-encrypt",
              plc_class: str = "s7-300", state_dir: Path | None = None) -> None:
    """The network mode (module docstring); ``registration`` is (API URL or None, key)."""
    from machine_sim.fleet import (
        Fleet,
        FleetSpecError,
        generated_fleet,
        load_fleet,
        parse_center,
        parse_centers,
    )
    from machine_sim.link import MqttTarget

    try:
        settings: dict[str, Any] = {}
        if fleet_file is not None:
            if machines:
                raise UserError("give either --fleet or --machines, not both")
            entries, settings = load_fleet(fleet_file)
            if only:
                unknown = sorted(set(only) - {e.machine.name for e in entries})
                if unknown:
                    raise UserError(f"--only {', '.join(unknown)}: not in {fleet_file} "
                                    f"({', '.join(e.machine.name for e in entries)})")
                entries = [e for e in entries if e.machine.name in only]
        elif machines:
            if secret is None:
                raise UserError("--machines needs --secret (or EDNC_SIM_SECRET): the secret "
                                "the center has for the generated machines")
            entries = generated_fleet(machines, secret, controller=controller, seed=seed,
                                      link=link, port=port, opcua_security=opcua_security,
                                      plc_class=plc_class)
        else:
            raise UserError("give --machines N (with --secret) or --fleet FILE, "
                            "or --campaign OUT.csv")
        where = center or settings.get("center")
        connecting = any(e.link_kind == "ednc" for e in entries)
        if where is None and (connecting or (registration is not None and
                              registration[0] is None)):
            raise UserError("give --center HOST:PORT (or 'center' in the fleet file)")
        addresses = parse_centers(where) if where is not None else []
        target = None
        mq = settings.get("mqtt")
        if mqtt is not None:
            host, port = parse_center(mqtt)
            target = MqttTarget(host, port)
        elif isinstance(mq, dict) and "host" in mq:
            target = MqttTarget(str(mq["host"]), int(mq.get("port", 1883)),
                                str(mq.get("prefix", "ednc")))
    except FleetSpecError as exc:
        raise UserError(str(exc)) from exc
    if cycle_ms is not None and not cycle_ms > 0:
        raise UserError(f"--cycle-ms must be > 0, got {cycle_ms}")
    cycle_s = None if cycle_ms is None else cycle_ms / 1000.0
    if state_dir is not None:
        try:
            state_dir.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise UserError(f"--state-dir {state_dir}: cannot create it "
                            f"({exc.strerror or exc})") from None
    if registration is not None:
        url = registration[0] or f"http://{_url_host(addresses[0][0])}:8080"
        secret_text = secret or ""
        added, known = asyncio.run(_register_at(url, registration[1], entries, secret_text))
        typer.echo(f"registered {len(added)} machines at {url}"
                   + (f"; {len(known)} were already registered" if known else ""))

    async def main() -> dict[str, int]:
        async with Fleet(entries, addresses or None, mqtt=target, cycle_s=cycle_s,
                         state_dir=state_dir) as f:
            if f.machines:
                typer.echo(f"{len(f.machines)} simulated machines connecting to "
                           + ", ".join(f"{host}:{port}" for host, port in addresses))
            for served in f.served:
                where = getattr(served.server, "address", None) or getattr(
                    served.server, "endpoint", "?")
                typer.echo(f"{served.machine.name}: {served.machine.controller}-style "
                           f"controller serving its window on {where}")
            with contextlib.suppress(TimeoutError):
                async with asyncio.timeout(duration):
                    async with asyncio.TaskGroup() as tg:
                        if f.machines:
                            tg.create_task(_hint_if_unwelcomed(f.summary, machines > 0),
                                           name="sim-unwelcomed-hint")
                        await asyncio.Event().wait()
            return f.summary()

    with contextlib.suppress(KeyboardInterrupt):
        try:
            summary = asyncio.run(main())
        except FleetSpecError as exc:  # e.g. a served machine's password is not set
            raise UserError(str(exc)) from exc
        typer.echo(json.dumps(summary))
        if summary["welcomes"] == 0 and summary["served"] < summary["machines"]:
            typer.echo(unwelcomed_hint(machines > 0), err=True)


def unwelcomed_hint(generated: bool) -> str:
    """Why no machine was welcomed, usually, and what to do about it."""
    how = ("run again with --register --api-key KEY (registers them through the center's "
           "REST API), or POST each to /api/machines" if generated else
           "list them in the center's EDNC_MACHINES_FILE or POST each to /api/machines")
    return ("ednc sim: no machine was welcomed by the center. It admits only machines it "
            "has registered, with the same name, address and secret; " + how + ".")


async def _hint_if_unwelcomed(summary: Callable[[], dict[str, int]], generated: bool) -> None:
    """Say once, while the run goes on, that no machine has been welcomed yet."""
    await asyncio.sleep(UNWELCOMED_HINT_S)
    if summary()["welcomes"] == 0:
        typer.echo(unwelcomed_hint(generated), err=True)


def _url_host(host: str) -> str:
    return f"[{host}]" if ":" in host else host


def machine_description(m: Machine) -> dict[str, Any]:
    """The description the REST API takes for a generated (single-spindle) machine."""
    return {"name": m.name, "controller": m.controller, "ip": m.ip, "chain": m.chain,
            "travel_mm": {a.key: [float(a.travel[0]), float(a.travel[1])] for a in m.axes},
            "tool_length_mm": float(m.branches[0].tool_length_mm)}


async def register_fleet(client: httpx.AsyncClient, entries: list[FleetEntry], secret: str,
                         ) -> tuple[list[str], list[str]]:
    """Register each machine (``POST /api/machines``); returns (added, already known).

    ``client`` carries the base URL and the ``X-API-Key`` header. A machine the center has
    already (409) is left as it is: its secret there may differ, which the run then shows
    as a refusal.

    Raises
    ------
    UserError
        The API is unreachable, refuses the key, or refuses a description.
    """
    added: list[str] = []
    known: list[str] = []
    for e in entries:
        body = {**machine_description(e.machine), "secret": secret}
        if e.link is not None:
            body["link"] = dict(e.link)
        try:
            r = await client.post("/api/machines", json=body)
        except httpx.HTTPError as exc:
            raise UserError(f"--register: cannot reach the center's REST API at "
                            f"{client.base_url}: {exc or type(exc).__name__}; "
                            "give its URL with --api") from exc
        if r.status_code == 201:
            added.append(e.machine.name)
        elif r.status_code == 409:
            known.append(e.machine.name)
        elif r.status_code in (401, 403):
            raise UserError(f"--register: the center refused the API key ({r.status_code}); "
                            "give the key of its EDNC_API_KEY with --api-key")
        else:
            raise UserError(f"--register: the center refused {e.machine.name} "
                            f"({r.status_code}): {r.text[:300]}")
    return added, known


async def _register_at(url: str, key: str, entries: list[FleetEntry], secret: str,
                       ) -> tuple[list[str], list[str]]:
    async with httpx.AsyncClient(base_url=url, headers={"X-API-Key": key},
                                 timeout=10.0) as client:
        return await register_fleet(client, entries, secret)


def _effects(specs: list[str], sensors: tuple[str, ...]) -> Any:
    from machine_sim.effects import (
        Backlash,
        Effects,
        Noise,
        Periodic,
        ThermalDrift,
        ThermalExpansion,
        TimeDrift,
    )

    parts: dict[str, list[Any]] = {"expansion": [], "drift": [], "backlash": [],
                                   "periodic": [], "time": []}
    noise = Noise()
    for spec in specs:
        kind, *args = spec.split(":")
        try:
            if kind == "backlash" and len(args) == 2:
                parts["backlash"].append(Backlash(args[0], float(args[1])))
            elif kind == "periodic" and len(args) in (3, 4):
                phase = float(args[3]) if len(args) == 4 else 0.0
                parts["periodic"].append(Periodic(args[0], float(args[1]), float(args[2]),
                                                  phase))
            elif kind == "expansion" and len(args) == 3:
                parts["expansion"].append(ThermalExpansion(args[0], args[1], float(args[2])))
            elif kind == "drift" and len(args) in (3, 4):
                lag = float(args[3]) if len(args) == 4 else 0.0
                parts["drift"].append(ThermalDrift(args[0], args[1], float(args[2]),
                                                   lag_s=lag))
            elif kind == "time" and len(args) == 2:
                parts["time"].append(TimeDrift(args[0], float(args[1])))
            elif kind == "noise" and len(args) in (1, 2):
                noise = Noise(float(args[0]), float(args[1]) if len(args) == 2 else 0.0)
            else:
                raise UserError(f"--effect {spec!r}: expected backlash:AXIS:B_um, "
                                "periodic:AXIS:A_um:P_mm[:PHASE], expansion:AXIS:SENSOR:ALPHA, "
                                "drift:AXIS:SENSOR:K[:LAG_S], time:AXIS:UM_PER_H or "
                                "noise:UM[:URAD]")
        except ValueError as exc:
            raise UserError(f"--effect {spec!r}: {exc}") from exc
        if kind in ("expansion", "drift") and args[1] not in sensors:
            raise UserError(f"--effect {spec!r}: no sensor {args[1]!r}; the simulated "
                            f"machine has {', '.join(sensors)}")
    return Effects(tuple(parts["expansion"]), tuple(parts["drift"]),
                   tuple(parts["backlash"]), tuple(parts["periodic"]), noise,
                   tuple(parts["time"]))


def write_campaign_file(out: Path, machine_path: Path | None, effect: list[str],
                        truth: Path | None, seed: int) -> None:
    """The campaign mode (module docstring)."""
    from ednc.inputs import warn
    from machine_sim.campaign import standard_campaign, write_campaign
    from machine_sim.instruments import SimulatedMachine
    from machine_sim.testprograms import RTestSetupError
    from machine_sim.thermal import default_thermal
    from machine_sim.truth import random_geometry
    from volumetric.errors import MachineSpecError
    from volumetric.model.machine import description_warnings, load_machine, metres_problem

    if machine_path is None:
        raise UserError("--campaign needs --machine M.json")
    try:
        m = load_machine(machine_path, require_pivots=True)
    except MachineSpecError as exc:
        raise UserError(str(exc)) from exc
    metres = metres_problem(m)
    if metres is not None:  # a campaign needs room on every axis: nothing to measure
        raise UserError(f"{machine_path}: {metres}")
    for w in description_warnings(m):
        warn(f"{machine_path}: {w}")
    rng = np.random.default_rng(seed)
    effects = _effects(effect, default_thermal(m).names)
    try:
        sim = SimulatedMachine(m, random_geometry(m, rng), effects, seed=seed)
    except ValueError as exc:
        raise UserError(str(exc)) from exc
    try:
        meas = standard_campaign(sim, rng)
    except (RTestSetupError, ValueError) as exc:  # e.g. a travel too short for a test
        raise UserError(f"{machine_path}: no campaign on this machine: {exc}") from exc
    try:
        write_campaign(out, meas)
        if truth is not None:
            truth.write_text(json.dumps({"geometry": sim.geometry.to_json(),
                                         "effects": dataclasses.asdict(sim.effects),
                                         "seed": seed},
                                        indent=1))
    except OSError as exc:
        raise UserError(f"cannot write: {exc}") from exc
    typer.echo(f"{len(meas)} readings over {meas.time_s[-1] / 3600:.1f} h written to {out}")
