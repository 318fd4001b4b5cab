"""OPC UA secure by default (issue 30 item 5), the simulated SINUMERIK's busy answers and
session limit, and the write block per PLC class.

A TCP relay between the center and the simulated controller keeps every byte both ways:
with the link's defaults (Basic256Sha256 SignAndEncrypt, the center's own certificate)
the password is nowhere in them; with ``security_policy: None`` it is, and the memory
says so. The relay also stands for a controller whose certificate changes behind one
endpoint (it forwards to another server).
"""

from __future__ import annotations

import asyncio
import contextlib
import stat
from collections.abc import AsyncIterator
from pathlib import Path

import pytest
from asyncua.client.client import Client

from machine_sim.opcua_server import PLC_WRITER, OpcuaUser, sinumerik_server
from machine_sim.windowcnc import WindowCNC
from server.links.opcua import PLC_BLOCK, OpcuaMemory
from server.links.opcuapki import Pki, pki_at, thumbprint
from server.links.window.memory import LinkError
from server.schemas.link import OpcuaLink
from tests.support.cli import ednc
from tests.support.integration import spec
from tests.support.relay import Relay, appears

pytestmark = pytest.mark.timeout(300)

PASSWORD = "Plc-Writer-7f3a9c"  # distinctive: found only where it really is
USERS = {"ednc": OpcuaUser(PASSWORD, PLC_WRITER)}


