"""The tolerances of the tables evaluation (protocol/README.md section 6.3), shared by the
reference evaluation (:mod:`machine_sim.chaineval`) and the fleet cycle
(:mod:`machine_sim.chaineval_cycle`), so the two cannot drift apart."""

from __future__ import annotations

import math
from typing import Final

RCOND: Final = 1e-9
"""Singular values of the column-normalised weighted Jacobian below RCOND · σ_max are zero
(an unobservable axis gets no correction). README section 6.3."""
STEP_TOL: Final = 1e-7
"""Refinement stops once no correction changes by more than this, mm or degrees."""
MAX_STEPS: Final = 6
PIVOT: Final = 1e-8
"""Pivots of the column-normalised normal matrix (unit diagonal) below this take the SVD
path: the normal equations square the condition number, so rows with σ_min/σ_max below
about 1e-4 are solved as the README says, by SVD."""
DEG: Final = math.pi / 180.0
SERIES: Final = 1e-4
"""θ² (rad²) below which the Rodrigues coefficients' series are exact to double precision."""
