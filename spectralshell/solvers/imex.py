"""IMEX time-stepping schemes kept as data: multistep coefficients and Runge-Kutta tableaux.

Every scheme advances the linear semi-discrete system

    M dv/dt = L v + F(t, v),        F(t, v) = f(t) N v,

with L treated implicitly and F explicitly, at a constant step h. M may be singular (algebraic
rows); the schemes below never need M^{-1}.

Multistep schemes (s steps), v_k = v(t_k), F_k = F(t_k, v_k):

    sum_{j=0}^{s} a_j M v_{n+1-j} = h ( sum_{j=0}^{s} b_j L v_{n+1-j} + sum_{j=1}^{s} c_j F_{n+1-j} ).

(a, b) is an implicit linear multistep method and (a, c) an explicit one; the scheme has order p
when both satisfy the order conditions sum_j a_j (-j)^q = q sum_j b_j (-j)^(q-1), q = 0..p (and
the same with c). Coefficients: SBDF1-4 (backward differentiation with extrapolated F, Ascher,
Ruuth and Wetton 1995, SIAM J. Numer. Anal. 32), CNAB2 (Crank-Nicolson/Adams-Bashforth) and
MCNAB2 (the modified CNAB of the same paper).

Runge-Kutta schemes (Ascher, Ruuth and Spiteri 1997, Appl. Numer. Math. 25, "ARS(s, sigma, p)"):
stage 0 is v_n; for i = 1..s

    M v_i = M v_n + h sum_{j<i} (AE_ij F(t_n + c_j h, v_j) + AI_ij L v_j) + h AI_ii L v_i,

and v_{n+1} = v_s: both tableaux are stiffly accurate (their last rows are the weights b), so
no M^{-1} is needed and the algebraic rows hold at the new step. c_i = sum_j AE_ij = sum_j AI_ij.
RK111 (IMEX Euler), RK222 = ARS(2,2,2) (gamma = 1 - 1/sqrt 2, L-stable implicit part),
RK443 = ARS(4,4,3) (third order, L-stable implicit part).

The order conditions of both families (the additive/partitioned Runge-Kutta conditions up to
order 3, including the coupling ones) are checked in ``tests/test_imex.py``, together with the
observed order on scalar and sphere problems.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from math import sqrt

import numpy as np

from .._validate import require_choice

F = Fraction


@dataclass(frozen=True, kw_only=True)
class Multistep:
    """An IMEX linear multistep scheme: a (M weights), b (implicit L), c (explicit F; c[0] = 0)."""

    name: str
    order: int
    a: tuple
    b: tuple
    c: tuple
    description: str

    @property
    def steps(self) -> int:
        """Number of previous values it needs (s)."""
        return len(self.a) - 1

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(a, b, c) as float arrays."""
        return tuple(np.array([float(x) for x in w]) for w in (self.a, self.b, self.c))


@dataclass(frozen=True, kw_only=True)
class RungeKutta:
    """An IMEX Runge-Kutta scheme: explicit and implicit (s+1) x (s+1) tableaux (row 0 = stage 0)."""

    name: str
    order: int
    explicit: tuple
    implicit: tuple
    description: str

    @property
    def stages(self) -> int:
        """Number of stages after stage 0 (s)."""
        return len(self.explicit) - 1

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(AE, AI, c) as float arrays; c = row sums."""
        AE = np.array([[float(x) for x in row] for row in self.explicit])
        AI = np.array([[float(x) for x in row] for row in self.implicit])
        return AE, AI, AE.sum(axis=1)


def _ars222() -> RungeKutta:
    g = 1 - 1 / sqrt(2)
    d = 1 - 1 / (2 * g)
    return RungeKutta(
        name="RK222", order=2,
        explicit=((0, 0, 0), (g, 0, 0), (d, 1 - d, 0)),
        implicit=((0, 0, 0), (0, g, 0), (0, 1 - g, g)),
        description="ARS(2,2,2): 2 implicit stages, second order, L-stable implicit part")


SCHEMES: dict[str, Multistep | RungeKutta] = {s.name: s for s in (
    Multistep(name="SBDF1", order=1, a=(1, -1), b=(1, 0), c=(0, 1),
              description="IMEX Euler (backward Euler / forward Euler)"),
    Multistep(name="SBDF2", order=2, a=(F(3, 2), -2, F(1, 2)), b=(1, 0, 0), c=(0, 2, -1),
              description="BDF2 with linearly extrapolated F"),
    Multistep(name="SBDF3", order=3, a=(F(11, 6), -3, F(3, 2), F(-1, 3)), b=(1, 0, 0, 0),
              c=(0, 3, -3, 1), description="BDF3 with quadratically extrapolated F"),
    Multistep(name="SBDF4", order=4, a=(F(25, 12), -4, 3, F(-4, 3), F(1, 4)), b=(1, 0, 0, 0, 0),
              c=(0, 4, -6, 4, -1), description="BDF4 with cubically extrapolated F"),
    Multistep(name="CNAB2", order=2, a=(1, -1, 0), b=(F(1, 2), F(1, 2), 0), c=(0, F(3, 2), F(-1, 2)),
              description="Crank-Nicolson / Adams-Bashforth 2 (not L-stable)"),
    Multistep(name="MCNAB2", order=2, a=(1, -1, 0), b=(F(9, 16), F(3, 8), F(1, 16)),
              c=(0, F(3, 2), F(-1, 2)), description="modified CNAB (damps the stiffest modes)"),
    RungeKutta(name="RK111", order=1, explicit=((0, 0), (1, 0)), implicit=((0, 0), (0, 1)),
               description="IMEX Euler as a one-stage Runge-Kutta scheme"),
    _ars222(),
    RungeKutta(
        name="RK443", order=3,
        explicit=((0, 0, 0, 0, 0), (F(1, 2), 0, 0, 0, 0), (F(11, 18), F(1, 18), 0, 0, 0),
                  (F(5, 6), F(-5, 6), F(1, 2), 0, 0), (F(1, 4), F(7, 4), F(3, 4), F(-7, 4), 0)),
        implicit=((0, 0, 0, 0, 0), (0, F(1, 2), 0, 0, 0), (0, F(1, 6), F(1, 2), 0, 0),
                  (0, F(-1, 2), F(1, 2), F(1, 2), 0), (0, F(3, 2), F(-3, 2), F(1, 2), F(1, 2))),
        description="ARS(4,4,3): 4 implicit stages, third order, L-stable implicit part"),
)}

#: The multistep schemes take their first s - 1 steps with this one-step scheme. A zero-stable
#: multistep method's global error is O(starting error) + O(h^p); s - 1 steps of local error O(h^4)
#: keep the starting error O(h^4), enough for every multistep scheme here (order <= 4).
STARTER = "RK443"


def scheme(name: str) -> Multistep | RungeKutta:
    """The registered scheme ``name`` (case-insensitive), e.g. 'sbdf3', 'RK443'."""
    key = str(name).upper() if isinstance(name, str) else name
    return SCHEMES[require_choice("scheme", key, tuple(SCHEMES))]
