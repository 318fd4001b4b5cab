"""The PLC program's side of a map in controller memory (protocol/README.md §13).

A controller reached through its own server (Modbus/TCP into a Fanuc PMC, OPC UA into a
SINUMERIK PLC) holds a window of memory the center writes and the PLC program reads.
:class:`PlcMapProgram` is that program's map handling, run once per scan beside the
ladder or IPO cycle it feeds:

* at start-up (:meth:`boot`) it declares itself in the identity block and, after a
  restart, takes the buffer its status names as active again, if that buffer still
  passes its header and CRC checks (else it applies nothing until the center switches);
* each scan it reads the switch word; a new sequence makes it copy the named buffer out
  of the window, check header, length and CRC-32 over its copy
  (:func:`protocol.ctrlmem.check_buffer`), and hand the payload to the controller's map
  store, which applies it with the same checks, evaluation and ramp rules as a map pushed
  over the EDNC protocol; then it writes its verdict (ack sequence and code) and, when
  applied, the active buffer;
* it takes new temperature slots (a sequence not 0 and not the one last taken, stamped
  with the applied map's version or 0, read again after the slots) into the controller's
  held readings, named by the map's thermal records: a slot of -2^31 leaves its sensor's
  held reading, a value the controller's screen refuses too (bit i of ``temp_refused``);
  at a swap it keeps the held readings and forgets the sequence it last took, so the
  slots written for the new map are taken as soon as their stamp matches;
* it writes its status: heartbeat, the state bits of §13.1 (map in use, ramping,
  releasing, alarm, clamped, expired), applied map version, the temperature sequence
  taken and what was refused of it, positions and corrections.

The window is a ``bytearray`` shared with the controller's server (it is the memory the
server maps its registers or nodes onto); nothing here does I/O.
"""

from __future__ import annotations

import math
import struct

import numpy as np
from numpy.typing import NDArray

from protocol import MapAck, MapEncoding, decode_payload, split_into_chunks
from protocol.ctrlmem import (
    IDENTITY_SIZE,
    NO_TEMPERATURE,
    STATUS_AT,
    STATUS_SIZE,
    SWITCH_AT,
    TEMP_SEQ_AT,
    AckCode,
    Identity,
    Layout,
    State,
    Status,
    check_buffer,
    decode_command,
    decode_status,
    encode_identity,
    encode_status,
    sensor_slots,
    unpack_switch,
)
from protocol.mapformat import MapFormatError

from .controller import Compensator

__all__ = ["PlcMapProgram"]

_MAP_IN_USE = int(State.MAP_IN_USE)
_RAMPING = int(State.RAMPING)
_RELEASING = int(State.RELEASING)
_ALARM = int(State.ALARM)
_EXPIRED = int(State.EXPIRED)
_R_STATUS_KEPT = int(State.RAMPING | State.ALARM | State.CLAMPED | State.EXPIRED)
"""The bits a Fanuc-style ladder's R status byte gives the status word (of its low 6)."""


