"""EDNC_MACHINES_FILE: the plant's machines registered at start-up, from the fleet file."""

from __future__ import annotations

from pathlib import Path

import httpx
import pytest
import yaml

from server.app import create_app
from server.bootstrap import MachinesFileError, read_machines_file
from server.settings import Settings

REPO = Path(__file__).resolve().parents[1]


async def _machines(settings: Settings) -> list[dict[str, object]]:
    app = create_app(settings)
    async with app.router.lifespan_context(app):
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://t") as client:
            reply = await client.get("/api/machines")
            assert reply.status_code == 200
            body: list[dict[str, object]] = reply.json()
            return body


async def test_the_deploy_fleet_file_registers_every_machine(tmp_path: Path) -> None:
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'c.db'}",
                        machines_file=REPO / "deploy" / "fleet.yaml")
    got = await _machines(settings)
    assert [m["name"] for m in got] == sorted(["vmc-01", "gantry-02", "hmc-03", "vmc-04",
                                                "5ax-05", "mill-06", "pmc-07",
                                                "sinumerik-08"])
    assert all("secret" not in m for m in got)
    assert {m["name"]: m["ip"] for m in got}["vmc-01"] == "172.30.0.11"


async def test_a_second_start_updates_instead_of_duplicating(tmp_path: Path) -> None:
    fleet = yaml.safe_load((REPO / "deploy" / "fleet.yaml").read_text())
    path = tmp_path / "fleet.yaml"
    path.write_text(yaml.safe_dump(fleet))
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'c.db'}", machines_file=path)
    await _machines(settings)
    fleet["machines"][0]["machine"]["tool_length_mm"] = 175.0
    path.write_text(yaml.safe_dump(fleet))
    got = await _machines(settings)
    assert len(got) == 8
    vmc = next(m for m in got if m["name"] == "vmc-01")
    assert isinstance(vmc["description"], dict)
    assert vmc["description"]["tool_length_mm"] == 175.0


@pytest.mark.parametrize(("edit", "message"), [
    (lambda f: f["machines"][1].pop("secret"), r"machines\[1\]\.secret"),
    (lambda f: f["machines"][2]["machine"].update(chain="w X X b Z t"), r"machines\[2\]"),
    (lambda f: f["machines"][0]["machine"].update(ip="300.1.1.1"), r"machines\[0\]\.ip"),
])
def test_a_bad_entry_is_named(tmp_path: Path, edit: object, message: str) -> None:
    fleet = yaml.safe_load((REPO / "deploy" / "fleet.yaml").read_text())
    assert callable(edit)
    edit(fleet)
    path = tmp_path / "fleet.yaml"
    path.write_text(yaml.safe_dump(fleet))
    with pytest.raises(MachinesFileError, match=message):
        read_machines_file(path)
