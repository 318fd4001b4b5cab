"""Prometheus metrics of the service, on a registry of their own per application.

A per-app :class:`~prometheus_client.CollectorRegistry` (not the process-global one) lets
tests build several apps in one process without "duplicated timeseries" errors. The TCP
server and the push scheduler update the service-wide instruments; the per-machine series
(``ednc_machine_*``, labelled ``machine``) are set from a dashboard snapshot at every
scrape (:meth:`Metrics.set_machines`), so that they say what the dashboard says;
``GET /metrics`` exposes them all. ``deploy/alerts.yml`` holds example alert rules on them.

``*_created`` series are not exported (:func:`prometheus_client.disable_created_metrics`):
they double every counter's lines and no rule here reads them.
"""

from __future__ import annotations

import platform
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from prometheus_client import (
    CollectorRegistry,
    Counter,
    Gauge,
    Histogram,
    Info,
    disable_created_metrics,
    generate_latest,
)
from prometheus_client.exposition import CONTENT_TYPE_LATEST
from prometheus_client.metrics_core import CounterMetricFamily, GaugeMetricFamily, Metric
from prometheus_client.registry import Collector

from server.health import STATES
from server.version import __version__

if TYPE_CHECKING:  # the dashboard's schemas import more of the server than metrics need
    from server.dashboard.schemas import DashboardSnapshot, MachineCard

__all__ = ["CONTENT_TYPE_LATEST", "MachineSample", "Metrics", "machine_samples"]

disable_created_metrics()  # type: ignore[no-untyped-call]

OUTCOMES = ("applied", "rejected", "failed")
"""Map delivery outcomes, pre-created at 0 so that ``rate()`` and alerts see the series
before the first rejection."""
REFUSAL_REASONS = ("unknown", "unregistered", "auth", "duplicate", "owned", "throttled",
                   "busy", "timeout", "protocol")


@dataclass(frozen=True, slots=True)
class MachineSample:
    """One machine's per-machine series at one scrape (None: no value, no series).

    Ages in s, lengths in µm; ``state`` one of :data:`server.health.STATES`.
    """

    machine: str
    state: str
    connected: bool
    map_version_applied: int | None = None
    map_age_s: float | None = None
    telemetry_age_s: float | None = None
    thermal_state_age_s: float | None = None
    model_age_s: float | None = None
    residual_um: float | None = None
    tolerance_um: float | None = None
    map_error_um: float | None = None
    temperatures_C: dict[str, float] = field(default_factory=dict)
    rejects_total: int = 0
    link: str = "ednc"
    link_state: str = "offline"
    link_reason: str = ""


_GAUGES: tuple[tuple[str, str, str], ...] = (
    ("map_version_applied", "ednc_machine_map_version_applied",
     "Map version the machine last acknowledged as applied."),
    ("map_age_s", "ednc_machine_map_age_seconds",
     "Seconds since the applied map was sent."),
    ("telemetry_age_s", "ednc_machine_telemetry_age_seconds",
     "Seconds since the machine's last telemetry."),
    ("thermal_state_age_s", "ednc_machine_thermal_state_age_seconds",
     "Seconds since the stalest temperature the thermal compensation follows was read."),
    ("model_age_s", "ednc_machine_model_age_seconds", "Seconds since the newest model was "
                                                      "stored."),
    ("residual_um", "ednc_machine_verification_residual_um",
     "Largest body-diagonal range of the last verification (compensated when measured), "
     "micrometres."),
    ("tolerance_um", "ednc_machine_accuracy_tolerance_um",
     "The machine's accuracy tolerance (largest compensated diagonal range), micrometres."),
    ("map_error_um", "ednc_machine_map_error_um",
     "The newest map's worst tool-tip error as sent, micrometres."),
)


class MachineCollector(Collector):
    """The per-machine series, from the samples of the last :meth:`Metrics.set_machines`."""

    def __init__(self) -> None:
        self.samples: tuple[MachineSample, ...] = ()

    def describe(self) -> Iterable[Metric]:
        return ()  # families depend on the machines; nothing to check at registration

    def collect(self) -> Iterator[Metric]:
        samples = self.samples
        state = GaugeMetricFamily(
            "ednc_machine_accuracy_state", "1 for the machine's accuracy state (ok, unknown, "
            "warn, offline, alarm, out_of_tolerance; see server/health.py), 0 for the others.",
            labels=["machine", "state"])
        connected = GaugeMetricFamily("ednc_machine_connected",
                                      "1 while the machine has a live link.", labels=["machine"])
        links = GaugeMetricFamily(
            "ednc_machine_link_info", "1 for how the center reaches the machine: ednc (the "
            "machine connects), modbus or opcua (the center connects to its controller).",
            labels=["machine", "link"])
        link_state = GaugeMetricFamily(
            "ednc_machine_link_state", "1 for what the machine's link is doing now "
            "(connected, connecting, plc_stopped, refused, unreachable, failed, offline), "
            "with the reason (server/links/state.py).",
            labels=["machine", "link", "state", "reason"])
        for s in samples:
            for label in STATES:
                state.add_metric([s.machine, label], 1.0 if s.state == label else 0.0)
            connected.add_metric([s.machine], 1.0 if s.connected else 0.0)
            links.add_metric([s.machine, s.link], 1.0)
            link_state.add_metric([s.machine, s.link, s.link_state, s.link_reason], 1.0)
        yield state
        yield connected
        yield links
        yield link_state
        for attr, name, doc in _GAUGES:
            family = GaugeMetricFamily(name, doc, labels=["machine"])
            for s in samples:
                value = getattr(s, attr)
                if value is not None:
                    family.add_metric([s.machine], float(value))
            yield family
        temps = GaugeMetricFamily("ednc_machine_temperature_celsius",
                                  "Latest temperature of each sensor, °C.",
                                  labels=["machine", "sensor"])
        rejects = CounterMetricFamily("ednc_machine_map_rejects",
                                      "Map deliveries the machine rejected (stored ones).",
                                      labels=["machine"])
        for s in samples:
            for sensor, celsius in sorted(s.temperatures_C.items()):
                temps.add_metric([s.machine, sensor], celsius)
            rejects.add_metric([s.machine], float(s.rejects_total))
        yield temps
        yield rejects

