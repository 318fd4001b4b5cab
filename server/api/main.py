"""All API routers under ``/api`` (``/metrics`` stays at the root, where scrapers look)."""

from __future__ import annotations

from fastapi import APIRouter

from server.api.routes import (
    diagnoses,
    events,
    history,
    machines,
    maps,
    measurements,
    metrics,
    models,
    opcua,
    status,
    temperatures,
    verifications,
)
from server.dashboard import routes as dashboard

api_router = APIRouter(prefix="/api")
for module in (machines, status, models, measurements, maps, diagnoses, verifications, events,
               temperatures, history, opcua):
    api_router.include_router(module.router)
api_router.include_router(dashboard.api)

root_router = APIRouter()
root_router.include_router(metrics.router)
root_router.include_router(dashboard.pages)
