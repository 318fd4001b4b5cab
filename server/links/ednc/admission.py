"""What an unauthenticated peer may cost the center, and no more.

The machine port faces the plant network. Before a peer has proved it holds a machine's
secret it gets, in order:

1. :class:`AddressBook`: admission at accept. Every machine is registered at one address;
   a connection from any other address is closed before it takes a handshake slot, a
   buffer or a database row (counted, logged at most once a minute per address). An
   address is one EDNC machine's, or shared by machines reached through a link (a
   gateway's; :mod:`server.db.machines`): those are admitted too, so a controller
   registered with a link that dials in anyway is told why it is refused.
2. :class:`HandshakeSlots`: a bounded number of handshakes in progress, per address and
   in total. When all are taken, a newcomer from an address without a handshake takes the
   slot of the oldest handshake that is waiting for its peer (a holder that sent nothing,
   or a Hello and no AuthResponse): a real machine answers within milliseconds, so it is
   never the oldest waiter, and a registered machine always gets in however many peers
   hold connections open.
3. :class:`LoginThrottle`: failed logins per address and per machine name delay the next
   attempt exponentially; a throttled attempt is refused AUTH_FAILED without looking at
   its answer, so guessing gains nothing from speed.
4. :class:`RefusalLog`: refusals are stored as at most one event row per peer per minute
   with a count, so a flood of refused connections cannot grow the database.

Everything here is in memory, bounded in entries, and costs O(1) per connection.
"""

from __future__ import annotations

import asyncio
import contextlib
import hashlib
import logging
import time
from collections import OrderedDict
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from typing import Any, Final

from sqlalchemy import event, inspect, select
from sqlalchemy.orm import Session

from server.db import Database
from server.db.secretbox import SecretKeyError
from server.db.tables import MachineRow

log = logging.getLogger(__name__)

MAX_TRACKED: Final = 65536
"""Entries kept per table (addresses, names): beyond it the least recently used goes. A
peer could otherwise grow the tables with every address of an IPv6 /64."""


def digest(secret: str) -> bytes:
    """What a session remembers of the secret it logged in with, to tell a change."""
    return hashlib.sha256(secret.encode("utf-8")).digest()


