"""``ednc discover`` on loopback: a Fanuc-style PMC's Modbus window is found with the
machine it declares and the link to register; a closed port answers nothing; a Modbus
server without a window is named as such; a subnet too large is refused."""

from __future__ import annotations

import asyncio
import json

import pytest

from machine_sim.modbus_server import PmcModbusServer
from machine_sim.windowcnc import WindowCNC
from server.links.discover import discover, hosts_of
from tests.support.cli import ednc, one_line_error
from tests.support.integration import spec


async def test_a_modbus_window_is_found_with_its_machine_and_link() -> None:
    m = spec("gantry-02").machine
    async with WindowCNC(m, lambda c: PmcModbusServer(c, port=0, register=300),
                         cycle_s=0.01) as cnc:
        found = await discover(["127.0.0.1"], modbus_port=cnc.server.port, opcua_port=None,
                               ednc_port=None, register=300)
        assert len(found) == 1
        f = found[0]
        assert (f.kind, f.machine) == ("modbus", m.name)
        assert f.link == {"kind": "modbus", "host": "127.0.0.1", "port": cnc.server.port,
                          "start_register": 300, "byte_order": "little"}
        elsewhere = await discover(["127.0.0.1"], modbus_port=cnc.server.port,
                                   opcua_port=None, ednc_port=None, register=0)
        assert elsewhere[0].machine is None and "no EDNC window" in elsewhere[0].detail


async def test_nothing_answers_on_closed_ports() -> None:
    server = await asyncio.start_server(lambda r, w: None, "127.0.0.1", 0)
    port = server.sockets[0].getsockname()[1]
    server.close()
    await server.wait_closed()
    assert await discover(["127.0.0.1"], modbus_port=port, opcua_port=port,
                          ednc_port=port, timeout_s=0.3) == []


def test_the_cli_refuses_a_subnet_too_large_and_prints_json() -> None:
    assert "at most 4096" in one_line_error(ednc("discover", "--subnet", "127.0.0.0/8"))
    assert hosts_of("127.0.0.1/32") == ["127.0.0.1"]
    r = ednc("discover", "--subnet", "127.0.0.1/32", "--modbus-port", "1", "--opcua-port",
             "0", "--ednc-port", "0", "--json", "--timeout-ms", "200")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout) == []


@pytest.mark.parametrize("bad", ["10.0.0.0/33", "banana"])
def test_the_cli_refuses_a_bad_subnet(bad: str) -> None:
    assert "--subnet" in one_line_error(ednc("discover", "--subnet", bad))
