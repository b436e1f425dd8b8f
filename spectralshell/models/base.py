"""The contract between a physical model and the Floquet engine.

A model describes a linear system with periodically pumped stiffness,

    D(d/dt) u(t) + 2 tau sin(t) G u(t) = 0,                                   (1)

where ``u`` has ``block_size`` real components, ``D`` is a real linear time-invariant operator
(its transfer function satisfies D(conj s) = conj D(s)) and ``G`` is a real matrix. Inserting the
Floquet-Fourier form u = exp(gamma t) sum_n u_n exp(i n t) (thesis (2.5)) and
sin t = (e^{it} - e^{-it}) / (2i) gives, for every integer n,

    D(s_n) u_n = i tau G (u_{n-1} - u_{n+1}),     s_n = gamma + i n,           (2)

the general form of thesis (2.6). A model therefore supplies only ``D(s)`` (vectorised over s) and
``G``; it never sees a truncation, a packing or a solver.

For the damped Mathieu equation (2.9), D(s) = s^2 + nu s + kappa and G = kappa: dividing (2) by
i kappa gives exactly the printed (2.6) -i((s^2 + nu s)/kappa + 1) u_n = tau (u_{n-1} - u_{n+1}).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, kw_only=True, eq=False)
class HillSystem:
    """Physics of one model in the form (2): unforced response D(s) and forcing matrix G.

    Attributes
    ----------
    name : model name, for provenance only.
    block_size : number b of real components of u.
    unforced : D, mapping complex ``s`` of shape (k,) to an array of shape (k, b, b).
    forcing : G, real (b, b).
    polynomial : coefficient matrices (D_0, D_1, ..., D_p) with D(s) = sum_j s^j D_j when D is a
        matrix polynomial with invertible leading coefficient (needed for Floquet exponents as a
        linear eigenproblem), otherwise None.
    n_resonant : the largest Fourier index at which D(i n) can be (nearly) singular, i.e. the
        natural frequency in units of the forcing frequency; truncations start above it.
    """

    name: str
    block_size: int
    unforced: Callable[[np.ndarray], np.ndarray]
    forcing: np.ndarray
    polynomial: tuple[np.ndarray, ...] | None = None
    n_resonant: float = 0.0
