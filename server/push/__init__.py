"""Pushing maps to connected machines.

``scheduler``: one worker per session that keeps its machine's map current (the flow
and its triggers are described there); ``steps``: the database transactions it runs;
``watcher``: the commit hook that tells it a model changed; ``adapter``: the numeric
core's map build behind a database-shaped call. Data flows scheduler -> steps / adapter;
nothing here imports the scheduler back.
"""

from server.push.adapter import build_for, thermal_sensors
from server.push.scheduler import THRESHOLD_K, Delivery, PushScheduler
from server.push.watcher import CommitWatcher

__all__ = ["THRESHOLD_K", "CommitWatcher", "Delivery", "PushScheduler", "build_for",
           "thermal_sensors"]
