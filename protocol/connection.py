"""``Connection``: the sans-I/O endpoint. Bytes in, messages out; messages in, bytes out.

    conn = Connection(Role.MACHINE)
    sock.sendall(conn.send(Hello(...)))
    conn.receive_data(sock.recv(65536))        # b"" when the peer closed
    while (event := conn.next_event()) is not NEED_DATA:
        match event:
            case Challenge(nonce=n): ...
            case Sentinel.CONNECTION_CLOSED: ...

No I/O, no clocks, no threads: the caller owns the socket and the timers (limits.py).
"""

from __future__ import annotations

from enum import Enum
from typing import Final

from .codec import decode_payload, encode_payload
from .codes import ErrorCode
from .errors import LocalProtocolError, RemoteProtocolError
from .frames import FrameBuffer, encode_frame
from .messages import TYPE_OF, Error, Message, clip_text
from .state import Channel, ConnectionState, Role, State

_SEQ_MOD: Final = 1 << 32


class Sentinel(Enum):
    """What ``next_event`` returns when it has no message."""

    NEED_DATA = "NEED_DATA"
    """No whole frame buffered: call ``receive_data`` with more bytes first."""
    CONNECTION_CLOSED = "CONNECTION_CLOSED"
    """The peer closed the stream (``receive_data(b"")``) at a frame boundary."""


NEED_DATA: Final = Sentinel.NEED_DATA
CONNECTION_CLOSED: Final = Sentinel.CONNECTION_CLOSED


class Connection:
    """One end of one EDNC connection, playing ``our_role``.

    Sequence numbers are assigned by ``send`` and checked by ``next_event``: each
    direction starts at 0 and counts up by one (mod 2**32); a gap or a repeat from the
    peer is a RemoteProtocolError. After a RemoteProtocolError the connection stays
    broken: ``next_event`` raises the same error again and ``send`` accepts only an
    ``Error`` for the peer before the caller closes the socket.
    """

    __slots__ = ("_broken", "_buffer", "_eof", "_recv_seq", "_send_seq", "_state",
                 "our_role")

    def __init__(self, our_role: Role) -> None:
        self.our_role: Final = our_role
        self._state = ConnectionState()
        self._buffer = FrameBuffer()
        self._send_seq = 0
        self._recv_seq = 0
        self._eof = False
        self._broken: RemoteProtocolError | None = None

    @property
    def their_role(self) -> Role:
        """The peer's role."""
        return self.our_role.peer

    @property
    def states(self) -> dict[Channel, State]:
        """A copy of each channel's current state."""
        return dict(self._state.states)

    @property
    def session(self) -> State:
        """The SESSION channel's state (READY once Welcome passed, CLOSED after Error)."""
        return self._state.states[Channel.SESSION]

    def send(self, msg: Message) -> bytes:
        """Frame ``msg`` with the next sequence number and return the bytes to write.

        Raises
        ------
        LocalProtocolError
            The message is not allowed for our role in the current state; nothing changes.
        """
        if TYPE_OF.get(type(msg)) is None:
            raise LocalProtocolError(f"{type(msg).__name__} is not a protocol message")
        if self._broken is not None and not isinstance(msg, Error):
            raise LocalProtocolError(f"cannot send {type(msg).__name__}: the peer broke the "
                                     f"protocol ({self._broken}); only Error may follow")
        channel, new = self._state.check(self.our_role, msg, local=True)
        data = encode_frame(TYPE_OF[type(msg)], self._send_seq, encode_payload(msg))
        self._state.states[channel] = new
        self._send_seq = (self._send_seq + 1) % _SEQ_MOD
        return data

    def send_error(self, code: ErrorCode, text: str) -> bytes:
        """An Error frame closing the session, or ``b""`` if it is already closed.

        For the usual ending after a RemoteProtocolError or a timeout:
        ``sock.sendall(conn.send_error(ErrorCode.PROTOCOL_ERROR, str(exc)))``, then close.
        ``text`` is clipped to fit the message.
        """
        if self.session is State.CLOSED:
            return b""
        return self.send(Error(code, clip_text(text)))

    def receive_data(self, data: bytes) -> None:
        """Hand over bytes read from the socket; ``b""`` means the peer closed it."""
        if self._eof:
            raise LocalProtocolError("receive_data called after the end of the stream")
        if data:
            self._buffer.feed(data)
        else:
            self._eof = True

    def next_event(self) -> Message | Sentinel:
        """The next message from the peer, ``NEED_DATA`` or ``CONNECTION_CLOSED``.

        Raises
        ------
        RemoteProtocolError
            The peer sent a bad frame, a bad field, a message out of turn (the text names
            the rule), a wrong sequence number, or closed the stream inside a frame.
        """
        if self._broken is not None:
            raise self._broken
        try:
            return self._next()
        except RemoteProtocolError as exc:
            self._broken = exc
            raise

    def _next(self) -> Message | Sentinel:
        frame = self._buffer.next_frame()
        if frame is None:
            if not self._eof:
                return NEED_DATA
            if self._buffer.pending:
                raise RemoteProtocolError(f"stream closed inside a frame "
                                          f"({self._buffer.pending} bytes of it received)")
            return CONNECTION_CLOSED
        if frame.seq != self._recv_seq:
            kind = "repeats" if frame.seq < self._recv_seq else "skips ahead of"
            raise RemoteProtocolError(f"{frame.kind.name} frame has sequence number "
                                      f"{frame.seq}, which {kind} the expected "
                                      f"{self._recv_seq}")
        msg = decode_payload(frame.kind, frame.payload)
        self._state.process(self.their_role, msg, local=False)
        self._recv_seq = (self._recv_seq + 1) % _SEQ_MOD
        return msg
