"""Damped Mathieu equation u'' + nu u' + kappa (1 + 2 tau sin t) u = 0 (thesis (2.2), (2.9)).

In the form of :mod:`spectralshell.models.base`: D(s) = s^2 + nu s + kappa, G = kappa, b = 1.
The undamped equation (nu = 0) maps onto the canonical Mathieu equation
y'' + (a - 2 q cos 2x) y = 0 of DLMF 28.2.1 by t = 2x - pi/2 (so sin t = -cos 2x):
a = 4 kappa, q = 4 kappa tau (derived in ``derivations/mathieu_mapping.py``).
"""

from __future__ import annotations

import numpy as np

from ..params.mathieu import MathieuParams
from ..params.registry import Model, register
from .base import HillSystem


def hill_system(*, kappa: float, nu: float) -> HillSystem:
    """Return the Hill-system physics of the damped Mathieu equation (2.9).

    Notes
    -----
    Thesis (2.9): u'' + nu u' + kappa (1 + 2 tau sin t) u = 0, i.e. D(s) = s^2 + nu s + kappa and
    G = kappa in D(d/dt) u + 2 tau sin(t) G u = 0. The natural frequency sqrt(kappa) (in units of
    the forcing frequency) sets ``n_resonant``.
    """
    kappa = float(kappa)
    nu = float(nu)

    def unforced(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=complex)
        return (s * s + nu * s + kappa).reshape(-1, 1, 1)

    return HillSystem(
        name="mathieu",
        block_size=1,
        unforced=unforced,
        forcing=np.array([[kappa]]),
        polynomial=(np.array([[kappa]]), np.array([[nu]]), np.array([[1.0]])),
        n_resonant=float(np.sqrt(kappa)),
    )


def _hill_system(p: MathieuParams) -> HillSystem:
    return hill_system(kappa=p.kappa, nu=p.nu)


MODEL = register(Model(
    name="mathieu",
    summary="damped Mathieu equation u'' + nu u' + kappa (1 + 2 tau sin t) u = 0 (thesis 2)",
    params=MathieuParams, hill_system=_hill_system))
