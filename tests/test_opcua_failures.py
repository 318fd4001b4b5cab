"""Both OPC UA links fail alike (issue 30 item 1): the window link
(:class:`~server.links.opcua.OpcuaMemory`) and the native SINUMERIK link
(:class:`~server.links.sinumerik_sd.SdSession`) meet the same fault with the same state and
reason (server/links/opcualogin.py's table), and ``ednc serve`` shows a native link's
failure as it shows a window link's: the status's ``link_state``/``link_reason`` and a
``link`` event.

Each fault is made for real: a simulated SINUMERIK (:class:`~machine_sim.sinumerik_native.
NativeSinumerik`) with another password, only security None, a trust list without the
center, a node that is not there; a port nobody listens on; a TCP server that never
answers.
"""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import AsyncIterator, Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest

from machine_sim.opcua_server import OpcuaUser
from machine_sim.sinumerik_native import NativeSinumerik
from server.links.opcua import OpcuaMemory
from server.links.opcualogin import OpcuaSecurity
from server.links.opcuapki import Pki, pki_at
from server.links.sinumerik_sd import SdSession
from server.links.window.memory import LinkError
from tests.support.integration import center
from volumetric.model.machine import Machine, parse_machine

pytestmark = pytest.mark.timeout(120)

PASSWORD = "Sea-Writer-51c0"
SEA_WRITER = frozenset({"SinuReadAll", "SeaWrite"})
USERS = {"ednc": OpcuaUser(PASSWORD, SEA_WRITER), "nobody": OpcuaUser("n", frozenset())}
MACHINE: Machine = parse_machine({
    "name": "vmc-sd", "controller": "siemens", "ip": "127.0.0.1", "chain": "w X Y b Z t",
    "tool_length_mm": 100.0, "travel_mm": {"x": [0, 800], "y": [0, 500], "z": [-500, 0]}})
MISSING = "ns=2;s=/NC/_N_AX_SEA_ACX/$SA_NO_SUCH_DATUM[u1]"


