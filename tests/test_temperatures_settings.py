"""The temperature limits of issue 13 come from the settings (EDNC_TEMPERATURE_MAX_RATE,
EDNC_TEMPERATURE_JUMP, EDNC_TEMPERATURE_STALE_S) into the running services: the intake
refuses a jump the defaults would let through, and readings age to stale on the
configured time, on the board, in the MQTT status and on the dashboard."""

from __future__ import annotations

import asyncio
from pathlib import Path

from server.center import Center
from server.db import Database
from server.db import machines as machine_repo
from server.intake import TemperatureIntake
from server.services import machine_services
from server.settings import load_settings
from server.temperatures import TemperatureBoard
from tests.support.link import DEADLINE_S, SECRET, description


async def test_the_services_take_the_rate_and_stale_limits_from_the_settings(
        tmp_path: Path) -> None:
    settings = load_settings(database_url=f"sqlite:///{tmp_path / 'c.db'}",
                             machine_host="127.0.0.1", machine_port=0,
                             temperature_max_rate=0.05, temperature_jump=0.5,
                             temperature_stale_s=0.5)
    async with asyncio.timeout(DEADLINE_S), Database.open(settings.database_url) as db:
        center = Center(settings=settings, db=db)
        async with machine_services(center) as svc:
            await db.run(machine_repo.create_machine, name="vmc-01", ip="127.0.0.1",
                         controller="fanuc", secret=SECRET,
                         description={**description("vmc-01", "fanuc", "127.0.0.1"),
                                      "sensors": ["spindle"]})
            intake = svc.intake
            assert isinstance(intake, TemperatureIntake)
            assert (intake.max_rate_K_per_s, intake.jump_allowance_K) == (0.05, 0.5)
            assert svc.temperatures.stale_after_s == 0.5
            await intake.lookup("vmc-01")
            assert intake.take("vmc-01", "spindle", 20.0) is None
            refusal = intake.take("vmc-01", "spindle", 21.0)  # 1 K at once: 0.5 K allowed
            assert refusal is not None and refusal.reason == "too_fast"
            assert "allowed 0.5" in refusal.text
            assert intake.take("vmc-01", "spindle", 20.4) is None
            assert svc.temperatures.mark_stale() == 0
            await asyncio.sleep(0.55)
            assert svc.temperatures.mark_stale() == 1
            reading = svc.temperatures.readings("vmc-01")["T_spindle_C"]
            assert reading.stale and reading.celsius == 20.4  # the last good value kept


def test_an_argument_still_wins_over_the_settings(tmp_path: Path) -> None:
    settings = load_settings(database_url=f"sqlite:///{tmp_path / 'c.db'}",
                             temperature_max_rate=0.05, temperature_jump=0.5)
    center = Center(settings=settings, db=None)  # type: ignore[arg-type]  # not opened
    intake = TemperatureIntake(center, TemperatureBoard(), max_rate_K_per_s=2.0,
                               jump_allowance_K=0.0)
    assert (intake.max_rate_K_per_s, intake.jump_allowance_K) == (2.0, 0.0)
    default = TemperatureIntake(Center(settings=load_settings(
        database_url=f"sqlite:///{tmp_path / 'd.db'}"), db=None),  # type: ignore[arg-type]
        TemperatureBoard())
    assert (default.max_rate_K_per_s, default.jump_allowance_K) == (1.0, 10.0)


def test_the_mqtt_status_checks_staleness_at_half_a_short_limit(tmp_path: Path) -> None:
    from server.feed import Feed
    from server.mqtt import MqttBridge

    def bridge(stale_after_s: float) -> MqttBridge:
        center = Center(settings=load_settings(
            database_url=f"sqlite:///{tmp_path / 'c.db'}"), db=None)  # type: ignore[arg-type]
        return MqttBridge(center, Feed(center), TemperatureBoard(stale_after_s),
                          host="unused")

    assert bridge(2.0).stale_check_s == 1.0
    assert bridge(60.0).stale_check_s == 5.0