# Pushing a map is a TCP round trip on a LAN plus the PLC's apply: milliseconds to seconds.
PUSH_LATENCY_BUCKETS_S = (0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 30.0)


class Metrics:
    """The service's instruments.

    Attributes
    ----------
    machines_connected : Gauge
        Machines with an open session (read from the registry at scrape time once
        :meth:`track_connected` is called).
    pushes : Counter
        Map deliveries by ``outcome``: ``applied``, ``rejected``, ``failed`` (no answer).
    push_latency : Histogram
        Seconds from sending a map to the machine's answer.
    refusals : Counter
        Connections refused, by ``reason`` (e.g. ``unknown``, ``auth``, ``duplicate``).
    events : Counter
        Events recorded, by ``kind``.
    logins_throttled : Counter
        Logins refused without a look at their answer, because failures from that address
        or for that name came too fast (also counted in ``refusals`` as ``throttled``).
    build_info : Info
        ``ednc_build_info{version, python} 1``.
    machines : MachineCollector
        The per-machine series (``ednc_machine_*``), set by :meth:`set_machines`.
    """

    def __init__(self) -> None:
        self.registry = CollectorRegistry(auto_describe=True)
        self.machines_connected = Gauge(
            "ednc_machines_connected", "Machines with an open session.", registry=self.registry
        )
        self.pushes = Counter(
            "ednc_map_pushes", "Error-map deliveries by outcome.", ["outcome"],
            registry=self.registry,
        )
        self.push_latency = Histogram(
            "ednc_map_push_latency_seconds", "Seconds from sending a map to the machine's answer.",
            buckets=PUSH_LATENCY_BUCKETS_S, registry=self.registry,
        )
        self.refusals = Counter(
            "ednc_connections_refused", "Machine connections refused, by reason.", ["reason"],
            registry=self.registry,
        )
        self.events = Counter(
            "ednc_events", "Events recorded, by kind.", ["kind"], registry=self.registry
        )
        self.handshake_evictions = Counter(
            "ednc_handshake_evictions", "Handshakes closed to give their slot to a peer from "
            "another address (all slots taken, this one waiting longest on its peer).",
            registry=self.registry,
        )
        self.logins_throttled = Counter(
            "ednc_logins_throttled", "Machine logins refused by the failed-login throttle.",
            registry=self.registry,
        )
        for outcome in OUTCOMES:
            self.pushes.labels(outcome=outcome)
        for reason in REFUSAL_REASONS:
            self.refusals.labels(reason=reason)
        self.build_info = Info("ednc_build", "The running control center.",
                               registry=self.registry)
        self.build_info.info({"version": __version__,
                              "python": platform.python_version()})
        self.machines = MachineCollector()
        self.registry.register(self.machines)

    def set_machines(self, samples: Sequence[MachineSample]) -> None:
        """Replace the per-machine series (machines absent from ``samples`` disappear)."""
        self.machines.samples = tuple(samples)

    def track_connected(self, count: Callable[[], int]) -> None:
        """Read the connected-machines gauge from ``count()`` at every scrape."""
        self.machines_connected.set_function(count)

    def exposition(self) -> bytes:
        """The text exposition format of every instrument."""
        return generate_latest(self.registry)


def _thermal_age(card: MachineCard) -> float | None:
    """Age of the stalest temperature the machine's compensation follows, s (a reading
    from telemetry is as old as the telemetry)."""
    ages = [t.age_s if t.age_s is not None else card.telemetry_age_s
            for t in card.temperatures]
    known = [a for a in ages if a is not None]
    return max(known) if known else None


def machine_samples(snapshot: DashboardSnapshot, rejects: dict[str, int] | None = None
                    ) -> list[MachineSample]:
    """The per-machine series of a dashboard snapshot (``rejects``: stored rejections by
    machine name). Add a series here and in :class:`MachineCollector`."""
    out = []
    for card in snapshot.machines:
        accuracy = card.accuracy
        out.append(MachineSample(
            machine=card.name, state=card.health, connected=card.connected,
            map_version_applied=card.maps.applied, map_age_s=card.maps.age_s,
            telemetry_age_s=card.telemetry_age_s, thermal_state_age_s=_thermal_age(card),
            model_age_s=None if accuracy is None else accuracy.model_age_s,
            residual_um=None if accuracy is None else accuracy.residual_um,
            tolerance_um=None if accuracy is None else accuracy.tolerance_um,
            map_error_um=card.maps.error_um,
            temperatures_C={t.name: t.celsius for t in card.temperatures},
            rejects_total=(rejects or {}).get(card.name, 0), link=card.link,
            link_state=card.link_state, link_reason=card.link_reason))
    return out
