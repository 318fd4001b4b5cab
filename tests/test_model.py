"""MachineModel: extension terms fold into the geometry and survive JSON."""

from __future__ import annotations

import json

import numpy as np
import pytest

from volumetric.model.components import GeometricErrors, Polynomial, Sinusoid
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import parse_machine
from volumetric.model.model import BacklashTerm, MachineModel, PeriodicTerm, ThermalTerm

M = parse_machine({"chain": "w X Y b Z t", "travel_mm": {"x": [-100, 400], "y": [0, 300],
                                                         "z": [-300, 0]}})


def test_thermal_expansion_scales_positioning_from_the_start_of_travel() -> None:
    base = GeometricErrors({"EXX": Polynomial((0.0, 0.01))})
    model = MachineModel("m", base, (ThermalTerm("thermal_expansion", "x", "T_x_C", 11.5, 20.0,
                                                  -100.0),))
    q = np.array([[-100.0, 0, 0], [400.0, 0, 0]])
    cold = volumetric_error(M, model.geometry_at({"T_x_C": 20.0}), q).position_um[:, 0]
    warm = volumetric_error(M, model.geometry_at({"T_x_C": 22.0}), q).position_um[:, 0]
    # 11.5 µm/(m·K) × 2 K × 0.5 m = 11.5 µm at the end of travel, nothing at its start
    np.testing.assert_allclose(warm - cold, [0.0, 11.5], atol=1e-9)


def test_drift_and_periodic_terms_add_to_positioning() -> None:
    model = MachineModel("m", GeometricErrors(), (
        ThermalTerm("thermal_drift", "z", "T_s_C", 2.0, 25.0),
        PeriodicTerm("y", 3.0, 10.0, 0.0),
    ))
    g = model.geometry_at({"T_s_C": 30.0})
    q = np.array([[0.0, 2.5, -10.0]])
    v = volumetric_error(M, g, q).position_um[0]
    np.testing.assert_allclose(v, [0.0, 3.0, 10.0], atol=1e-9)


def test_missing_temperature_is_named() -> None:
    model = MachineModel("m", GeometricErrors(), (ThermalTerm("thermal_drift", "z", "T_s_C",
                                                               2.0, 25.0),))
    with pytest.raises(ValueError, match="T_s_C"):
        model.geometry_at({})


def test_json_round_trip_keeps_every_term() -> None:
    model = MachineModel(
        "m",
        GeometricErrors({"EXX": Polynomial((0.0, 1.0, 2.0), 10.0, 100.0),
                         "EYY": Sinusoid(1.0, 5.0, 0.3)}, {"EC0Y": 12.0}),
        (ThermalTerm("thermal_expansion", "x", "T_x_C", 11.5, 20.0, -100.0),
         PeriodicTerm("y", 3.0, 10.0, 0.5), BacklashTerm("x", 6.0)),
        {"rms_um": 0.4},
    )
    again = MachineModel.from_json(json.loads(json.dumps(model.to_json())))
    assert again == model
    assert again.reversal_um() == {"x": 6.0}


@pytest.mark.parametrize("body", [
    {"components": [1, 2]}, {"locations": "EC0Y"}, {"terms": {"a": 1}}, {"terms": [3]},
    {"info": []}, {"components": {"EXX": {"type": "polynomial"}}},
    {"components": {"EXX": {"type": "table", "positions": [0, 1], "values": [0]}}}, [],
])
def test_malformed_models_raise_the_one_documented_error(body: object) -> None:
    from volumetric.errors import ComponentErrorSpecError

    with pytest.raises(ComponentErrorSpecError):
        MachineModel.from_json(body)  # type: ignore[arg-type]
