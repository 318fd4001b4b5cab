"""``/api/machines/{name}/measurements``: measurement CSVs (formats.md §2), stored raw."""

from __future__ import annotations

import asyncio
import logging
import re
from pathlib import PurePath
from typing import Annotated, Any

from fastapi import APIRouter, HTTPException, Path, Query, Request, Response, status
from starlette.datastructures import UploadFile

from server.api.deps import DatabaseDep, MachineDep, WriteAccess
from server.api.errors import NOT_FOUND, WRITE, unprocessable
from server.db import Database, DuplicateError
from server.db import measurements as measurement_repo
from server.db.tables import MachineRow, MeasurementSetRow
from server.numeric import MeasurementError, measurement_check
from server.schemas.common import NAME_PATTERN
from server.schemas.measurement import MeasurementSetPublic
from volumetric.plausible.files import decode_text

log = logging.getLogger(__name__)

router = APIRouter(
    prefix="/machines/{name}/measurements", tags=["measurements"], responses=NOT_FOUND
)

# The public data sets run to a few MB; 64 MB leaves room for long campaigns while
# keeping one upload from filling the server's memory.
MAX_UPLOAD_BYTES = 64 * 1024 * 1024
SetName = Annotated[str, Path(pattern=NAME_PATTERN, description="Name of the set.")]

_UPLOAD_BODY: dict[str, Any] = {
    "requestBody": {
        "required": True,
        "content": {
            "text/csv": {"schema": {"type": "string"}},
            "multipart/form-data": {
                "schema": {
                    "type": "object",
                    "required": ["file"],
                    "properties": {"file": {"type": "string", "format": "binary"}},
                }
            },
        },
    }
}


def _unprocessable(message: str) -> HTTPException:
    return unprocessable(["body"], message, "measurement_format")


def set_public(row: MeasurementSetRow, machine: str) -> MeasurementSetPublic:
    return MeasurementSetPublic(
        machine=machine, name=row.name, row_count=row.row_count,
        size_bytes=row.size_bytes, created_at=row.created_at,
    )


async def _read_upload(request: Request) -> tuple[bytes, str | None]:
    """The uploaded bytes and, for a multipart upload, the file's name."""
    length = request.headers.get("content-length", "")
    if length.isdigit() and int(length) > MAX_UPLOAD_BYTES:
        raise HTTPException(status.HTTP_413_CONTENT_TOO_LARGE,
                            f"upload larger than {MAX_UPLOAD_BYTES} bytes")
    media = request.headers.get("content-type", "").split(";")[0].strip().lower()
    if media == "multipart/form-data":
        # The context manager closes the spooled temporary file of the upload.
        async with request.form(max_files=1, max_fields=10) as form:
            upload = form.get("file")
            if not isinstance(upload, UploadFile):
                raise _unprocessable("multipart upload needs the CSV as a file field "
                                     "named 'file'")
            return await upload.read(MAX_UPLOAD_BYTES + 1), upload.filename
    if media in ("text/csv", "text/plain", "application/octet-stream"):
        return await request.body(), None
    raise HTTPException(
        status.HTTP_415_UNSUPPORTED_MEDIA_TYPE,
        f"send the CSV as text/csv or as a multipart/form-data file, not {media or 'no type'!r}",
    )


def _decode(data: bytes, source: str) -> str:
    if len(data) > MAX_UPLOAD_BYTES:
        raise HTTPException(status.HTTP_413_CONTENT_TOO_LARGE,
                            f"upload larger than {MAX_UPLOAD_BYTES} bytes")
    try:  # UTF-8, or UTF-16 with its mark (as the offline reader takes it)
        text = decode_text(data, source)
    except ValueError as exc:
        raise _unprocessable(str(exc)) from None
    if "\x00" in text:
        raise _unprocessable(f"{source}: contains NUL characters; is it a binary file?")
    return text


@router.post(
    "", status_code=status.HTTP_201_CREATED, dependencies=[WriteAccess],
    openapi_extra=_UPLOAD_BODY,
    responses={**WRITE, 409: {"description": "The machine already has a set of that name."},
               413: {"description": "Upload too large."},
               415: {"description": "Neither text/csv nor multipart/form-data."}},
)
async def upload_measurements(
    request: Request, db: DatabaseDep, machine: MachineDep,
    set_name: Annotated[str | None, Query(pattern=NAME_PATTERN,
                                          description="Name of the set; default: the file "
                                          "name, else set-<n>.")] = None,
) -> MeasurementSetPublic:
    """Store a measurement CSV after the numeric core has read it without error.

    Send it as the body (``Content-Type: text/csv``) or as a multipart file field ``file``.
    A CSV the core refuses gets 422 with the core's message (line and column).
    """
    data, filename = await _read_upload(request)
    stem = PurePath(filename).stem if filename else ""
    source = filename or set_name or "upload.csv"
    text = _decode(data, source)
    try:
        rows, warnings = await asyncio.to_thread(measurement_check, text, source,
                                                 machine.description)
    except MeasurementError as exc:
        raise _unprocessable(str(exc)) from None
    name = set_name
    if name is None:
        if re.match(NAME_PATTERN, stem):
            name = stem
        else:
            name = f"set-{await db.run(measurement_repo.count_measurement_sets, machine.id) + 1}"
    try:
        row = await db.run(measurement_repo.add_measurement_set, machine.id, name=name,
                           csv_text=text, row_count=rows)
    except DuplicateError as exc:
        raise HTTPException(status.HTTP_409_CONFLICT, str(exc)) from None
    for w in warnings:
        log.warning("measurements of %s: %s", machine.name, w)
    return set_public(row, machine.name).model_copy(update={"warnings": warnings})


@router.get("")
async def list_measurements(db: DatabaseDep, machine: MachineDep) -> list[MeasurementSetPublic]:
    """The machine's measurement sets, newest first."""
    rows = await db.run(measurement_repo.list_measurement_sets, machine.id)
    return [set_public(r, machine.name) for r in rows]


async def _get_set(
    db: Database, machine: MachineRow, set_name: str, *, with_text: bool
) -> MeasurementSetRow:
    row = await db.run(measurement_repo.get_measurement_set, machine.id, set_name,
                       with_text=with_text)
    if row is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND,
                            f"machine {machine.name!r} has no measurement set {set_name!r}")
    return row


@router.get("/{set_name}")
async def get_measurements(
    db: DatabaseDep, machine: MachineDep, set_name: SetName
) -> MeasurementSetPublic:
    """One measurement set's metadata."""
    return set_public(await _get_set(db, machine, set_name, with_text=False), machine.name)


@router.get("/{set_name}/csv", response_class=Response,
            responses={200: {"content": {"text/csv": {"schema": {"type": "string"}}}}})
async def download_measurements(
    db: DatabaseDep, machine: MachineDep, set_name: SetName
) -> Response:
    """The measurement CSV as uploaded."""
    row = await _get_set(db, machine, set_name, with_text=True)
    return Response(
        row.csv_text, media_type="text/csv; charset=utf-8",
        headers={"Content-Disposition": f'attachment; filename="{machine.name}-{row.name}.csv"'},
    )