class AddressBook:
    """The addresses machines are registered at, read from the database.

    Refreshed from the database at start, after every committed transaction on this
    process that adds, changes or deletes a machine (:meth:`watch`), and every
    ``refresh_s`` (another node may register machines on a shared database).
    """

    def __init__(self, db: Database, *, refresh_s: float = 30.0) -> None:
        self.db = db
        self.refresh_s = refresh_s
        self._addresses: frozenset[str] = frozenset()
        self._digests: dict[int, bytes] = {}
        self._added_meanwhile: set[str] = set()
        self._changed_secrets: set[int] = set()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._dirty = asyncio.Event()
        self._on_secret_change: Callable[[set[int]], None] | None = None

    def admits(self, ip: str) -> bool:
        """Whether a machine is registered at ``ip`` (canonical form, see ``peer_ip``)."""
        return ip in self._addresses

    def _load(self) -> tuple[frozenset[str], dict[int, bytes]]:
        """The registered addresses, and a digest of each machine's secret (opened: a
        secret sealed again with a new nonce, or sealed for the first time, is the same
        secret)."""
        digests: dict[int, bytes] = {}
        with self.db.session() as session:
            rows = session.execute(select(MachineRow.id, MachineRow.ip, MachineRow.secret))
            ips = set()
            for machine_id, ip, stored in rows:
                ips.add(ip)
                try:
                    secret = self.db.secrets.open(stored, machine_id)
                except SecretKeyError:
                    continue  # the login will say so; nothing to compare
                digests[machine_id] = digest(secret)
        return frozenset(ips), digests

    def digest(self, machine_id: int) -> bytes | None:
        """The digest of the machine's current secret (:func:`digest`), if known."""
        return self._digests.get(machine_id)

    async def refresh(self) -> None:
        """Re-read the book; report machines whose secret changed since the last read
        (changed through another node: this node's own commits are reported at once)."""
        # addresses added while the read runs may be missing from it: keep them too
        self._added_meanwhile = set()
        loaded, digests = await asyncio.to_thread(self._load)
        self._addresses = loaded | self._added_meanwhile
        changed = {i for i, d in digests.items()
                   if i in self._digests and self._digests[i] != d}
        self._digests = digests
        if changed and self._on_secret_change is not None:
            self._on_secret_change(changed)

    # -- change notifications (SQLAlchemy session events, on worker threads)
    _KEY: Final = "ednc.admission.changed"

    def _after_flush(self, session: Session, _context: Any) -> None:
        if session.bind is not self.db.engine:
            return
        info = session.info.setdefault(self._KEY, {"machines": False, "secrets": {},
                                                    "ips": set()})
        for obj in (*session.new, *session.dirty, *session.deleted):
            if isinstance(obj, MachineRow):
                info["machines"] = True
                if obj not in session.deleted:
                    info["ips"].add(obj.ip)
                if obj in session.dirty and inspect(obj).attrs.secret.history.has_changes():
                    with contextlib.suppress(SecretKeyError):
                        info["secrets"][obj.id] = digest(self.db.secrets.open(obj.secret,
                                                                              obj.id))

    def _after_commit(self, session: Session) -> None:
        info = session.info.pop(self._KEY, None)
        if info and self._loop is not None:
            with contextlib.suppress(RuntimeError):  # loop closed: nobody left to tell
                # scheduled before the committing caller's own wake-up (asyncio.to_thread
                # resolves its future the same way, later): a machine registered and
                # connecting at once finds its address already admitted
                self._loop.call_soon_threadsafe(self._changed, info["machines"],
                                                dict(info["secrets"]), set(info["ips"]))

    def _after_soft_rollback(self, session: Session, _previous: Any) -> None:
        session.info.pop(self._KEY, None)

    def _after_bulk(self, update_context: Any) -> None:
        # ``delete(MachineRow)`` statements bypass the flush; refresh on them too
        if update_context.session.bind is self.db.engine and self._loop is not None:
            with contextlib.suppress(RuntimeError):
                self._loop.call_soon_threadsafe(self._changed, True, {}, set())

    def _changed(self, machines: bool, secrets: dict[int, bytes], ips: set[str]) -> None:
        if ips:
            self._addresses |= ips  # at once; removals wait for the refresh
            self._added_meanwhile |= ips
        if machines:
            self._dirty.set()
        self._digests.update(secrets)
        if secrets and self._on_secret_change is not None:
            self._on_secret_change(set(secrets))

    async def run(self, on_secret_change: Callable[[set[int]], None]) -> None:
        """Keep the book current until cancelled; report machines whose secret changed."""
        self._loop = asyncio.get_running_loop()
        self._on_secret_change = on_secret_change
        listeners: list[tuple[Any, str, Callable[..., None]]] = [
            (Session, "after_flush", self._after_flush),
            (Session, "after_commit", self._after_commit),
            (Session, "after_soft_rollback", self._after_soft_rollback),
            (Session, "after_bulk_delete", self._after_bulk),
            (Session, "after_bulk_update", self._after_bulk),
        ]
        for target, name, fn in listeners:
            event.listen(target, name, fn)
        try:
            await self.refresh()
            while True:
                with contextlib.suppress(TimeoutError):
                    async with asyncio.timeout(self.refresh_s):
                        await self._dirty.wait()
                self._dirty.clear()
                try:
                    await self.refresh()
                except Exception as exc:  # the database may be back next time; keep the old book
                    log.warning("could not refresh the registered addresses: %s", exc)
        finally:
            for target, name, fn in listeners:
                event.remove(target, name, fn)


@dataclass(slots=True)
class Slot:
    """One handshake in progress."""

    ip: str
    started: float
    evict: Callable[[], None]
    waiting_on_peer: bool = True
    """True while the center waits for the peer (Hello, AuthResponse); False while the
    center itself works (database, lease)."""


