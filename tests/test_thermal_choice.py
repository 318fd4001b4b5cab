"""Which model of a thermal drift the diagnosis names and saves
(:func:`volumetric.diagnose.lagged.named_thermal`): the static candidate's gates name the
drift, the models of it are compared with each other on the same held-out readings."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.candidates import Candidate
from volumetric.diagnose.gates import Scored, score
from volumetric.diagnose.lagged import named_thermal

N = 600
RNG = np.random.default_rng(7)
BASE = 3.0 * RNG.choice([-1.0, 1.0], N)  # the rigid base's held-out residuals, µm (±3:
# a candidate's squared residuals scale with a chunk's own factor alone)
ORDER = np.arange(N)
JUDGE = np.ones(N, dtype=bool)


def scored(effect: str, heldout: NDArray[np.float64], lagged: bool = False) -> Scored:
    extra = {"lagged": True} if lagged else {}
    c = Candidate(effect, "z", None if lagged else "T1", np.ones((N, 1)), extra)
    return score(c, heldout, BASE, float(np.sqrt(np.mean(BASE ** 2))), JUDGE, ORDER)


def test_a_model_of_every_sensor_that_fails_the_gates_alone_is_saved_when_the_static_drift_names_it(
        ) -> None:
    static = scored("thermal_drift", BASE * 0.94)  # passes: 6 % gain, the same every chunk
    # a lower figure, its gain all in every other of the 30 chunks: too noisy to pass
    noisy = BASE * np.where(ORDER // (N // 30) % 2 == 0, 0.0, np.sqrt(1.75))
    dyn = scored("thermal_drift", noisy, lagged=True)
    assert dyn.z < 1.0 and dyn.rms_after_um < static.rms_after_um
    assert named_thermal(dyn, dyn, [static, dyn], ORDER) is dyn
    # without a static drift that passes, a model that fails the gates names nothing
    weak = scored("thermal_drift", BASE * 0.99)
    assert named_thermal(dyn, dyn, [weak, dyn], ORDER) is None


def test_one_sensor_is_kept_over_a_model_of_every_sensor_only_when_the_split_tells_them_apart(
        ) -> None:
    static = scored("thermal_drift", BASE * 0.8)
    # as good on half the readings, worse on the other: about the same figure, the
    # paired gain of the one sensor over it within its noise
    halves = np.where(ORDER < N // 2, 0.7, 0.9)
    close = scored("thermal_drift", BASE * halves, lagged=True)
    assert static.rms_after_um < close.rms_after_um  # ranked first, but not clear of it
    assert named_thermal(static, close, [static, close], ORDER) is close
    far = scored("thermal_drift", BASE * 1.0 + RNG.normal(0.0, 0.5, N), lagged=True)
    assert named_thermal(static, far, [static, far], ORDER) is static
    # another effect on top is named by its own gates, whatever the thermal models
    other = scored("backlash", BASE * 0.5)
    assert named_thermal(other, close, [other, static, close], ORDER) is other
