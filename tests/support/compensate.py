"""Errors of a realistic size for the two-spindle arch machine, shared by the compensation
and error-map tests."""

from __future__ import annotations

import numpy as np

from volumetric.model.components import GeometricErrors, Polynomial, component_names
from volumetric.model.machine import Machine


def realistic_arch_errors(m: Machine, rng: np.random.Generator) -> GeometricErrors:
    """Cubic component errors of some 10 µm / 10 µrad per coefficient and squareness of
    tens of µrad: before compensation the tool tips are off by tens of µm, as in Table 1."""
    comps = {}
    for a in m.axes:
        span = a.travel[1] - a.travel[0]
        for n in component_names(a):
            comps[n] = Polynomial(tuple(rng.normal(0, 8.0, 4)), a.travel[0], span)
    locs = {"EC0Y": 40.0, "EA0Z1": -25.0, "EB0Z1": 30.0, "EA0Z2": 35.0, "EB0Z2": -20.0}
    return GeometricErrors(comps, locs)
