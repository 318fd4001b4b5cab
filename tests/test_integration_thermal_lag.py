"""A lagged thermal model, as ``ednc diagnose --out`` saves it, applied live (issue 15,
item 6): the center follows the lag state of the spindle sensor from the readings it
receives and sends it on (with a second sensor lagged at the same time constant, the lag
of their weighted sum as one state); the machine's map carries a record on it; the correction the
machine applies follows the model's drift over the readings' history, not the drift at
steady state. Over real TCP with simulated Fanuc-style (factored map) and Siemens-style
(tables map) machines, the readings posted through the REST API with their own times."""

from __future__ import annotations

import asyncio
import datetime as dt
from contextlib import AsyncExitStack
from pathlib import Path

import numpy as np
import pytest

from machine_sim.lookup import FactoredLadder, TablesMap
from tests.support.integration import (
    DEADLINE_S,
    THERMAL,
    THERMAL_TABLES,
    Spec,
    before_rounding,
    center,
    diagnosed_spindle,
    require_loopback_aliases,
    until,
    with_model,
)
from volumetric.model.lag import first_order_lag
from volumetric.model.model import DynamicThermalTerm, LagColumn, MachineModel

TAU_S = 600.0
LEVEL_UM_PER_K = 0.8
LAG_UM_PER_K = -3.0
COLUMN_LAG_UM_PER_K = 1.5
"""The column sensor's lag at the same time constant, in the mixed variant: the center
sends the two lags as one state, the lag of their weighted sum."""


def lagged(model: MachineModel, mixed: bool = False
           ) -> tuple[MachineModel, DynamicThermalTerm]:
    """``model``'s geometry with a lagged spindle drift along z instead of its static one
    (``mixed``: and the column sensor's lag of the same time constant)."""
    columns = [
        LagColumn("level", "T_spindle_C", 0.0, LEVEL_UM_PER_K, input_C=20.0),
        LagColumn("lag", "T_spindle_C", TAU_S, LAG_UM_PER_K, state_C=20.0, input_C=20.0)]
    if mixed:
        columns.append(LagColumn("lag", "T_column_C", TAU_S, COLUMN_LAG_UM_PER_K,
                                 state_C=20.0, input_C=20.0))
    term = DynamicThermalTerm("z", 0.4, tuple(columns))
    return MachineModel(model.machine, model.geometry, (term,), model.info), term


@pytest.mark.parametrize(("spec", "mixed"), [(THERMAL, False), (THERMAL_TABLES, False),
                                             (THERMAL, True)],
                         ids=["fanuc", "siemens", "fanuc-two-sensors"])
