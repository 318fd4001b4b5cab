"""The OPC UA link over real loopback sockets, asyncua on both sides.

A Siemens-style simulated machine serves its window (PLC data block 900) and NC data
through a SINUMERIK-shaped OPC UA server (machine_sim/opcua_server.py); the center reaches
it through :class:`~server.links.opcua.OpcuaMemory`. Checked: the server's limits
(login, rights per user, 10 sessions, 100 ms), a map written with
:func:`protocol.ctrlmem.plan_map_write` applied exactly as the EDNC path applies it, and
faults (the connection dropped after every write, a corrupted buffer).
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
from collections.abc import AsyncIterator
from pathlib import Path

import numpy as np
import pytest
from asyncua import ua
from asyncua.client.client import Client
from asyncua.crypto.cert_gen import setup_self_signed_certificate
from cryptography.x509.oid import ExtendedKeyUsageOID

from machine_sim.lookup import active_map
from machine_sim.opcua_server import PLC_WRITER, READER, OpcuaUser, sinumerik_server
from machine_sim.runtime import MachineRuntime
from machine_sim.siemens import SD_ABS_VALUE, SiemensNC
from machine_sim.windowcnc import WindowCNC
from protocol import Controller, MapEncoding
from protocol.ctrlmem import STATUS_AT, STATUS_SIZE, Layout, decode_status, plan_map_write
from protocol.maptables import decode_payload
from server.links.opcua import OpcuaMemory
from server.links.secret import read_secret
from server.links.window.memory import LinkError
from server.links.window.session import ControllerSession
from server.mapcodec import encode, with_version
from server.push.adapter import build_for
from server.schemas.link import OpcuaLink
from tests.support.integration import campaign, spec
from volumetric.identify.fit import fit

pytestmark = pytest.mark.timeout(300)

VMC = "vmc-06"  # Siemens-style 3-axis machine of the test fleet
USERS = {"ednc": OpcuaUser("plc-pw", PLC_WRITER), "viewer": OpcuaUser("view-pw", READER),
         "setter": OpcuaUser("sea-pw", frozenset({"SinuReadAll", "SeaWrite"}))}


@functools.cache
def payloads() -> tuple[bytes, bytes]:
    """Two map versions of the machine as the center builds them for a Siemens-style PLC
    (v1 of its fitted model, v2 the same map under version 2)."""
    sim, readings, _ = campaign(VMC)
    model = fit(sim.machine, readings).model
    s = spec(VMC)
    formats = MapEncoding.FLOAT32_MM | MapEncoding.TABLES
    built = build_for(s.description, "siemens", model.to_json(), {}, 1.0, formats)
    one = encode(with_version(built, 1))
    two = encode(with_version(built, 2))
    return one, two


@functools.cache
def coarse_payload() -> bytes:
    """Version 2 of the machine's map, built at 4 µm instead of 1 µm (other tables)."""
    sim, readings, _ = campaign(VMC)
    model = fit(sim.machine, readings).model
    formats = MapEncoding.FLOAT32_MM | MapEncoding.TABLES
    built = build_for(spec(VMC).description, "siemens", model.to_json(), {}, 4.0, formats)
    return encode(with_version(built, 2))


@contextlib.asynccontextmanager
async def machine() -> AsyncIterator[WindowCNC]:
    m = spec(VMC).machine
    async with WindowCNC(m, sinumerik_server(USERS), runtime=MachineRuntime(m, seed=1),
                         cycle_s=0.01) as cnc:
        yield cnc


def memory(cnc: WindowCNC, user: str = "ednc", env: str = "OPCUA_TEST_PW") -> OpcuaMemory:
    return OpcuaMemory(f"opc.tcp://127.0.0.1:{cnc.server.port}", user, f"env:{env}",
                       timeout_s=5.0)