@pytest.fixture
def pki(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Pki:
    """The center's certificates in a folder of this test (nothing trusted yet)."""
    monkeypatch.setenv("EDNC_OPCUA_PKI_DIR", str(tmp_path / "center"))
    return pki_at(tmp_path / "center")


async def _both(endpoint: str, pki: Pki, *, user: str = "ednc", password: str = PASSWORD,
                security: OpcuaSecurity | None = None, timeout_s: float = 5.0,
                use: Callable[[Any], Awaitable[object]] | None = None
                ) -> tuple[tuple[str, str], tuple[str, str]]:
    """(state, reason) of the failure on the window link and on the native link, each
    connecting to ``endpoint`` and then ``use``-ing it."""
    sec = security or OpcuaSecurity()
    window = OpcuaMemory(endpoint, user, "env:UNUSED", password=password, pki=pki,
                         security_policy=sec.policy, security_mode=sec.mode, trust=sec.trust,
                         timeout_s=timeout_s, retry_delays_s=(),
                         sd_nodes={"X.43900": MISSING})
    native = SdSession(endpoint, user, password, MACHINE.axis_names, security=sec, pki=pki,
                       timeout_s=timeout_s, retry_delays_s=(),
                       sd_nodes={"X.43900": MISSING})
    out: list[tuple[str, str]] = []
    for link in (window, native):
        with pytest.raises(LinkError) as err:
            try:
                await link.connect()
                if use is not None:
                    await use(link)
            finally:
                await link.close()
        out.append((err.value.state, err.value.reason))
    return out[0], out[1]


@contextlib.asynccontextmanager
async def nc(**server: Any) -> AsyncIterator[str]:
    async with NativeSinumerik(MACHINE, USERS, **server) as cnc:
        yield cnc.endpoint


async def test_a_wrong_password_is_refused_login_on_both(pki: Pki) -> None:
    async with nc() as url:
        window, native = await _both(url, pki, password="not-it")
    assert window == native == ("refused", "login")


async def test_a_controller_offering_no_security_is_refused_security_on_both(
        pki: Pki) -> None:
    async with nc(security_modes=("None",)) as url:
        window, native = await _both(url, pki)
    assert window == native == ("refused", "security")


async def test_a_controller_not_in_the_trust_list_is_refused_on_both(pki: Pki) -> None:
    async with nc() as url:
        window, native = await _both(url, pki, security=OpcuaSecurity(trust="list"))
    assert window == native == ("refused", "server_certificate")


async def test_a_controller_that_does_not_trust_the_center_is_refused_on_both(
        pki: Pki, tmp_path: Path) -> None:
    from asyncua.crypto.cert_gen import setup_self_signed_certificate
    from cryptography.x509.oid import ExtendedKeyUsageOID

    other = tmp_path / "other.der"  # the only client the controller trusts
    await setup_self_signed_certificate(
        tmp_path / "other-key.pem", other, "urn:other", "localhost",
        [ExtendedKeyUsageOID.CLIENT_AUTH], {"commonName": "other"})
    async with nc(trusted_clients=[other]) as url:
        window, native = await _both(url, pki)
    assert window == native == ("refused", "BadCertificateUntrusted")


async def test_nothing_listening_is_unreachable_connect_on_both(pki: Pki) -> None:
    window, native = await _both("opc.tcp://127.0.0.1:9", pki, timeout_s=2.0)
    assert window == native == ("unreachable", "connect")


async def test_a_controller_that_never_answers_is_unreachable_no_answer_on_both(
        pki: Pki) -> None:
    held: list[asyncio.StreamWriter] = []

    async def silent(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        held.append(writer)  # takes the connection, reads, never answers
        with contextlib.suppress(ConnectionError):
            while await reader.read(4096):
                pass

    server = await asyncio.start_server(silent, "127.0.0.1", 0)
    port = server.sockets[0].getsockname()[1]
    try:
        window, native = await _both(f"opc.tcp://127.0.0.1:{port}", pki, timeout_s=0.5)
    finally:
        for w in held:
            w.close()
        server.close()
    assert window == native == ("unreachable", "no_answer")


async def test_a_missing_node_and_a_missing_right_read_the_same_on_both(pki: Pki) -> None:
    async def read(link: Any) -> object:  # what each link reads of setting data
        if isinstance(link, OpcuaMemory):
            return await link.read_axes(MACHINE.axis_names)
        return await link.read()

    async with nc() as url:
        missing = await _both(url, pki, use=read)
        rights = await _both(url, pki, user="nobody", password="n", use=read)
    assert missing[0] == missing[1] == ("refused", "BadNodeIdUnknown")
    assert rights[0] == rights[1] == ("refused", "rights")


async def test_a_user_without_seawrite_is_refused_rights_not_an_axis_refusal(
        pki: Pki) -> None:
    from server.links.sdwrites import SD_ABS_VALUE, SdWrite

    users = {"reader": OpcuaUser("r", frozenset({"SinuReadAll"}))}
    async with NativeSinumerik(MACHINE, users) as cnc:
        session = SdSession(cnc.endpoint, "reader", "r", MACHINE.axis_names, pki=pki)
        await session.connect()
        try:
            with pytest.raises(LinkError, match="lacks SeaWrite") as err:
                await session.write([SdWrite("X", ((SD_ABS_VALUE, 0.01),))])
        finally:
            await session.close()
    assert (err.value.state, err.value.reason) == ("refused", "rights")


async def test_ednc_serve_shows_a_native_links_refusal_with_its_reason(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, pki: Pki) -> None:
    """A mistyped password on a ``sinumerik_sd`` link: the status says ``refused``
    (``login``) within seconds and a ``link`` event says why, once."""
    monkeypatch.setenv("SD_FAILURE_PW", "not-it")
    desc = {"name": "vmc-sd", "controller": "siemens", "ip": "127.0.0.1",
            "chain": "w X Y b Z t", "tool_length_mm": 100.0,
            "travel_mm": {"x": [0, 800], "y": [0, 500], "z": [-500, 0]}}
    async with nc() as url, center(f"sqlite:///{tmp_path / 'ednc.db'}") as plant:
        link = {"kind": "sinumerik_sd", "endpoint": url, "user": "ednc",
                "password_ref": "env:SD_FAILURE_PW"}
        r = await plant.client.post("/api/machines", json={**desc, "link": link,
                                                          "secret": "s" * 24})
        assert r.status_code == 201, r.text
        async with asyncio.timeout(10.0):
            while (await plant.status("vmc-sd"))["link_state"] != "refused":
                await asyncio.sleep(0.1)
        st = await plant.status("vmc-sd")
        assert st["link_reason"] == "login" and "wrong user or password" in st["link_text"]
        async with asyncio.timeout(10.0):
            while not [e for e in await plant.events(machine="vmc-sd")
                       if e["kind"] == "link"]:
                await asyncio.sleep(0.1)
        await asyncio.sleep(3.0)  # retries meanwhile (backoff): the reason said once
        said = [e["detail"] for e in await plant.events(machine="vmc-sd")
                if e["kind"] == "link"]
        assert len(said) == 1 and "refused (login)" in said[0], said


async def test_a_native_link_refused_after_login_is_paced_as_the_window_links(
        pki: Pki) -> None:
    """A user without SeaWrite: the session opens, reads, and its first write is refused.
    That must not reset the backoff (issue 30's storm: a login per refusal): in 6 s the
    follower logs in twice (at once, then after the first step of 3-4 s)."""
    from server.links.sinumerik_sd import SdFollower
    from volumetric.model.model import ThermalTerm

    users = {"reader": OpcuaUser("r", frozenset({"SinuReadAll"}))}
    terms = (ThermalTerm("thermal_drift", "z", "T_spindle_C", -2.5, 20.0),)
    async with NativeSinumerik(MACHINE, users) as cnc:
        session = SdSession(cnc.endpoint, "reader", "r", MACHINE.axis_names, pki=pki)
        logins: list[float] = []
        connect = session.connect

        async def counted() -> None:
            logins.append(asyncio.get_running_loop().time())
            await connect()

        session.connect = counted  # type: ignore[method-assign]
        async with SdFollower(MACHINE.name, session, terms) as follower:
            follower.set_temperatures({"T_spindle_C": 31.0})
            await asyncio.sleep(6.0)
        assert follower.last_error is not None and "lacks SeaWrite" in follower.last_error
    assert len(logins) == 2, logins
    assert 3.0 <= logins[1] - logins[0] <= 5.0, logins