@pytest.fixture(autouse=True)
def env(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("OPCUA_SEC_PW", PASSWORD)
    monkeypatch.setenv("EDNC_OPCUA_PKI_DIR", str(tmp_path / "pki"))


@contextlib.asynccontextmanager
async def controller(**kw: object) -> AsyncIterator[WindowCNC]:
    m = spec("vmc-06").machine
    async with WindowCNC(m, sinumerik_server(USERS, **kw), cycle_s=0.02) as cnc:
        yield cnc


def link(endpoint: str, **kw: object) -> OpcuaLink:
    return OpcuaLink.model_validate({"kind": "opcua", "endpoint": endpoint, "user": "ednc",
                                     "password_ref": "env:OPCUA_SEC_PW", **kw})


async def test_the_password_never_crosses_the_wire_in_clear_by_default() -> None:
    async with controller() as cnc, Relay(cnc.server.port) as relay:
        mem = OpcuaMemory.from_link(link(relay.endpoint))
        assert (mem.security_policy, mem.security_mode) == ("Basic256Sha256",
                                                            "SignAndEncrypt")
        await mem.connect()
        try:
            assert await mem.read(0, 4) == b"EDCM"
            await mem.write(256, b"\x11\x22\x33\x44")
            assert bytes(cnc.window[256:260]) == b"\x11\x22\x33\x44"
        finally:
            await mem.close()
        assert not mem.insecure
        assert not any("clear" in n for n in mem.take_notices())
        seen = bytes(relay.to_server)
        assert len(seen) > 1000  # the login and the requests went through the relay
        assert not appears(PASSWORD, seen) and not appears(PASSWORD, bytes(relay.to_client))
        assert b"EDCM" not in bytes(relay.to_client)  # the window's bytes encrypted too
        sign = OpcuaMemory.from_link(link(relay.endpoint, security_mode="Sign"))
        before = len(relay.to_server)
        await sign.connect()  # Sign: the channel in clear, the password token encrypted
        try:
            assert await sign.read(0, 4) == b"EDCM"
        finally:
            await sign.close()
        assert len(relay.to_server) > before
        assert not appears(PASSWORD, bytes(relay.to_server))


async def test_security_none_must_be_asked_for_and_then_the_password_is_seen() -> None:
    async with controller() as cnc, Relay(cnc.server.port) as relay:
        mem = OpcuaMemory.from_link(link(relay.endpoint, security_policy="None"))
        assert mem.insecure and mem.security_mode == "None"
        (notice,) = mem.take_notices()
        assert "security None" in notice and "clear text" in notice
        assert mem.take_notices() == []  # each once
        again = OpcuaMemory.from_link(link(relay.endpoint, security_policy="None"))
        assert again.take_notices() == []  # and once per controller: no event per retry
        await mem.connect()
        try:
            assert await mem.read(0, 4) == b"EDCM"
        finally:
            await mem.close()
        assert appears(PASSWORD, bytes(relay.to_server))  # what the relay test must catch
        with pytest.raises(LinkError, match="Basic256Sha256 with Sign or SignAndEncrypt"):
            OpcuaMemory.from_link(link(relay.endpoint, security_policy="None",
                                       security_mode="Sign"))


async def test_the_center_certificate_is_made_once_and_kept(tmp_path: Path) -> None:
    root = tmp_path / "own-pki"
    a = Pki(root).identity()
    assert a.created and a.path.exists()
    assert stat.S_IMODE((root / "own" / "center.key.pem").stat().st_mode) == 0o600
    b = Pki(root).identity()  # a restart reads it back
    assert not b.created and b.thumbprint == a.thumbprint == thumbprint(a.der)
    shared = pki_at(root)
    assert shared is pki_at(root) and shared.identity() is shared.identity()
    # two sessions connecting at once on a fresh folder make one certificate
    fresh = pki_at(tmp_path / "fresh")
    got = await asyncio.gather(*(asyncio.to_thread(fresh.identity) for _ in range(8)))
    assert len({g.thumbprint for g in got}) == 1


async def test_a_changed_controller_certificate_is_refused_until_trusted(
        tmp_path: Path) -> None:
    key_a, cert_a = tmp_path / "a-key.pem", tmp_path / "a.der"
    key_b, cert_b = tmp_path / "b-key.pem", tmp_path / "b.der"
    from asyncua.crypto.cert_gen import setup_self_signed_certificate
    from cryptography.x509.oid import ExtendedKeyUsageOID

    use = [ExtendedKeyUsageOID.SERVER_AUTH, ExtendedKeyUsageOID.CLIENT_AUTH]
    for key, cert, who in ((key_a, cert_a, "a"), (key_b, cert_b, "b")):
        await setup_self_signed_certificate(key, cert, "urn:freeopcua:python:server",
                                            "localhost", use, {"commonName": who})
    pki = pki_at()
    async with (controller(certificate=cert_a, private_key=key_a) as a,
                controller(certificate=cert_b, private_key=key_b) as b,
                Relay(a.server.port) as relay):
        mem = OpcuaMemory.from_link(link(relay.endpoint))
        await mem.connect()  # first use: a's certificate kept for this endpoint
        await mem.close()
        assert any("trusted on first use" in n for n in mem.take_notices())
        assert pki.pinned(relay.endpoint) == cert_a.read_bytes()
        await mem.connect()  # again, with the kept one (no GetEndpoints first)
        await mem.close()
        relay.upstream = b.server.port  # another controller behind the same endpoint
        with pytest.raises(LinkError, match=r"certificate changed.*refused") as err:
            await mem.connect()
        assert thumbprint(cert_b.read_bytes()) in str(err.value)
        assert (err.value.state, err.value.reason) == ("refused", "server_certificate")
        (rejected,) = pki.rejected_dir.iterdir()
        assert rejected.read_bytes() == cert_b.read_bytes()
        pki.trusted_dir.mkdir(parents=True, exist_ok=True)
        rejected.rename(pki.trusted_dir / "b.der")  # the operator trusts it
        await mem.connect()
        try:
            assert await mem.read(0, 4) == b"EDCM"
        finally:
            await mem.close()
        # trust: list takes only the trust list, first use or not
        strict = OpcuaMemory.from_link(link(relay.endpoint, trust="list"))
        relay.upstream = a.server.port
        with pytest.raises(LinkError, match="not in the trust list"):
            await strict.connect()
        relay.upstream = b.server.port
        await strict.connect()
        await strict.close()


async def test_sessions_never_activated_do_not_lock_the_center_out() -> None:
    async with controller() as cnc:
        half_open: list[Client] = []
        try:
            for _ in range(10):  # all ten places taken by logins never completed
                c = Client(f"opc.tcp://127.0.0.1:{cnc.server.port}", timeout=5)
                await c.connect_socket()
                await c.send_hello()
                await c.open_secure_channel()
                await c.create_session()
                half_open.append(c)
            mem = OpcuaMemory(f"opc.tcp://127.0.0.1:{cnc.server.port}", "ednc",
                              "env:OPCUA_SEC_PW")
            await mem.connect()
            try:
                assert await mem.read(0, 4) == b"EDCM"
            finally:
                await mem.close()
            internal = cnc.server._internal  # type: ignore[attr-defined]
            assert internal.evicted >= 1
            # ten activated sessions are another matter: the eleventh is refused
            full = [OpcuaMemory(f"opc.tcp://127.0.0.1:{cnc.server.port}", "ednc",
                                "env:OPCUA_SEC_PW", retry_delays_s=(0.05,))
                    for _ in range(11)]
            try:
                for m in full[:10]:
                    await m.connect()
                with pytest.raises(LinkError, match="BadTooManySessions"):
                    await full[10].connect()
                assert full[10].busy_retries == 1  # asked again once, then refused
            finally:
                for m in full:
                    await m.close()
        finally:
            for c in half_open:
                c.disconnect_socket()


async def test_busy_answers_are_retried_within_the_session() -> None:
    async with controller(busy=0.3, seed=7) as cnc:
        mem = OpcuaMemory(f"opc.tcp://127.0.0.1:{cnc.server.port}", "ednc",
                          "env:OPCUA_SEC_PW")
        await mem.connect()
        try:
            for k in range(40):
                data = bytes([k, k + 1, k + 2, k + 3])
                await mem.write(256, data)
                assert await mem.read(256, 4) == data
            internal = cnc.server._internal  # type: ignore[attr-defined]
            assert internal.busy_answers > 5 and mem.busy_retries >= internal.busy_answers - 2
            client = mem._client
            assert client is not None  # the same session throughout
        finally:
            await mem.close()
    async with controller(busy=0.995, seed=1) as cnc:  # busy for good: bounded, then fails
        mem = OpcuaMemory(f"opc.tcp://127.0.0.1:{cnc.server.port}", "ednc",
                          "env:OPCUA_SEC_PW", retry_delays_s=(0.01, 0.01, 0.01))
        cnc.server._internal.busy = 0.0  # type: ignore[attr-defined]
        await mem.connect()
        cnc.server._internal.busy = 0.995  # type: ignore[attr-defined]
        try:
            with pytest.raises(LinkError, match=r"busy.*BadResourceUnavailable"):
                await mem.read(0, 4)
            assert mem.busy_retries == 3
        finally:
            await mem.close()


def test_the_write_block_follows_the_plc_class() -> None:
    url = "opc.tcp://10.0.3.18:4840"
    assert OpcuaMemory.from_link(link(url)).block == 240 == PLC_BLOCK["s7-300"]
    assert OpcuaMemory.from_link(link(url, plc_class="s7-1500")).block == 960
    assert OpcuaMemory.from_link(link(url, plc_class="s7-1500", block_bytes=480)).block == 480
    assert link(url).security_policy == "Basic256Sha256"
    assert link(url).trust == "first_use"


async def test_the_certificate_is_shown_for_the_controllers_trust_lists() -> None:
    from cryptography import x509
    from cryptography.hazmat.primitives.serialization import Encoding

    from server.api.routes.opcua import center_certificate
    from server.links.opcuapki import certificate_line

    line = certificate_line(pki_at())  # what ednc serve prints; a first start makes it
    shown = await center_certificate()
    identity = pki_at().identity()
    assert f"made now: thumbprint {identity.thumbprint}" in line
    assert shown.thumbprint == identity.thumbprint and shown.path == str(identity.path)
    pem = x509.load_pem_x509_certificate(shown.pem.encode())
    assert pem.public_bytes(Encoding.DER) == identity.der
    assert "made now" not in certificate_line(Pki(pki_at().root))  # a restart reads it


async def test_an_s7_300_class_plc_takes_240_bytes_per_write() -> None:
    async with controller(plc_class="s7-300") as cnc:
        url = f"opc.tcp://127.0.0.1:{cnc.server.port}"
        big = OpcuaMemory.from_link(link(url, plc_class="s7-1500"))
        await big.connect()
        try:
            with pytest.raises(LinkError, match=r"set the link's plc_class s7-300.*"
                                                r"BadRequestTooLarge"):
                await big.write(512, bytes(range(244)) * 3 + bytes(228))  # 960 bytes
        finally:
            await big.close()
        small = OpcuaMemory.from_link(link(url))  # the default: an S7-300's 240
        await small.connect()
        try:
            await small.write(512, bytes(range(240)))
            assert bytes(cnc.window[512:752]) == bytes(range(240))
        finally:
            await small.close()


def test_ednc_sim_options_set_the_links_and_the_simulated_controllers(
        monkeypatch: pytest.MonkeyPatch) -> None:
    from machine_sim.fleet import generated_fleet, served_machine

    monkeypatch.setenv("EDNC_OPCUA_PASSWORD", PASSWORD)
    secret = "0123456789abcdef0123"
    (plain,) = generated_fleet(1, secret, link="opcua", opcua_security="none")
    assert plain.link is not None and plain.link["security_policy"] == "None"
    assert served_machine(plain).server.security_modes == ("None",)  # type: ignore[attr-defined]
    (one,) = generated_fleet(1, secret, link="opcua", plc_class="s7-1500")
    assert one.link is not None and (one.link["security_mode"], one.link["plc_class"]) == (
        "SignAndEncrypt", "s7-1500")
    served = served_machine(one).server
    assert served.security_modes == ("None", "Sign", "SignAndEncrypt")  # type: ignore[attr-defined]
    assert served.plc_class == "s7-1500"  # type: ignore[attr-defined]
    assert OpcuaLink.model_validate(one.link).plc_class == "s7-1500"
    for option, value in (("--opcua-security", "encrypt"), ("--plc-class", "s7-400")):
        r = ednc("sim", "--link", "opcua", "--machines", "1", "--secret", secret, option,
                 value)
        assert r.returncode == 2 and f"{option} {value!r}: expected" in r.stderr, r.stderr


async def test_each_transient_answer_is_asked_again_and_others_are_not() -> None:
    from asyncua import ua

    mem = OpcuaMemory("opc.tcp://10.0.3.18:4840", "ednc", "env:OPCUA_SEC_PW",
                      retry_delays_s=(0.0, 0.0, 0.0))
    for name in ("BadTooManySessions", "BadResourceUnavailable", "BadTimeout"):
        answers: list[object] = [getattr(ua.StatusCodes, name)] * 2 + ["ok"]

        async def request(answers: list[object] = answers) -> object:
            got = answers.pop(0)
            if isinstance(got, int):
                raise ua.UaStatusCodeError(got)
            return got

        before = mem.busy_retries
        assert await mem._call(request, "read", 0, 4, lambda _: []) == "ok"
        assert mem.busy_retries - before == 2, name
    # a node answered busy inside a good response is asked again too
    busy = ua.StatusCode(ua.StatusCodes.BadResourceUnavailable)
    codes = [[busy, ua.StatusCode()], [ua.StatusCode(), ua.StatusCode()]]

    async def write() -> list[ua.StatusCode]:
        return codes.pop(0)

    assert all(c.is_good() for c in await mem._call(write, "write", 0, 8, list))
    refused = 0

    async def denied() -> object:
        nonlocal refused
        refused += 1
        raise ua.UaStatusCodeError(ua.StatusCodes.BadUserAccessDenied)

    with pytest.raises(LinkError, match="lacks PlcWrite"):
        await mem._call(denied, "write", 0, 4, list)
    assert refused == 1  # a refusal is not asked again


async def test_a_controller_busy_for_30_percent_of_its_answers_applies_every_map() -> None:
    """Issue 30's target for busy answers, over OPC UA: 10 of 10 pushes applied within
    10 s each through the center's session, which stays up throughout."""
    import dataclasses

    import numpy as np

    from machine_sim.truth import random_geometry
    from protocol import Controller
    from server.links.window.session import ControllerSession
    from server.mapcodec import build_for, encode
    from volumetric.model.model import MachineModel

    m = spec("vmc-06").machine
    truth = random_geometry(m, np.random.default_rng(4), scale=2.0, form="table")
    content = build_for(m, MachineModel(m.name, truth), {}, tolerance_um=1.0,
                        controller="siemens")
    async with controller(busy=0.3, seed=11) as cnc:
        mem = OpcuaMemory.from_link(link(f"opc.tcp://127.0.0.1:{cnc.server.port}"))
        told: list[tuple[str, str]] = []
        session = ControllerSession(m.name, "127.0.0.1", Controller.SIEMENS, m.axis_names,
                                    mem, link="opcua", chain=m.chain, poll_s=0.1,
                                    on_condition=lambda c: told.append((c.reason, c.text)))
        await session.open()
        runner = asyncio.create_task(session.run())
        try:
            for version in range(1, 11):
                payload = encode(dataclasses.replace(content, version=version))
                verdict = await session.push_map(version, payload, 10.0)
                assert verdict.applied and verdict.version == version
            assert session.closed_because is None  # one session throughout
            internal = cnc.server._internal  # type: ignore[attr-defined]
            assert internal.busy_answers >= 30 and mem.busy_retries >= internal.busy_answers - 2
            # shown, not hidden: the link connected with reason busy, what was answered
            busy = [text for reason, text in told if reason == "busy"]
            assert busy and "BadResourceUnavailable" in busy[0], told
        finally:
            session.abort(None, "test over")
            await runner


async def test_a_controller_offering_no_security_is_refused_unless_the_link_allows_it(
        ) -> None:
    async with controller(security_modes=("None",)) as cnc:
        url = f"opc.tcp://127.0.0.1:{cnc.server.port}"
        with pytest.raises(LinkError, match=r"does not offer Basic256Sha256 SignAndEncrypt "
                                            r"\(it offers None None\)"):
            await OpcuaMemory.from_link(link(url)).connect()
        plain = OpcuaMemory.from_link(link(url, security_policy="None"))
        await plain.connect()
        try:
            assert await plain.read(0, 4) == b"EDCM"
        finally:
            await plain.close()


async def test_a_server_that_does_not_resolve_the_path_is_named_as_such() -> None:
    async with controller(db=901) as cnc:  # the window in another data block
        mem = OpcuaMemory.from_link(link(f"opc.tcp://127.0.0.1:{cnc.server.port}"))
        await mem.connect()
        try:
            with pytest.raises(LinkError, match=r"DB900 bytes 0\.\.63: no such node .*does "
                                                r"not resolve the path.*BadNodeIdUnknown"):
                await mem.read(0, 64)
        finally:
            await mem.close()


def test_the_simulated_controllers_keep_one_certificate(tmp_path: Path) -> None:
    from cryptography import x509
    from cryptography.hazmat.primitives import serialization

    from machine_sim.opcua_server import sim_certificate

    der, pem = sim_certificate(tmp_path / "sim")
    assert (tmp_path / "sim" / "server.pem").exists()
    sim_certificate.cache_clear()  # another process: reads the same back
    assert sim_certificate(tmp_path / "sim") == (der, pem)
    key = serialization.load_pem_private_key(pem, None)
    public = serialization.Encoding.DER, serialization.PublicFormat.SubjectPublicKeyInfo
    assert key.public_key().public_bytes(*public) == \
        x509.load_der_x509_certificate(der).public_key().public_bytes(*public)


async def test_each_failure_says_its_state_and_reason(tmp_path: Path) -> None:
    """The classification the link state shows (server/links/state.py), given where the
    failure is known."""
    users = {**USERS, "viewer": OpcuaUser("view-pw", frozenset({"SinuReadAll"}))}
    m = spec("vmc-06").machine
    async with WindowCNC(m, sinumerik_server(users), cycle_s=0.02) as cnc:
        url = f"opc.tcp://127.0.0.1:{cnc.server.port}"

        async def failure(mem: OpcuaMemory, *, write: bool = False) -> tuple[str, str]:
            with pytest.raises(LinkError) as err:
                await mem.connect()
                try:
                    if write:
                        await mem.write(256, b"\x00\x01")
                finally:
                    await mem.close()
            return err.value.state, err.value.reason

        wrong = OpcuaMemory(url, "ednc", "env:OPCUA_SEC_PW", password="not-it")
        assert await failure(wrong) == ("refused", "login")
        unset = OpcuaMemory(url, "ednc", "env:OPCUA_UNSET_PW")
        assert await failure(unset) == ("refused", "password_ref")
        viewer = OpcuaMemory(url, "viewer", "env:X", password="view-pw")
        assert await failure(viewer, write=True) == ("refused", "rights")
        nobody = OpcuaMemory("opc.tcp://127.0.0.1:9", "ednc", "env:OPCUA_SEC_PW",
                             timeout_s=2.0)
        assert await failure(nobody) == ("unreachable", "connect")
    async with controller(security_modes=("None",)) as cnc:
        only_none = OpcuaMemory(f"opc.tcp://127.0.0.1:{cnc.server.port}", "ednc",
                                "env:OPCUA_SEC_PW")
        assert await failure(only_none) == ("refused", "security")