class HandshakeSlots:
    """Handshakes in progress, at most ``per_address`` per address and ``total`` in all."""

    def __init__(self, total: int, per_address: int) -> None:
        if total < 1 or per_address < 1:
            raise ValueError("handshake limits must be at least 1")
        self.total = total
        self.per_address = per_address
        self._slots: dict[int, Slot] = {}
        self._per_ip: dict[str, int] = {}
        self._next = 0
        self.evicted = 0

    def __len__(self) -> int:
        return len(self._slots)

    def acquire(self, ip: str, evict: Callable[[], None]) -> int | None:
        """A slot id for a handshake from ``ip``, or None when it must be refused.

        ``evict`` is called (synchronously) if the slot is later given to a newcomer.
        """
        held = self._per_ip.get(ip, 0)
        if held >= self.per_address:
            return None
        # When all are taken, only an address with no handshake of its own may take
        # another's slot: a flood from one address cannot push out anyone, and the slot
        # taken is the one whose peer has kept us waiting longest.
        if len(self._slots) >= self.total and (held > 0 or not self._evict_oldest_waiter()):
            return None
        self._next += 1
        self._slots[self._next] = Slot(ip, time.monotonic(), evict)
        self._per_ip[ip] = held + 1
        return self._next

    def _evict_oldest_waiter(self) -> bool:
        waiting = [(s.started, key) for key, s in self._slots.items() if s.waiting_on_peer]
        if not waiting:
            return False
        _, key = min(waiting)
        slot = self._slots[key]
        self.release(key)
        self.evicted += 1
        slot.evict()
        return True

    def waiting(self, key: int, on_peer: bool) -> None:
        """Mark whether the handshake ``key`` now waits for its peer."""
        slot = self._slots.get(key)
        if slot is not None:
            slot.waiting_on_peer = on_peer

    def release(self, key: int) -> None:
        slot = self._slots.pop(key, None)
        if slot is None:
            return
        left = self._per_ip[slot.ip] - 1
        if left:
            self._per_ip[slot.ip] = left
        else:
            del self._per_ip[slot.ip]


@dataclass(slots=True)
class _Failures:
    count: int = 0
    blocked_until: float = 0.0
    last: float = 0.0


class LoginThrottle:
    """Exponential delay after failed logins, per key (``ip:...`` and ``name:...``).

    After the n-th failure in a row a key is blocked for ``base_s * 2**(n-1)`` seconds, at
    most ``max_s``; a success clears it, as does ``forget_s`` without a failure.
    """

    def __init__(self, *, base_s: float = 0.5, max_s: float = 60.0,
                 forget_s: float = 900.0, clock: Callable[[], float] = time.monotonic) -> None:
        self.base_s = base_s
        self.max_s = max_s
        self.forget_s = forget_s
        self.clock = clock
        self._keys: OrderedDict[str, _Failures] = OrderedDict()

    def blocked(self, *keys: str) -> str | None:
        """The first of ``keys`` that may not try now, or None."""
        now = self.clock()
        for key in keys:
            entry = self._keys.get(key)
            if entry is None:
                continue
            if now - entry.last > self.forget_s:
                del self._keys[key]
            elif now < entry.blocked_until:
                return key
        return None

    def failed(self, *keys: str) -> None:
        now = self.clock()
        for key in keys:
            entry = self._keys.pop(key, None) or _Failures()
            entry.count += 1
            entry.last = now
            delay = min(self.max_s, self.base_s * 2.0 ** min(entry.count - 1, 30))
            entry.blocked_until = now + delay
            self._keys[key] = entry  # most recent last
            while len(self._keys) > MAX_TRACKED:
                self._keys.popitem(last=False)

    def succeeded(self, *keys: str) -> None:
        for key in keys:
            self._keys.pop(key, None)


@dataclass(slots=True)
class _Window:
    started: float
    detail: str
    reason: str
    count: int = 0
    """Refusals after the first (the first is stored at once)."""


Refusal = tuple[str, str, str]
"""(who, detail, reason) of one refusal row."""

Store = Callable[[list[Refusal]], Awaitable[None]]
"""``store(rows)``: write refusal events in one transaction (and tell the feed)."""


