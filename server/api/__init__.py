"""The REST API: one router per resource in :mod:`server.api.routes`, assembled in
:mod:`server.api.main`."""
