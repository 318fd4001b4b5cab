"""``/api/opcua/certificate``: the center's OPC UA application certificate, for the
controllers' trust lists (:mod:`server.links.opcuapki`)."""

from __future__ import annotations

import asyncio

from cryptography.hazmat.primitives import serialization
from fastapi import APIRouter, HTTPException
from pydantic import BaseModel, Field

from server.links.opcuapki import CENTER_URI, pki_at, sha256_fingerprint
from server.links.window.memory import LinkError

router = APIRouter(prefix="/opcua", tags=["opcua"])


class CertificatePublic(BaseModel):
    """The center's certificate as an operator checks it before trusting it."""

    thumbprint: str = Field(description="SHA-1 of the DER bytes, hex: what a SINUMERIK's "
                                        "certificate dialog shows")
    sha256: str = Field(description="SHA-256 fingerprint, AB:CD:...")
    application_uri: str
    subject: str
    not_after: str = Field(description="end of validity, ISO 8601 UTC")
    path: str = Field(description="the DER file on the center, to copy to the controller")
    pem: str = Field(description="the certificate, PEM")


@router.get("/certificate")
async def center_certificate() -> CertificatePublic:
    """The center's OPC UA certificate (made on first use: the OPC UA links use it)."""
    try:
        identity = await asyncio.to_thread(pki_at().identity)
    except LinkError as exc:
        raise HTTPException(status_code=503, detail=str(exc)) from None
    cert = identity.certificate
    return CertificatePublic(
        thumbprint=identity.thumbprint, sha256=sha256_fingerprint(identity.der),
        application_uri=CENTER_URI, subject=cert.subject.rfc4514_string(),
        not_after=cert.not_valid_after_utc.isoformat(), path=str(identity.path),
        pem=cert.public_bytes(serialization.Encoding.PEM).decode("ascii"))
