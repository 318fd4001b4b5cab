"""The EDNC wire protocol: a sans-I/O codec shared by the center and the machines.

No sockets, no event loop: ``Connection`` turns bytes into messages and messages into
bytes, and enforces the state machine of ``state.py``. README.md in this folder is the
specification a PLC programmer implements the machine side from.
"""

from .auth import compute_mac, new_nonce, verify_mac
from .codes import Controller, ErrorCode, MapEncoding, MapRejectReason, MessageType
from .connection import CONNECTION_CLOSED, NEED_DATA, Connection, Sentinel
from .errors import LocalProtocolError, ProtocolError, RemoteProtocolError
from .mapformat import (
    ErrorMapPayload,
    GridAxis,
    MapFormatError,
    OutputAxis,
    decode_map,
    encode_map,
    pack_values,
)
from .maptransfer import MapAccepted, MapAssembler, MapRejected, split_into_chunks
from .messages import (
    AuthResponse,
    AxisReading,
    Challenge,
    Error,
    Heartbeat,
    HeartbeatReply,
    Hello,
    MapAck,
    MapBegin,
    MapChunk,
    MapEnd,
    MapReject,
    Message,
    Reject,
    ReleaseCompensation,
    Released,
    SensorReading,
    Telemetry,
    TemperatureReading,
    Temperatures,
    Welcome,
    clip_text,
)
from .state import Channel, Role, State

__all__ = [
    "CONNECTION_CLOSED",
    "NEED_DATA",
    "AuthResponse",
    "AxisReading",
    "Challenge",
    "Channel",
    "Connection",
    "Controller",
    "Error",
    "ErrorCode",
    "ErrorMapPayload",
    "GridAxis",
    "Heartbeat",
    "HeartbeatReply",
    "Hello",
    "LocalProtocolError",
    "MapAccepted",
    "MapAck",
    "MapAssembler",
    "MapBegin",
    "MapChunk",
    "MapEncoding",
    "MapEnd",
    "MapFormatError",
    "MapReject",
    "MapRejectReason",
    "MapRejected",
    "Message",
    "MessageType",
    "OutputAxis",
    "ProtocolError",
    "Reject",
    "ReleaseCompensation",
    "Released",
    "RemoteProtocolError",
    "Role",
    "SensorReading",
    "Sentinel",
    "State",
    "Telemetry",
    "TemperatureReading",
    "Temperatures",
    "Welcome",
    "clip_text",
    "compute_mac",
    "decode_map",
    "encode_map",
    "new_nonce",
    "pack_values",
    "split_into_chunks",
    "verify_mac",
]
