"""Thermal terms as Siemens temperature compensation (machine_sim/siemens_thermal.py and
SiemensNC.write_temp_comp): the NC's settled correction along each axis equals minus the
terms' error there (µm → mm), with the slope in SD43910/SD43920 (MD32750 bit 1) or, with
bit 1 off, evaluated by the PLC; bit 0 gates the offset; MD32760 limits the rate."""

from __future__ import annotations

import numpy as np
import pytest

from machine_sim.siemens import (
    MD_TEMP_COMP_TYPE,
    SD_REF_POSITION,
    SD_SLOPE,
    SiemensAlarm,
    SiemensConfig,
    SiemensNC,
)
from machine_sim.siemens_thermal import TempCompData, temp_comp_data
from volumetric.model.model import ThermalTerm

TERMS = (
    ThermalTerm("thermal_drift", "z", "T_spindle_C", 1.5, 20.0),
    ThermalTerm("thermal_expansion", "x", "T_x_screw_C", 11.5, 20.0, q_min=0.0),
    ThermalTerm("thermal_expansion", "x", "T_bed_C", -4.0, 21.0, q_min=-100.0),
    ThermalTerm("thermal_drift", "x", "T_spindle_C", -0.4, 20.0),
    ThermalTerm("thermal_expansion", "y", "T_column_C", 8.0, 19.0, q_min=50.0),
)
TEMPS = {"T_spindle_C": 27.5, "T_x_screw_C": 24.0, "T_bed_C": 22.5, "T_column_C": 23.0}


def error_um(axis: str, q: float) -> float:
    """The terms' positioning error of ``axis`` at ``q``, µm, from the model's own
    components (not from the code under test)."""
    total = 0.0
    for t in TERMS:
        if t.axis == axis:
            c = t.component(TEMPS[t.sensor]).coefficients
            total += sum(ck * q ** k for k, ck in enumerate(c))
    return total


def test_setting_data_cancel_the_terms_along_each_axis() -> None:
    data = temp_comp_data(TERMS, TEMPS, ["X", "Y", "Z"])
    assert set(data) == {"X", "Y", "Z"}
    assert data["Z"].slope == 0.0 and not data["Z"].needs_slope
    assert data["X"].needs_slope and data["X"].ref_mm == 0.0  # the first term's q_min
    for axis in "xyz":
        for q in np.linspace(-300.0, 500.0, 17):
            correction_um = data[axis.upper()].correction_mm(float(q)) * 1000.0
            assert correction_um == pytest.approx(-error_um(axis, float(q)), abs=1e-9)
    assert abs(error_um("x", 500.0)) > 10.0  # the check is not trivially near zero


def test_missing_temperature_or_axis_is_an_error() -> None:
    with pytest.raises(ValueError, match="needs T_column_C"):
        temp_comp_data(TERMS, {k: v for k, v in TEMPS.items() if k != "T_column_C"},
                       ["X", "Y", "Z"])
    with pytest.raises(ValueError, match="axis 'y', which the NC does not have"):
        temp_comp_data(TERMS, TEMPS, ["X", "Z"])


def settle(nc: SiemensNC, pos: np.ndarray, cycles: int = 2000) -> np.ndarray:
    for _ in range(cycles):
        applied = nc.ipo_cycle(0.0, pos)
    return applied.copy()


@pytest.mark.parametrize("comp_type", [3, 1])
def test_the_nc_applies_the_terms_value_at_every_position(comp_type: int) -> None:
    nc = SiemensNC("sie-01", ["X", "Y", "Z"], SiemensConfig(temp_comp_type=comp_type))
    nc.write_temp_comp(temp_comp_data(TERMS, TEMPS, nc.axes))
    if comp_type == 3:  # the NC's own slope: SD43910/SD43920 hold it
        assert nc.read_sd(SD_SLOPE, "X") != 0.0
        assert nc.read_sd(SD_REF_POSITION, "Y") == 50.0
    else:  # bit 1 off: the PLC carries the slope, SD43910 stays empty
        assert nc.read_sd(SD_SLOPE, "X") == 0.0
    for pos in ([0.0, 0.0, 0.0], [450.0, 250.0, -200.0], [-100.0, 60.0, -10.0]):
        applied = settle(nc, np.array(pos))
        for j, axis in enumerate("xyz"):
            assert applied[j] * 1000.0 == pytest.approx(-error_um(axis, pos[j]), abs=1e-6)
    assert not nc.alarms


def test_offset_needs_bit_0_and_the_rate_is_limited() -> None:
    nc = SiemensNC("sie-01", ["X", "Y", "Z"], SiemensConfig(temp_comp_type=3))
    nc.write_md(MD_TEMP_COMP_TYPE, "Z", 2)
    with pytest.raises(SiemensAlarm, match="SD43900_DISABLED"):
        nc.write_temp_comp({"Z": TempCompData(offset_mm=0.01)})
    nc.write_temp_comp({"X": TempCompData(offset_mm=0.1)})
    step = float(nc.max_step_mm()[0])
    assert 0 < step < 0.01  # MD32760 · MD32000 · ipo / 60
    pos = np.zeros(3)
    for k in range(1, 6):
        applied = nc.ipo_cycle(0.0, pos)
        # the PLC writes SD43900 on its first cycle; from then on the NC ramps
        assert applied[0] == pytest.approx(min(0.1, k * step), rel=1e-9)
    assert settle(nc, pos)[0] == pytest.approx(0.1)
