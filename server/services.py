"""The long-lived machine services of one control-center process, for ``create_app``.

:func:`machine_services` is a service factory (``create_app(services=[machine_services])``,
which ``ednc serve`` uses): inside it run, started in this order and stopped in reverse,

0. the :class:`~server.heap.HeapKeeper` (short garbage-collector passes with a thousand
   sessions: the survivors of each full pass are frozen),
1. the :class:`~server.push.PushScheduler` (it must listen before any machine arrives),
2. the :class:`~server.leasing.LeaseKeeper` (this node's machine leases: released after
   the sessions closed) and the :class:`~server.plant.LinkPublisher` (this node's live
   links in the database for every node's dashboard; its last write comes after the
   sessions closed),
3. the :class:`~server.links.ednc.MachineServer` on ``EDNC_MACHINE_HOST:PORT``, then the
   :class:`~server.links.window.service.ControllerLinks` (the center as client of the
   machines registered with a ``modbus`` or ``opcua`` link; their sessions share the
   machine server's session table) and the :class:`~server.links.sdservice.NativeSdLinks`
   (machines registered with a ``sinumerik_sd`` link: the center writes their NC's
   temperature compensation setting data; off with leases),
4. the :class:`~server.intake.TemperatureIntake` (checks, stores and forwards every
   temperature; handed to the Center for the REST API),
5. the :class:`~server.mqtt.MqttBridge` when ``EDNC_MQTT_HOST`` is set (MQTT off
   otherwise; a configured broker that is down does not stop start-up: the bridge keeps
   retrying in the background).
"""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator
from contextlib import AsyncExitStack, asynccontextmanager
from dataclasses import dataclass
from typing import Any

from server.center import Center
from server.feed import Feed
from server.heap import HeapKeeper
from server.intake import TemperatureIntake
from server.leasing import LeaseKeeper
from server.links.ednc import LinkTiming, MachineServer
from server.links.ednc.server import MAX_HANDSHAKES
from server.links.sdservice import NativeSdLinks
from server.links.window.service import ControllerLinks
from server.mqtt import MqttBridge
from server.plant import LinkPublisher
from server.push import PushScheduler
from server.temperatures import TemperatureBoard

log = logging.getLogger(__name__)


@dataclass
class MachineServices:
    """The running services, for tests, benchmarks and the CLI's start-up line."""

    feed: Feed
    temperatures: TemperatureBoard
    push: PushScheduler
    server: MachineServer
    mqtt: MqttBridge | None
    leases: LeaseKeeper | None = None
    links: LinkPublisher | None = None
    intake: TemperatureIntake | None = None
    heap: HeapKeeper | None = None
    controllers: ControllerLinks | None = None
    native: NativeSdLinks | None = None


@asynccontextmanager
async def machine_services(
    center: Center, *, timing: LinkTiming | None = None, stale_after_s: float | None = None,
    push_options: dict[str, Any] | None = None, mqtt_options: dict[str, Any] | None = None,
    publish_period_s: float = 1.0, max_handshakes: int = MAX_HANDSHAKES,
) -> AsyncIterator[MachineServices]:
    """Run the push scheduler, the machine TCP server and (if configured) the MQTT bridge.

    Parameters
    ----------
    center : Center
    timing : LinkTiming, optional
        Handshake and heartbeat deadlines (the settings' heartbeat by default).
    stale_after_s : float, optional
        Age after which a temperature counts as stale (``EDNC_TEMPERATURE_STALE_S``).
    push_options : dict, optional
        Keyword arguments of :class:`PushScheduler` (``threshold_K``, ``tolerance_um``...).
    max_handshakes : int
        Connections allowed between accept and Welcome at once.
    mqtt_options : dict, optional
        Keyword arguments of :class:`MqttBridge` (``backoff``, ``stale_check_s``...).
    publish_period_s : float
        How often this node's changed live links are written for the other nodes, s.
    """
    settings = center.settings
    feed = Feed(center)
    temperatures = TemperatureBoard(
        settings.temperature_stale_s if stale_after_s is None else stale_after_s)
    async with AsyncExitStack() as stack:
        heap = await stack.enter_async_context(HeapKeeper())
        push = await stack.enter_async_context(
            PushScheduler(center, feed, temperatures, **(push_options or {})))
        leases = (await stack.enter_async_context(LeaseKeeper(center))
                  if settings.uses_leases else None)
        links = await stack.enter_async_context(
            LinkPublisher(center, period_s=publish_period_s))
        server = await stack.enter_async_context(MachineServer(
            center, feed, temperatures, worker=push.serve, host=settings.machine_host,
            port=settings.machine_port, timing=timing, leases=leases,
            max_handshakes=max_handshakes))
        controllers = await stack.enter_async_context(ControllerLinks(
            center, feed, server.sessions, push.serve, leases=leases,
            reconcile_s=settings.controller_reconcile_s,
            telemetry_s=server.timing.telemetry_period_ms / 1000))
        native = await stack.enter_async_context(NativeSdLinks(
            center, feed, temperatures, commit_listeners=push.commit_listeners,
            reconcile_s=settings.controller_reconcile_s,
            enabled=not settings.uses_leases))
        intake = await stack.enter_async_context(
            TemperatureIntake(center, temperatures, feed, sessions=server.sessions))
        center.intake = intake
        stack.callback(setattr, center, "intake", None)
        center.temperatures = temperatures  # the dashboard's view of the board
        stack.callback(setattr, center, "temperatures", None)
        mqtt = None
        if settings.mqtt_host is not None:
            mqtt = await stack.enter_async_context(MqttBridge(
                center, feed, temperatures, host=settings.mqtt_host, port=settings.mqtt_port,
                prefix=settings.mqtt_topic_prefix, **(mqtt_options or {})))
        else:
            log.info("EDNC_MQTT_HOST is not set: MQTT is off")
        yield MachineServices(feed, temperatures, push, server, mqtt, leases, links, intake,
                              heap, controllers, native)