async def test_a_lagged_thermal_model_is_applied_with_its_history(tmp_path: Path,
                                                                 spec: Spec,
                                                                 mixed: bool) -> None:
    """Fanuc-style: a factored map, corrections compared before the ladder's rounding.
    Siemens-style: a tables map evaluated by the machine (its sensors not on its PLC
    here, so that the readings' times are the test's). Two sensors: the spindle's and
    the column's lags of one time constant, sent as one state (each sensor's lag stepped
    on its own readings, summed with the weights)."""
    require_loopback_aliases()
    base, _ = await asyncio.to_thread(diagnosed_spindle, THERMAL)
    model, term = lagged(MachineModel(spec.name, base.geometry, (), base.info), mixed)
    name = spec.name
    m = spec.machine
    ref = np.array([[0.5 * (a.travel[0] + a.travel[1]) for a in m.axes]])
    z = m.axis_names.index("Z")
    # readings a minute apart, in the past: the lag runs on the readings' own times
    start = dt.datetime.now(dt.UTC) - dt.timedelta(hours=1)
    t_s = np.arange(8) * 60.0
    celsius = np.array([20.0, 21.0, 22.0, 23.0, 23.0, 23.0, 23.0, 23.0])
    column = np.array([20.0, 20.0, 20.5, 20.5, 21.0, 21.5, 21.5, 21.5])
    temps = {"T_spindle_C": celsius} | ({"T_column_C": column} if mixed else {})
    # what the center must send: each sensor's lag from rest at the first reading, the
    # two summed with weights 3/4.5 and 1.5/4.5 (signs of the coefficients) about 20 °C
    lags = {c: first_order_lag(t_s, x, TAU_S) for c, x in temps.items()}
    if mixed:
        k = abs(LAG_UM_PER_K) + abs(COLUMN_LAG_UM_PER_K)
        want = 20.0 + (LAG_UM_PER_K * (lags["T_spindle_C"] - 20.0)
                       + COLUMN_LAG_UM_PER_K * (lags["T_column_C"] - 20.0)) / k
    else:
        want = lags["T_spindle_C"]
    applied: list[float] = []
    lag_sent: list[float] = []
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        # built without temperatures: the map carries them
        sim = await with_model(stack, plant, spec, model, own_sensors=False)
        ctl = sim.runtime.controller
        store = ctl.store
        kind = FactoredLadder if spec is THERMAL else TablesMap
        assert isinstance(store.active, kind)
        sensors = {r.sensor for r in store.active.payload.thermal}
        assert sensors == {"spindle", "lag1"}, sensors  # as the Temperatures carry them
        for k in range(len(t_s)):
            when = start + dt.timedelta(seconds=float(t_s[k]))
            r = await plant.client.post(f"/api/machines/{name}/temperatures", json={
                "readings": [{"sensor": c[2:-2], "celsius": float(x[k]),
                              "time": when.isoformat()} for c, x in temps.items()]})
            assert r.status_code == 200, r.text
            assert all(v["accepted"] for v in r.json()["verdicts"]), r.text

            def holds(k: int = k) -> bool:
                have = ctl.temperatures.values()
                return bool(abs(have.get("T_spindle_C", -1e9) - celsius[k]) < 1e-9
                            and abs(have.get("T_lag1_C", -1e9) - want[k]) < 1e-9)

            await until(holds)
            lag_sent.append(ctl.temperatures.values()["T_lag1_C"])
            await asyncio.sleep(0.1)  # a few ladder cycles: the next one folds it in
            active = store.active
            at = ref if isinstance(active, TablesMap) else ref[:, [
                m.axis_names.index(a) for a in active.inputs]]
            applied.append(float(before_rounding(active, at)[0, z]) * 1e3)
        assert store.version == 1  # one map; the history moved only its thermal part
        # the dashboard says what the center's own sensor stands for
        card = (await plant.client.get(f"/api/machines/{name}/dashboard")).json()["card"]
        (shown,) = [t for t in card["temperatures"] if t["name"] == "lag1"]
        assert shown["source"] == "lag"
        assert shown["follows"] == ("a weighted sum of 2 sensors through a 10 min lag" if mixed
                                    else "T_spindle_C through a 10 min lag")
    # what the saved model gives over the same readings, from rest at the first
    drift = term.series(t_s, temps)
    if not mixed:
        lag = (drift - term.intercept_um - LEVEL_UM_PER_K * celsius) / LAG_UM_PER_K
        np.testing.assert_allclose(lag_sent, lag, rtol=0, atol=1e-9)
    moved = np.array(applied) - applied[0]
    expected = -(drift - drift[0])  # the correction opposes the drift
    steady = -(LEVEL_UM_PER_K + LAG_UM_PER_K) * (celsius - celsius[0])
    if mixed:
        steady -= COLUMN_LAG_UM_PER_K * (column - column[0])
    print(f"\nz correction moved {moved.round(3)} µm; the lagged model "
          f"{expected.round(3)}; at steady state it would be {steady.round(3)}")
    assert np.max(np.abs(expected - steady)) > 1.0  # the history matters here
    # factored: the ladder's fixed point (protocol/README.md section 6: each temperature in
    # m°C, so up to 0.5 mK times each coefficient, and its constants in 2^-16 counts);
    # tables: as the machine computes it (float32 tables)
    fixed = 5e-4 * (abs(LEVEL_UM_PER_K) + abs(LAG_UM_PER_K) + abs(COLUMN_LAG_UM_PER_K)) \
        + 2.0**-14
    np.testing.assert_allclose(moved, expected, rtol=0, atol=fixed if spec is THERMAL else 0.01)
