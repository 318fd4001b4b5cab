"""The live dashboard: the control room's view of every machine.

Pages (``/``, ``/dashboard``, ``/machines/{name}``) are static HTML, CSS and JavaScript from
``server/static`` (no framework, nothing loaded from elsewhere); they read the JSON
endpoints of :mod:`server.dashboard.routes` and the server-sent event stream ``/api/live``
(:mod:`server.dashboard.live`), which carries a whole :class:`DashboardSnapshot` at connect
and after every change.

Modules: ``schemas`` (what the pages read), ``telemetry`` (a link's telemetry made uniform),
``snapshot`` (database + registry → snapshot), ``live`` (the shared once-a-second
producer and its SSE encoding), ``mapgrid``, ``diagonals`` and ``modelview`` (pure views
of a map, a verification and a model for the plots), ``routes`` (the HTTP surface).
"""

from server.dashboard.schemas import DashboardSnapshot

__all__ = ["DashboardSnapshot"]