class PlcMapProgram:
    """Map handling of a PLC program over a controller-memory window.

    Parameters
    ----------
    window : bytearray
        The window (``layout.size`` bytes), shared with the controller's server.
    layout : Layout
    controller : Compensator
        The controller whose map store and temperatures the program feeds.
    formats : MapEncoding
        The map kinds the controller evaluates (declared in the identity block).
    increment_mm : float
        Unit of the positions and corrections in the status, mm per count.
    """

    def __init__(self, window: bytearray, layout: Layout, controller: Compensator, *,
                 formats: MapEncoding, increment_mm: float = 0.001) -> None:
        if len(window) < layout.size:
            raise ValueError(f"window of {len(window)} bytes, the layout needs {layout.size}")
        self.window = window
        self.layout = layout
        self.controller = controller
        self.formats = formats
        self.increment_mm = float(increment_mm)
        self.heartbeat = 0
        self._handled_seq = 0
        self._temp_seq: int | None = None
        """The temperature sequence last taken for the map in use (None: forgotten)."""
        self._temp_ack = 0
        self._temp_refused = 0
        self._slots: dict[int, str] = {}
        self.applied_switches = 0
        self.rejected_switches = 0

    # -- start-up
    def boot(self, now_s: float, name: str) -> None:
        """The PLC program starts (power-on or restart): declare the identity, and take the
        active buffer again if it still checks out (status in nonvolatile memory)."""
        ident = Identity(self.formats, self.layout.capacity, len(self.controller.axes),
                         round(self.increment_mm * 1e6), name)
        self.window[:IDENTITY_SIZE] = encode_identity(ident)
        st = decode_status(self.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
        self._handled_seq = st.ack_seq
        self._temp_seq = None  # no held readings yet: take the slots the window holds
        self._temp_ack = self._temp_refused = 0  # nothing taken since the start
        if st.active:
            checked = check_buffer(self.window, self.layout, st.active)
            applied = False
            if isinstance(checked[0], bytes):
                applied = self._apply(checked[0], checked[1].map_version, now_s)[0] == 0
            if not applied:  # the active buffer no longer checks out: apply nothing
                self._write_status(active=0)
                return
        self._write_status(active=st.active)

    # -- per scan
    def scan(self, now_s: float, positions: NDArray[np.float64],
             applied_mm: NDArray[np.float64]) -> None:
        """One scan: a new switch, new temperatures, then the status."""
        (word,) = struct.unpack_from("<H", self.window, SWITCH_AT)
        seq, buffer = unpack_switch(word)
        st = decode_status(self.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
        active, ack_code = st.active, st.ack_code
        if seq != 0 and seq != self._handled_seq:
            self._handled_seq = seq
            checked = check_buffer(self.window, self.layout, buffer)
            if isinstance(checked[0], bytes):
                code, _why = self._apply(checked[0], checked[1].map_version, now_s)
            else:
                code = int(checked[0])
            ack_code = code
            if code == 0:
                active = buffer
                self.applied_switches += 1
            else:
                self.rejected_switches += 1
        self._take_temperatures(now_s)
        self.heartbeat = (self.heartbeat + 1) & 0xFFFFFFFF
        self._write_status(active=active, ack_code=ack_code, positions=positions,
                           applied_mm=applied_mm, old=st)

    def _apply(self, payload: bytes, version: int, now_s: float) -> tuple[int, str]:
        """Hand a checked payload to the map store (its own checks and swap rule)."""
        reply = None
        for msg in split_into_chunks(payload, version):
            reply = self.controller.feed_map(msg, now_s)
        if isinstance(reply, MapAck):
            # the records of the map just applied, as the store decoded them from these
            # bytes (decoding them again here cost as much as the rest of a push)
            decoded = self.controller.store.applied_payload
            if decoded is not None:
                records = decoded.thermal
            else:
                try:
                    records = decode_payload(payload).thermal
                except MapFormatError:  # cannot happen: the store decoded it already
                    records = ()
            slots = sensor_slots([r.sensor for r in records])
            self._slots = {i: s for s, i in slots.items()}
            self._temp_seq = None  # read the slots again for the new map's sensors
            self._temp_ack = 0  # none taken for this map yet (§13.1)
            return 0, ""
        if reply is None:
            return int(AckCode.BAD_HEADER), "no verdict"
        return int(reply.reason), reply.text

    def _take_temperatures(self, now_s: float) -> None:
        """§13.1: take the slots when their sequence is new (not 0, not the one last
        taken), they follow the applied map's sensor order (stamp 0 or its version), and
        the sequence reads the same after them."""
        # the sequence alone first: most scans find nothing new (the slots are read below)
        (seq,) = struct.unpack_from("<H", self.window, TEMP_SEQ_AT)
        if seq == 0 or seq == self._temp_seq:
            return
        cmd = decode_command(self.window)
        seq = cmd.temp_seq
        if cmd.slots_version not in (0, self.controller.store.version):
            return  # written for another map: its slot order is another
        (again,) = struct.unpack_from("<H", self.window, TEMP_SEQ_AT)
        if again != seq:
            return  # written while read: take it next scan
        self._temp_seq = self._temp_ack = seq
        store = self.controller.temperatures
        refused = 0
        for i, sensor in self._slots.items():
            value = cmd.slots[i]
            if value == NO_TEMPERATURE:
                continue  # nothing to say: the held reading stays
            if not store.update(sensor, value / 1000.0, now_s, "center"):
                refused |= 1 << i  # the screen refused it: the held reading stays
        self._temp_refused = refused

    def _write_status(self, *, active: int, ack_code: int | None = None,
                      positions: NDArray[np.float64] | None = None,
                      applied_mm: NDArray[np.float64] | None = None,
                      old: Status | None = None) -> None:
        """The status block; ``old``: the block as this scan read it (unchanged since:
        the center writes only between scans), else it is read here."""
        if old is None:
            old = decode_status(self.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
        c = self.controller
        state = self._state_bits()
        # counts as the position registers hold them, halves up (§6), one value at a time
        # (the same division, add and floor as the array form, without its call overhead)
        inc = self.increment_mm
        pos = old.positions if positions is None else tuple(
            math.floor(v / inc + 0.5) for v in positions.tolist())
        app = old.applied if applied_mm is None else tuple(
            math.floor(v / inc + 0.5) for v in applied_mm.tolist())
        st = Status(self.heartbeat, self._handled_seq,
                    old.ack_code if ack_code is None else ack_code, active, state,
                    c.store.version, self._temp_ack, pos, app, self._temp_refused)
        self.window[STATUS_AT:STATUS_AT + STATUS_SIZE] = encode_status(st)

    def _state_bits(self) -> int:
        """The status state word (§13.1): a Fanuc-style ladder keeps exactly these bits
        in its R status byte; otherwise they come from the controller's state."""
        # plain ints: IntFlag's operators cost microseconds a scan, the bits are the same
        c = self.controller
        state = 0
        if c.store.active is not None:  # as of this scan's swap, not the ladder's last
            state |= _MAP_IN_USE
        if c.releasing:
            state |= _RELEASING
        r_status = getattr(c, "status", None)
        if isinstance(r_status, int):
            return state | (r_status & _R_STATUS_KEPT)
        label = getattr(c, "state", "")
        if label == "ramping":
            state |= _RAMPING
        if label == "alarm":
            state |= _ALARM
        events = c.store.events
        if c.store.active is None and events and events[-1].kind == "expired":
            state |= _EXPIRED
        return state