@pytest.fixture(autouse=True)
def passwords(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("EDNC_OPCUA_PKI_DIR", str(tmp_path / "pki"))  # the center's own
    monkeypatch.setenv("OPCUA_TEST_PW", "plc-pw")
    monkeypatch.setenv("OPCUA_VIEW_PW", "view-pw")
    monkeypatch.setenv("OPCUA_SEA_PW", "sea-pw")
    monkeypatch.setenv("OPCUA_WRONG_PW", "not-it")


def status(cnc: WindowCNC):  # type: ignore[no-untyped-def]
    return decode_status(cnc.window[STATUS_AT:STATUS_AT + STATUS_SIZE])


async def until(check: object, timeout_s: float = 20.0) -> None:
    async with asyncio.timeout(timeout_s):
        while not check():  # type: ignore[operator]
            await asyncio.sleep(0.01)


async def push(mem: OpcuaMemory, cnc: WindowCNC, payload: bytes, version: int) -> None:
    """Write ``payload`` into the inactive buffer and switch, as the center does."""
    st = status(cnc)
    target = 2 if st.active == 1 else 1
    for w in plan_map_write(Layout(cnc.layout.capacity), target, payload, version,
                            st.ack_seq + 1, block=mem.block):
        await mem.write(w.offset, w.data)
    await until(lambda: status(cnc).ack_seq == st.ack_seq + 1)


def raw_client(cnc: WindowCNC, user: str | None = None, password: str | None = None
               ) -> Client:
    c = Client(f"opc.tcp://127.0.0.1:{cnc.server.port}", timeout=5)
    if user is not None:
        c.set_user(user)
        c.set_password(password or "")
    return c


def test_one_secret_reader_for_both_opcua_links_keeps_a_password_s_spaces(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # the window link and the native SINUMERIK link read a password_ref through one
    # function: a file's line break goes, its spaces stay (they may be the password's)
    (tmp_path / "pw").write_text(" two words \n", encoding="utf-8")
    assert read_secret(f"file:{tmp_path}/pw") == " two words "
    monkeypatch.setenv("EDNC_TEST_SECRET", " x ")
    assert read_secret("env:EDNC_TEST_SECRET") == " x "
    with pytest.raises(LinkError, match="password of OPC UA user 'u': environment variable "
                                        "EDNC_UNSET_SECRET is not set") as err:
        read_secret("env:EDNC_UNSET_SECRET", "OPC UA user 'u'")
    assert err.value.reason == "password_ref"
    with pytest.raises(LinkError, match="neither env:NAME nor file:/path"):
        read_secret("vault:x")


async def test_login_needs_a_known_user_and_password_and_anonymous_reads_nothing(
        tmp_path: Path) -> None:
    async with machine() as cnc:
        with pytest.raises(LinkError, match=r"login as 'ednc' refused.*wrong user or password"):
            await memory(cnc, env="OPCUA_WRONG_PW").connect()
        with pytest.raises(LinkError, match="login as 'nobody' refused"):
            await memory(cnc, user="nobody").connect()
        with pytest.raises(LinkError, match="environment variable OPCUA_UNSET_PW is not set"):
            await memory(cnc, env="OPCUA_UNSET_PW").connect()
        missing = OpcuaMemory(f"opc.tcp://127.0.0.1:{cnc.server.port}", "ednc",
                              f"file:{tmp_path}/none")
        with pytest.raises(LinkError, match=r"cannot read .*/none"):
            await missing.connect()
        nobody_there = OpcuaMemory("opc.tcp://127.0.0.1:9", "ednc", "env:OPCUA_TEST_PW",
                                   timeout_s=2.0)
        with pytest.raises(LinkError, match="cannot connect"):
            await nobody_there.connect()
        with pytest.raises(LinkError, match="not connected"):
            await nobody_there.read(0, 4)
        (tmp_path / "pw").write_text("plc-pw\n")
        from_file = OpcuaMemory(f"opc.tcp://127.0.0.1:{cnc.server.port}", "ednc",
                                f"file:{tmp_path}/pw")
        await from_file.connect()
        assert (await from_file.read(0, 4)) == b"EDCM"
        await from_file.close()
        anonymous = raw_client(cnc)
        await anonymous.connect()
        try:
            for path in ("/Plc/DB900.DBD0:[1]", "/Channel/MachineAxis/actToolBasePos[u1,1]"):
                with pytest.raises(ua.UaStatusCodeError) as err:
                    await anonymous.get_node(f"ns=2;s={path}").read_value()
                assert err.value.code == ua.StatusCodes.BadUserAccessDenied
        finally:
            await anonymous.disconnect()


async def test_rights_per_user_and_nodes_outside_the_window_are_refused() -> None:
    async with machine() as cnc:
        viewer = memory(cnc, user="viewer", env="OPCUA_VIEW_PW")
        await viewer.connect()
        try:
            assert (await viewer.read(0, 4)) == b"EDCM"
            before = bytes(cnc.window[192:194])
            with pytest.raises(LinkError, match="user 'viewer' lacks PlcWrite"):
                await viewer.write(192, b"\x05\x00")
            assert bytes(cnc.window[192:194]) == before
        finally:
            await viewer.close()
        ednc = memory(cnc)
        await ednc.connect()
        try:
            size = len(cnc.window)
            with pytest.raises(LinkError, match="BadOutOfRange"):
                await ednc.write(size - 4, bytes(8))
            with pytest.raises(LinkError, match="BadOutOfRange"):
                await ednc.read(size - 2, 4)
            await ednc.write(size - 6, b"\x01\x02\x03\x04\x05\x06")  # word, dword edges
            assert bytes(cnc.window[size - 6:]) == b"\x01\x02\x03\x04\x05\x06"
            assert await ednc.read(size - 6, 6) == b"\x01\x02\x03\x04\x05\x06"
            with pytest.raises(LinkError, match="at most 240"):  # an S7-300's PDU
                await ednc.write(512, bytes(244))
        finally:
            await ednc.close()
        c = raw_client(cnc, "ednc", "plc-pw")
        await c.connect()
        try:
            async def refused(path: str, value: ua.Variant, code: int,
                              index_range: str | None = None) -> None:
                wv = ua.WriteValue(NodeId=ua.NodeId.from_string(f"ns=2;s={path}"),
                                   AttributeId=ua.AttributeIds.Value,
                                   Value=ua.DataValue(value), IndexRange=index_range)
                params = ua.WriteParameters(NodesToWrite=[wv])
                (got,) = await c.uaclient.write(params)
                assert got.value == code, (path, got)

            u32 = ua.VariantType.UInt32
            await refused("/Plc/DB901.DBD0:[1]", ua.Variant([1], u32),
                          ua.StatusCodes.BadNodeIdUnknown)
            await refused("/Plc/DB900.DBD0:[2]", ua.Variant([1], u32),
                          ua.StatusCodes.BadTypeMismatch)
            await refused("/Plc/DB900.DBW0:[1]", ua.Variant([1 << 16], u32),
                          ua.StatusCodes.BadOutOfRange)
            await refused("/Plc/DB900.DBD0:[4]", ua.Variant([1], u32),
                          ua.StatusCodes.BadIndexRangeInvalid, "0:0")
            # a PLC writer has no SeaWrite; positions are never writable
            sd = "/NC/_N_AX_SEA_ACX/$SA_TEMP_COMP_ABS_VALUE[u1]"
            dbl = ua.Variant(0.01, ua.VariantType.Double)
            await refused(sd, dbl, ua.StatusCodes.BadUserAccessDenied)
            await refused("/Channel/MachineAxis/actToolBasePos[u1,1]", dbl,
                          ua.StatusCodes.BadNotWritable)
        finally:
            await c.disconnect()
        setter = raw_client(cnc, "setter", "sea-pw")
        await setter.connect()
        try:
            cnc.stop_plc()  # the PLC's own SD43900 writes would overwrite ours
            node = setter.get_node("ns=2;s=/NC/_N_AX_SEA_ACX/$SA_TEMP_COMP_ABS_VALUE[u2]")
            await node.write_value(ua.Variant(0.0123, ua.VariantType.Double))
            nc = cnc.runtime.controller
            assert isinstance(nc, SiemensNC)
            assert nc.read_sd(SD_ABS_VALUE, m_axis(cnc, 1)) == 0.0123
            assert await node.read_value() == 0.0123
            with pytest.raises(ua.UaStatusCodeError) as err:  # past SD43900's ±0.5 mm
                await node.write_value(ua.Variant(0.9, ua.VariantType.Double))
            assert err.value.code == ua.StatusCodes.BadOutOfRange
        finally:
            await setter.disconnect()


def m_axis(cnc: WindowCNC, j: int) -> str:
    return cnc.machine.axis_names[j]


async def test_an_eleventh_session_is_refused_and_subscriptions_sample_no_faster_than_100ms(
        ) -> None:
    async with machine() as cnc:
        mems = [memory(cnc) for _ in range(10)]
        try:
            for m in mems:
                await m.connect()
            extra = memory(cnc)
            with pytest.raises(LinkError, match=r"no free OPC UA session.*BadTooManySessions"):
                await extra.connect()
            await mems[0].close()
            await extra.connect()  # a session freed is a session to take
            await extra.close()
        finally:
            for m in mems:
                await m.close()
        c = raw_client(cnc, "viewer", "view-pw")
        await c.connect()
        try:
            sub = await c.create_subscription(10, None)
            assert sub.parameters.RequestedPublishingInterval == 100.0  # revised, not 10
            params = ua.MonitoringParameters(ClientHandle=1, SamplingInterval=5.0,
                                             QueueSize=1)
            item = ua.MonitoredItemCreateRequest(
                ItemToMonitor=ua.ReadValueId(NodeId=ua.NodeId.from_string(
                    "ns=2;s=/Channel/MachineAxis/actToolBasePos[u1,1]"),
                    AttributeId=ua.AttributeIds.Value),
                MonitoringMode=ua.MonitoringMode.Reporting, RequestedParameters=params)
            (result,) = await c.uaclient.create_monitored_items(
                ua.CreateMonitoredItemsParameters(
                    SubscriptionId=sub.subscription_id, ItemsToCreate=[item],
                    TimestampsToReturn=ua.TimestampsToReturn.Both))
            assert result.StatusCode.is_good(), result
            assert result.RevisedSamplingInterval >= 100.0
            # the moving axis is sampled: new positions arrive (asyncua's own subscription
            # object, which dispatches them, is not used above; a second one is)
            seen: list[float] = []

            class Handler:
                def datachange_notification(self, node: object, val: float,
                                            data: object) -> None:
                    seen.append(val)

            sub2 = await c.create_subscription(10, Handler())
            await sub2.subscribe_data_change(c.get_node(
                "ns=2;s=/Channel/MachineAxis/actToolBasePos[u1,1]"))
            await until(lambda: len(set(seen)) >= 3, 10.0)
            assert len(set(seen)) >= 3
        finally:
            await c.disconnect()


async def test_a_map_written_over_opcua_is_applied_as_the_ednc_path_applies_it() -> None:
    p1, _ = payloads()
    async with machine() as cnc:
        mem = memory(cnc)
        await mem.connect()
        try:
            await push(mem, cnc, p1, 1)
            st = status(cnc)
            assert st.ack_code == 0 and st.applied_version == 1 and st.active in (1, 2)
            store = cnc.runtime.controller.store
            assert store.version == 1 and store.active is not None
            rng = np.random.default_rng(3)
            q = np.column_stack([rng.uniform(lo, hi, 50) for lo, hi in
                                 (a.travel for a in spec(VMC).machine.axes)])
            expected = active_map(decode_payload(p1)).lookup(q)
            assert np.abs(expected).max() > 1e-4  # the map corrects something
            np.testing.assert_array_equal(store.active.lookup(q), expected)
            # telemetry helper: positions and setting data as the NC holds them
            nc = cnc.runtime.controller
            assert isinstance(nc, SiemensNC)
            await until(lambda: bool(np.any(nc.sd[SD_ABS_VALUE] != 0.0)))  # the PLC's
            cnc.stop_plc()
            axes = await mem.read_axes(cnc.machine.axis_names)
            for j, a in enumerate(cnc.machine.axis_names):
                assert axes[a].position_mm == float(cnc.runtime.positions[j])
                assert axes[a].sd43900_mm == nc.read_sd(SD_ABS_VALUE, a)
            assert any(r.sd43900_mm != 0.0 for r in axes.values())
        finally:
            await mem.close()


async def test_the_controller_session_pushes_over_opcua_built_from_the_link() -> None:
    p1, p2 = payloads()
    async with machine() as cnc:
        link = OpcuaLink(kind="opcua", endpoint=f"opc.tcp://127.0.0.1:{cnc.server.port}",
                         user="ednc", password_ref="env:OPCUA_UNSET_PW")
        m = cnc.machine
        # the center resolved the reference itself (server/links/window/service.py)
        mem = OpcuaMemory.from_spec(link, password="plc-pw")
        s = ControllerSession(m.name, "127.0.0.1", Controller.SIEMENS, m.axis_names, mem,
                              link="opcua", chain=m.chain, poll_s=0.1)
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            assert (await s.push_map(1, p1, 30.0)).applied
            assert (await s.push_map(2, p2, 30.0)).applied
            assert cnc.runtime.controller.store.version == 2
        finally:
            s.abort(None, "test over")
            await runner


async def test_a_connection_dropped_after_any_write_leaves_the_last_good_map() -> None:
    """Writes 0..k-1 of a push delivered (and again in reverse), then the connection cut
    without CloseSession, for every k: the PLC keeps map 1 and acknowledges nothing."""
    p1, p2 = payloads()
    async with machine() as cnc:
        mem = memory(cnc)
        await mem.connect()
        await push(mem, cnc, p1, 1)
        await mem.close()
        store = cnc.runtime.controller.store
        st = status(cnc)
        target = 2 if st.active == 1 else 1
        writes = plan_map_write(Layout(cnc.layout.capacity), target, p2, 2, st.ack_seq + 1,
                                block=mem.block)
        assert len(writes) >= 5
        for k in range(len(writes)):  # the connection lost after write k-1, every k
            await mem.connect()
            for w in writes[:k]:
                await mem.write(w.offset, w.data)
            for w in reversed(writes[:k]):  # repeated, out of order: still no switch
                await mem.write(w.offset, w.data)
            client = mem._client
            assert client is not None
            client.disconnect_socket()  # dropped, no CloseSession
            with pytest.raises(LinkError, match=r"connection lost|no answer|not connected"):
                await mem.write(writes[k].offset, writes[k].data)
            await mem.close()
            await asyncio.sleep(0.05)  # several scans
            assert store.version == 1 and status(cnc).ack_seq == st.ack_seq, k
        await mem.connect()  # the center comes back and delivers the whole map
        try:
            await push(mem, cnc, p2, 2)
            assert status(cnc).ack_code == 0 and store.version == 2
        finally:
            await mem.close()


async def test_a_corrupted_buffer_is_refused_and_the_old_map_kept() -> None:
    p1, p2 = payloads()
    async with machine() as cnc:
        mem = memory(cnc)
        await mem.connect()
        try:
            await push(mem, cnc, p1, 1)
            st = status(cnc)
            target = 2 if st.active == 1 else 1
            writes = plan_map_write(Layout(cnc.layout.capacity), target, p2, 2,
                                    st.ack_seq + 1, block=mem.block)
            for w in writes[:-1]:
                await mem.write(w.offset, w.data)
            # one payload byte flipped after the header (and its CRC) went in
            at = writes[1].offset + len(p2) // 2 // 4 * 4
            word = bytearray(await mem.read(at, 4))
            word[1] ^= 0x40
            await mem.write(at, bytes(word))
            await mem.write(writes[-1].offset, writes[-1].data)
            await until(lambda: status(cnc).ack_seq == st.ack_seq + 1)
            after = status(cnc)
            assert after.ack_code == 4  # CHECKSUM_MISMATCH
            assert after.active == st.active and after.applied_version == 1
            assert cnc.runtime.controller.store.version == 1
        finally:
            await mem.close()


async def certificate(tmp_path: Path, who: str, uri: str) -> tuple[Path, Path]:
    key, cert = tmp_path / f"{who}-key.pem", tmp_path / f"{who}-cert.der"
    use = [ExtendedKeyUsageOID.CLIENT_AUTH, ExtendedKeyUsageOID.SERVER_AUTH]
    await setup_self_signed_certificate(key, cert, uri, "localhost", use, {"commonName": who})
    return cert, key


async def test_basic256sha256_sign_and_encrypt_carries_the_window(tmp_path: Path) -> None:
    """Only a trusted client certificate gets a session; the window over an encrypted
    channel reads and writes as over None."""
    server_cert, server_key = await certificate(tmp_path, "server",
                                                "urn:freeopcua:python:server")
    client_cert, client_key = await certificate(tmp_path, "center",
                                                "urn:example.org:FreeOpcUa:opcua-asyncio")
    stranger_cert, stranger_key = await certificate(tmp_path, "stranger",
                                                    "urn:example.org:FreeOpcUa:opcua-asyncio")
    m = spec(VMC).machine
    factory = sinumerik_server(USERS, certificate=server_cert, private_key=server_key,
                               trusted_clients=[client_cert])
    async with WindowCNC(m, factory, runtime=MachineRuntime(m, seed=1), cycle_s=0.01) as cnc:
        url = f"opc.tcp://127.0.0.1:{cnc.server.port}"
        stranger = OpcuaMemory(url, "ednc", "env:OPCUA_TEST_PW",
                               security_policy="Basic256Sha256", security_mode="Sign",
                               client_certificate=str(stranger_cert),
                               client_private_key=str(stranger_key))
        with pytest.raises(LinkError, match="does not trust the center's certificate"):
            await stranger.connect()
        own = OpcuaMemory(url, "ednc", "env:OPCUA_TEST_PW")  # the center's own, untrusted
        with pytest.raises(LinkError, match="does not trust the center's certificate"):
            await own.connect()
        link = OpcuaLink(kind="opcua", endpoint=url, user="ednc",
                         password_ref="env:OPCUA_TEST_PW", security_policy="Basic256Sha256",
                         security_mode="SignAndEncrypt", client_certificate=str(client_cert),
                         client_private_key=str(client_key))
        mem = OpcuaMemory.from_link(link)
        await mem.connect()
        try:
            client = mem._client
            assert client is not None
            assert client.security_policy.Mode == ua.MessageSecurityMode.SignAndEncrypt
            assert await mem.read(0, 4) == b"EDCM"
            await mem.write(256, b"\x11\x22\x33\x44")
            assert bytes(cnc.window[256:260]) == b"\x11\x22\x33\x44"
        finally:
            await mem.close()


async def test_servers_in_one_process_share_no_node() -> None:
    """The standard address space is built once per process and copied per server on
    first touch: each server sees its own Sinumerik folder once, and nothing of another's."""
    m = spec(VMC).machine
    other = spec("5ax-04").machine  # five axes beside vmc-06's three
    async with (WindowCNC(m, sinumerik_server(USERS), cycle_s=0.01) as a,
                WindowCNC(other, sinumerik_server(USERS), cycle_s=0.01) as b):
        # a standard node changed in one server stays as it was in the other
        level = ua.NodeId(ua.ObjectIds.Server_ServiceLevel)
        sa, sb = a.server.server, b.server.server  # type: ignore[attr-defined]
        await sa.write_attribute_value(level, ua.DataValue(ua.Variant(7, ua.VariantType.Byte)))
        assert sb.read_attribute_value(level).Value.Value == 255
        assert sa.read_attribute_value(level).Value.Value == 7
        for cnc in (a, b):
            c = raw_client(cnc, "viewer", "view-pw")
            await c.connect()
            try:
                names = [n.Name for n in [await x.read_browse_name()
                                          for x in await c.nodes.objects.get_children()]]
                assert names.count("Sinumerik") == 1, names
                ns = await c.get_namespace_array()
                assert ns.index("urn:ednc:sim:sinumerik") == 2
                axes = await c.get_node("ns=2;s=/Sinumerik/Channel/MachineAxis").get_children()
                got = sorted([await x.read_value() for x in axes
                              if (await x.read_browse_name()).Name.startswith("name")])
                assert got == sorted(cnc.machine.axis_names), got
            finally:
                await c.disconnect()


async def test_an_idle_session_is_closed_after_the_session_timeout() -> None:
    m = spec(VMC).machine
    async with WindowCNC(m, sinumerik_server(USERS, session_timeout_s=5.0),
                         cycle_s=0.01) as cnc:
        idle = Client(f"opc.tcp://127.0.0.1:{cnc.server.port}", timeout=5,
                      watchdog_intervall=600.0)  # no keep-alive reads of its own
        idle.set_user("viewer")
        idle.set_password("view-pw")
        await idle.connect()
        assert idle.session_timeout == 5_000  # revised to the server's
        busy = memory(cnc)
        await busy.connect()
        try:
            node = idle.get_node("ns=2;s=/Plc/DB900.DBD0:[1]")
            assert await node.read_value() == [int.from_bytes(b"EDCM", "big")]
            for _ in range(8):  # 8 s: the busy session reads, the idle one does not
                await asyncio.sleep(1.0)
                assert await busy.read(0, 4) == b"EDCM"
            with pytest.raises(ua.UaStatusCodeError) as err:
                await node.read_value()
            assert err.value.code in (ua.StatusCodes.BadSessionIdInvalid,
                                      ua.StatusCodes.BadSessionClosed,
                                      ua.StatusCodes.BadSessionNotActivated), err.value
        finally:
            await busy.close()
            idle.disconnect_socket()


async def test_two_centers_writing_at_once_never_give_a_mixed_map() -> None:
    p1, _ = payloads()
    other = coarse_payload()  # version 2, other values everywhere
    rng = np.random.default_rng(5)
    q = np.column_stack([rng.uniform(lo, hi, 20) for lo, hi in
                         (a.travel for a in spec(VMC).machine.axes)])
    good = [active_map(decode_payload(p)).lookup(q) for p in (p1, other)]
    assert not np.allclose(good[0], good[1])
    async with machine() as cnc:
        m = cnc.machine
        for _round in range(3):
            a, b = (ControllerSession(m.name, "127.0.0.1", Controller.SIEMENS, m.axis_names,
                                      memory(cnc), link="opcua", chain=m.chain, poll_s=0.1)
                    for _ in range(2))
            await a.open()
            await b.open()
            runs = [asyncio.create_task(a.run()), asyncio.create_task(b.run())]
            verdicts = await asyncio.gather(a.push_map(1, p1, 30.0),
                                            b.push_map(2, other, 30.0),
                                            return_exceptions=True)
            for x in (a, b):
                x.abort(None, "round over")
            await asyncio.gather(*runs)
            active = cnc.runtime.controller.store.active
            if active is not None:
                got = active.lookup(q)
                assert any(np.array_equal(got, g) for g in good), "a mixed map applied"
            assert all(isinstance(v, Exception) or v.version in (1, 2) for v in verdicts)