@dataclass
class RefusalLog:
    """Refusal events, at most one stored per peer per ``window_s`` plus one summary.

    The first refusal of a peer in a window is stored at once (the dashboard shows it at
    once); later ones are counted, and when the window ends one more row says how many
    there were. A flood of refused connections thus costs two rows a minute per peer.

    While :meth:`run` runs, rows are written by one writer task, each batch in one
    transaction (group commit): three hundred peers timing out together cost one or two
    commits, not three hundred database calls queued in front of a machine's handshake.
    :meth:`refused` still returns only once its row is stored, so a peer that sees its
    connection close finds its refusal in the table.
    """

    store: Store
    window_s: float = 60.0
    clock: Callable[[], float] = time.monotonic
    _windows: OrderedDict[str, _Window] = field(default_factory=OrderedDict)
    _queue: list[tuple[Refusal, asyncio.Future[None]]] = field(default_factory=list)
    _wake: asyncio.Event | None = None

    async def refused(self, who: str, detail: str, reason: str) -> None:
        now = self.clock()
        current = self._windows.get(who)
        if current is not None and now - current.started < self.window_s:
            current.count += 1
            return
        if current is not None:
            await self._summary(who, current)
        self._windows[who] = _Window(now, detail, reason)
        self._windows.move_to_end(who)
        while len(self._windows) > MAX_TRACKED:
            old_who, old = self._windows.popitem(last=False)
            await self._summary(old_who, old)
        await self._write((who, detail, reason))

    async def _summary(self, who: str, window: _Window) -> None:
        if window.count:
            await self._write((who, f"{window.count} more refusals in {self.window_s:g} s "
                                    f"after: {window.detail}", window.reason))

    async def _write(self, row: Refusal) -> None:
        if self._wake is None:  # no writer task: write it now
            await self.store([row])
            return
        done = asyncio.get_running_loop().create_future()
        self._queue.append((row, done))
        self._wake.set()
        await done

    async def _writer(self, wake: asyncio.Event) -> None:
        while True:
            await wake.wait()
            wake.clear()
            batch, self._queue = self._queue, []
            try:
                await self.store([row for row, _ in batch])
            except Exception:  # a lost batch of events must not stop the link
                log.exception("could not store %d refusal events", len(batch))
            finally:
                for _, done in batch:
                    if not done.done():
                        done.set_result(None)

    async def flush(self, *, everything: bool = False) -> None:
        """Store the summaries of the windows that have ended (all of them at shutdown)."""
        now = self.clock()
        ended = [who for who, w in self._windows.items()
                 if everything or now - w.started >= self.window_s]
        for who in ended:
            await self._summary(who, self._windows.pop(who))

    async def run(self, period_s: float = 5.0) -> None:
        """Write rows and flush ended windows every ``period_s`` until cancelled, then
        store all summaries."""
        wake = self._wake = asyncio.Event()
        writer = asyncio.create_task(self._writer(wake), name="refusal-writer")
        try:
            while True:
                await asyncio.sleep(period_s)
                await self.flush()
        finally:
            await asyncio.shield(self._close(writer))

    async def _close(self, writer: asyncio.Task[None]) -> None:
        await self.flush(everything=True)
        self._wake = None  # from now on each refusal is written directly
        writer.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await writer
        left, self._queue = self._queue, []
        if left:
            await self.store([row for row, _ in left])
        for _, done in left:
            if not done.done():
                done.set_result(None)


class OncePerWindow:
    """Whether to log about ``key`` now: at most once per ``window_s`` per key."""

    def __init__(self, window_s: float = 60.0) -> None:
        self.window_s = window_s
        self._last: OrderedDict[str, float] = OrderedDict()

    def __call__(self, key: str) -> bool:
        now = time.monotonic()
        last = self._last.get(key)
        if last is not None and now - last < self.window_s:
            return False
        self._last[key] = now
        self._last.move_to_end(key)
        while len(self._last) > MAX_TRACKED:
            self._last.popitem(last=False)
        return True
