"""Prometheus metrics of the service, on a registry of their own per application.

A per-app :class:`~prometheus_client.CollectorRegistry` (not the process-global one) lets
tests build several apps in one process without "duplicated timeseries" errors. The TCP
server and the push scheduler update these instruments; ``GET /metrics`` exposes them.
"""

from __future__ import annotations

from collections.abc import Callable

from prometheus_client import CollectorRegistry, Counter, Gauge, Histogram, generate_latest
from prometheus_client.exposition import CONTENT_TYPE_LATEST

__all__ = ["CONTENT_TYPE_LATEST", "Metrics"]

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

    def track_connected(self, count: Callable[[], int]) -> None:
        """Read the connected-machines gauge from ``count()`` at every scrape."""
        self.machines_connected.set_function(count)

    def exposition(self) -> bytes:
        """The text exposition format of every instrument."""
        return generate_latest(self.registry)
