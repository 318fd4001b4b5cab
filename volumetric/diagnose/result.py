"""The answer of a diagnosis (:class:`Diagnosis`, formats.md section 3 plus extensions) and
the error raised when the readings cannot support one."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.model.model import MachineModel

F64 = NDArray[np.float64]


class DiagnosisError(ValueError):
    """The readings cannot support a diagnosis; the message says what is missing."""


@dataclass(frozen=True)
class Diagnosis:
    """The answer of :func:`volumetric.diagnose.diagnosis.diagnose` (formats.md section 3
    plus extensions)."""

    effect: str
    axis: str | None
    sensor: str | None
    estimate: dict[str, Any]
    rms_before_um: float
    rms_after_um: float
    candidates: list[dict[str, Any]]
    not_assessed: dict[str, str]
    model: MachineModel
    details: dict[str, Any] = field(default_factory=dict)
    residual_before: F64 = field(default_factory=lambda: np.zeros(0), repr=False)
    residual_after: F64 = field(default_factory=lambda: np.zeros(0), repr=False)
    judged: NDArray[np.bool_] = field(default_factory=lambda: np.zeros(0, bool), repr=False)

    def to_json(self) -> dict[str, Any]:
        return {
            "effect": self.effect,
            "axis": self.axis,
            "sensor": self.sensor,
            "estimate": self.estimate,
            "rms_before_um": round(self.rms_before_um, 4),
            "rms_after_um": round(self.rms_after_um, 4),
            "candidates": self.candidates,
            "not_assessed": self.not_assessed,
            **self.details,
        }
