"""Dependencies of the REST routes, as ``Annotated`` aliases.

Reads are open; a route that changes data lists ``WriteAccess`` in its ``dependencies``,
which wants the service's API key in the ``X-API-Key`` header (401 without it or when it is
wrong; 403 when the service has no key configured and is therefore read-only).
"""

from __future__ import annotations

import secrets
from typing import Annotated

from fastapi import Depends, HTTPException, Path, Request, Security, status
from fastapi.security import APIKeyHeader

from server.center import Center
from server.db import Database
from server.db import machines as machine_repo
from server.db.tables import MachineRow
from server.schemas.common import NAME_PATTERN
from server.state import Registry

INT32_MAX = 2**31 - 1  # ids and versions are 32-bit integer columns


def get_center(request: Request) -> Center:
    """The :class:`Center` the lifespan stored on the app."""
    center = getattr(request.app.state, "center", None)
    if not isinstance(center, Center):
        raise RuntimeError("no Center on app.state: the app's lifespan has not run")
    return center


CenterDep = Annotated[Center, Depends(get_center)]


def get_database(center: CenterDep) -> Database:
    return center.db


def get_registry(center: CenterDep) -> Registry:
    return center.registry


DatabaseDep = Annotated[Database, Depends(get_database)]
RegistryDep = Annotated[Registry, Depends(get_registry)]

api_key_header = APIKeyHeader(
    name="X-API-Key",
    auto_error=False,
    description="The service's API key (EDNC_API_KEY); needed by every request that writes.",
)


def require_api_key(
    center: CenterDep, key: Annotated[str | None, Security(api_key_header)]
) -> None:
    """Let the request through only with the right API key."""
    expected = center.settings.api_key
    if expected is None:
        raise HTTPException(
            status.HTTP_403_FORBIDDEN,
            "writes are disabled: the service has no API key (set EDNC_API_KEY)",
        )
    if key is None:
        raise HTTPException(
            status.HTTP_401_UNAUTHORIZED,
            "this request changes data: send the API key in the X-API-Key header",
            headers={"WWW-Authenticate": "APIKey"},
        )
    # Constant-time comparison, on bytes: compare_digest refuses non-ASCII str.
    if not secrets.compare_digest(key.encode(), expected.get_secret_value().encode()):
        raise HTTPException(
            status.HTTP_401_UNAUTHORIZED, "wrong API key",
            headers={"WWW-Authenticate": "APIKey"},
        )


WriteAccess = Depends(require_api_key)

MachineName = Annotated[
    str, Path(pattern=NAME_PATTERN, description="The machine's name.", examples=["vmc-01"])
]
Version = Annotated[int, Path(ge=1, le=INT32_MAX, description="Version number (from 1).")]
ReportId = Annotated[int, Path(ge=1, le=INT32_MAX)]


async def get_machine_row(db: DatabaseDep, name: MachineName) -> MachineRow:
    """The machine named in the path, or 404."""
    row = await db.run(machine_repo.get_machine, name)
    if row is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no machine named {name!r}")
    return row


MachineDep = Annotated[MachineRow, Depends(get_machine_row)]
