"""``/metrics``: Prometheus text exposition of the app's own registry."""

from __future__ import annotations

from fastapi import APIRouter, Response

from server.api.deps import CenterDep
from server.dashboard.routes import refresh_machine_metrics
from server.metrics import CONTENT_TYPE_LATEST

router = APIRouter(tags=["metrics"])


@router.get("/metrics", response_class=Response,
            responses={200: {"content": {"text/plain": {"schema": {"type": "string"}}}}})
async def metrics(center: CenterDep) -> Response:
    """Connected machines, pushes, push latency, refusals, events, and per machine its
    accuracy state, map, telemetry and thermal ages, residual and rejects."""
    await refresh_machine_metrics(center)
    return Response(center.metrics.exposition(), media_type=CONTENT_TYPE_LATEST)
