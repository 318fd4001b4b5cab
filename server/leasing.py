"""Machine leases of one node: take them at handshake, renew them, give them back.

Several control-center processes (nodes, ``EDNC_NODE_ID``) may share one database; each
machine is served by exactly one of them at a time, the one holding its lease
(:mod:`server.db.leases`). The :class:`LeaseKeeper` is that node's side:

* :meth:`LeaseKeeper.claim`, called by the machine server after the machine authenticated
  and before Welcome: takes the lease, or says which node holds it (the machine is then
  refused and tries another center);
* every ``ttl_s / 3`` one statement renews the leases of all the node's sessions; a lease
  another node took (after it had expired: this node stalled, or lost the database for
  longer than the TTL) ends its session at once, as does a lease this node could not
  renew before its own TTL ran out, so that two nodes never serve one machine;
* :meth:`LeaseKeeper.release` when a session ends, and every lease of the node at a clean
  shutdown, so that the machine may go to another node without waiting for the TTL.

A node killed outright renews nothing: its leases expire ``ttl_s`` after their last
renewal and the other nodes then accept its machines.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from dataclasses import dataclass
from types import TracebackType
from typing import Final

from sqlalchemy.exc import SQLAlchemyError

from server.background import Background, every
from server.center import Center
from server.db import leases as lease_repo

log = logging.getLogger(__name__)

RENEWALS_PER_TTL: Final = 3
"""Renew every third of the TTL: two renewals may fail (a database blip) before the
lease runs out."""

OnLost = Callable[[str], None]
"""Told why the lease is gone; ends the session."""


@dataclass
class _Holding:
    name: str
    token: object
    """The session that holds the lease: a newer session of the same machine replaces it,
    and the older one's release must then leave the lease alone."""
    on_lost: OnLost
    valid_until: float
    """Loop time until which the lease is surely ours: taken before the last successful
    renewal statement, plus the TTL."""


class LeaseKeeper:
    """The leases of this node's sessions; an async context manager.

    Parameters
    ----------
    center : Center
        Its settings give ``node_id`` and ``lease_ttl_s``.
    ttl_s : float, optional
        Overrides ``center.settings.lease_ttl_s``.
    """

    def __init__(self, center: Center, *, ttl_s: float | None = None) -> None:
        self.center = center
        self.db = center.db
        self.node = center.settings.node_id
        self.ttl_s = ttl_s if ttl_s is not None else center.settings.lease_ttl_s
        self.renew_s = self.ttl_s / RENEWALS_PER_TTL
        self._held: dict[int, _Holding] = {}
        self._background = Background()
        self._releases: set[asyncio.Task[None]] = set()

    async def __aenter__(self) -> LeaseKeeper:
        self._background.start(every(self.renew_s, self.renew_once), "leases:renew")
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        await self._background.stop()
        if self._releases:
            await asyncio.gather(*self._releases, return_exceptions=True)
        self._held.clear()
        try:
            gone = await self.db.run(lease_repo.release_all, self.node)
            log.info("node %s: released %d machine leases", self.node, gone)
        except SQLAlchemyError:
            log.exception("node %s: could not release its leases (they expire in %g s)",
                          self.node, self.ttl_s)

    # -- sessions
    async def claim(self, machine_id: int, name: str, token: object,
                    on_lost: OnLost) -> str | None:
        """Take ``machine_id``'s lease for the session ``token``.

        Returns
        -------
        str or None
            None when this node now holds the lease (it is renewed until
            :meth:`release`, and ``on_lost`` is called if it is lost meanwhile); else why
            not, for the Reject: ``machine 'm' is owned by node X`` or the database
            failure.
        """
        loop = asyncio.get_running_loop()
        started = loop.time()
        taking = asyncio.ensure_future(
            self.db.run(lease_repo.acquire, machine_id, self.node, self.ttl_s))
        try:
            lease = await asyncio.shield(taking)
        except asyncio.CancelledError:
            # the handshake timed out (or the server closes) while the statement ran on
            # its thread: give back what it may still take, rather than leave it to expire
            taking.add_done_callback(lambda done: self._abandoned(done, machine_id, name))
            raise
        except SQLAlchemyError as exc:
            log.error("node %s: lease of %s: %s", self.node, name, exc)
            return f"machine {name!r}: its lease cannot be taken now (database error)"
        if lease.owner != self.node:
            return f"machine {name!r} is owned by node {lease.owner}"
        self._held[machine_id] = _Holding(name, token, on_lost, started + self.ttl_s)
        return None

    def _abandoned(self, done: asyncio.Future[lease_repo.Lease], machine_id: int,
                   name: str) -> None:
        if done.cancelled() or done.exception() is not None:
            return
        if done.result().owner == self.node and machine_id not in self._held:
            self._spawn_release(machine_id, name)

    def release(self, machine_id: int, token: object) -> None:
        """The session ``token`` ended: give its lease back (in the background), unless a
        newer session of the machine holds it now."""
        holding = self._held.get(machine_id)
        if holding is None or holding.token is not token:
            return
        del self._held[machine_id]
        self._spawn_release(machine_id, holding.name)

    def _spawn_release(self, machine_id: int, name: str) -> None:
        task = asyncio.create_task(self._release(machine_id, name),
                                   name=f"leases:release:{name}")
        self._releases.add(task)
        task.add_done_callback(self._releases.discard)

    async def _release(self, machine_id: int, name: str) -> None:
        try:
            await self.db.run(lease_repo.release, [machine_id], self.node)
        except SQLAlchemyError as exc:  # it expires by itself
            log.warning("node %s: lease of %s not released (%s); it expires in %g s",
                        self.node, name, exc, self.ttl_s)

    def holds(self, machine_id: int) -> bool:
        """Whether this node surely holds the machine's lease now (its local view)."""
        holding = self._held.get(machine_id)
        return holding is not None and asyncio.get_running_loop().time() < holding.valid_until

    def held(self) -> dict[int, str]:
        """Machine ids and names of the leases this node holds."""
        return {mid: h.name for mid, h in self._held.items()}

    # -- renewal
    async def renew_once(self) -> None:
        """Renew every held lease now; end the sessions whose lease is gone."""
        loop = asyncio.get_running_loop()
        started = loop.time()
        asked = dict(self._held)
        if not asked:
            return
        try:
            # a database that hangs must not keep sessions past their lease: stop waiting
            # after a renewal period (the statement may still finish on its thread)
            async with asyncio.timeout(self.renew_s):
                kept = await self.db.run(lease_repo.renew, list(asked), self.node,
                                         self.ttl_s)
        except (SQLAlchemyError, TimeoutError) as exc:
            log.error("node %s: lease renewal failed: %r", self.node, exc)
            now = loop.time()
            for mid, holding in asked.items():
                if self._held.get(mid) is holding and now >= holding.valid_until:
                    self._lose(mid, holding, f"lease not renewed for {self.ttl_s:g} s "
                                             "(database unreachable)")
            return
        for mid, holding in asked.items():
            if self._held.get(mid) is not holding:
                continue  # released or replaced meanwhile
            if mid in kept:
                holding.valid_until = started + self.ttl_s
            else:
                self._lose(mid, holding, "lease lost: another node serves this machine now")

    def _lose(self, machine_id: int, holding: _Holding, why: str) -> None:
        del self._held[machine_id]
        log.warning("node %s: %s: %s", self.node, holding.name, why)
        try:
            holding.on_lost(why)
        except Exception:  # one session's callback must not stop the renewals
            log.exception("node %s: ending the session of %s failed", self.node,
                          holding.name)


__all__ = ["RENEWALS_PER_TTL", "LeaseKeeper"]
