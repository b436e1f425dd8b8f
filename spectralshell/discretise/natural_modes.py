"""Hill blocks projected onto the lowest inviscid natural modes (a Galerkin basis in space).

A model whose blocks carry b spatial modes and an inviscid inertia (``HillSystem.inertia``:
D(s) = G + s^2 Mass at nu = 0, G and Mass symmetric, Mass positive definite; the cochlea's
b = M cosine modes with G = kappa C, Mass = diag(2/k), thesis 5.2) has natural modes

    G v_j = w_j^2 Mass v_j,     V^T Mass V = I,     V^T G V = diag(w_j^2),

w_1 <= w_2 <= ... in units of the forcing frequency (the same as
:func:`spectralshell.models.cochlea.natural_frequencies`). Writing u_n = V_m a_n with the m lowest
of them (V_m: b x m) in the Hill system D(s_n) u_n = i tau G (u_{n-1} - u_{n+1}) and multiplying by
V_m^T (Galerkin) gives the Hill system of the same form with blocks of size m,

    D_m(s) = V_m^T D(s) V_m = diag(w_j^2) + V_m^T (D(s) - G) V_m,     G_m = diag(w_j^2),

derived and checked in ``derivations/natural_mode_blocks.py``. Inviscid, D_m(s) = diag(w_j^2) +
s^2 I: m decoupled Mathieu equations, each mode pumped at its own natural frequency; viscosity
couples them through V_m^T diag(Z_k(s)) V_m (the cochlea's D(s) - G = diag(Z_k(s)), the
``diagonal_response``, so a projection costs O(b m^2) per s). With m = b the projection is a
congruence (V square and invertible): the same Floquet exponents and marginal tau.

Where the pumped resonance lies at the bottom of the natural spectrum (the slowest waves of a
low-frequency tone), a few natural modes carry it and the blocks shrink from b to m << b; where
many natural frequencies lie below the resonance (high-frequency tones on the cochlea) the basis
must hold them all and gains nothing. :func:`natural_basis_pays` decides before a point is solved
(:mod:`spectralshell.runner.solve`, minimum-tau maps). The truncation is then (m natural modes of
RATIO m cosine modes, N harmonics): every certificate (zero counts, disk bounds) and error
estimate is that of the projected Hill matrix, as for any truncation.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla

from .._validate import require_int_in_range
from ..errors import ParameterError
from ..models.base import HillSystem

#: Cosine modes per natural mode: the m natural modes are those of RATIO m cosine modes (their
#: lowest quarter, resolved by the cosine truncation; measured on the seeded Fig 5.18 sample,
#: validation/bench_sweep.py, where every point that the plan below projects agrees with the
#: cosine refinement's tau_min to <= 1e-4).
RATIO = 4
#: First M of a refinement in the natural basis (m = START / RATIO = 8 natural modes): a window
#: of three m (8, 12, 16) is the least the refinement's rule compares.
START = 32
#: Cosine modes of the probe truncation whose natural frequencies :func:`natural_basis_pays`
#: counts, and the most of them below the forcing frequency for which the basis pays.
PROBE_MODES = 128
CROWDING = 60


def natural_basis(system: HillSystem, m: int) -> tuple[np.ndarray, np.ndarray]:
    """(w_j^2 for j = 1..m ascending, V_m of shape (b, m)) of ``system`` (module notes): the m
    lowest eigenpairs of G v = w^2 Mass v with V_m^T Mass V_m = I.

    Raises
    ------
    ParameterError : the system has no inertia, m outside [1, b], or a natural frequency
        w_j^2 <= 0 (G not positive definite: no oscillatory natural modes to project on).
    """
    if system.inertia is None:
        raise ParameterError(f"model {system.name!r} has no inviscid inertia: its blocks cannot "
                             "be projected onto natural modes")
    m = require_int_in_range("n_natural", m, 1, system.block_size)
    w2, V = sla.eigh(system.forcing, system.inertia, subset_by_index=[0, m - 1])
    if not w2[0] > 0:
        raise ParameterError(f"model {system.name!r}: natural frequency squared w_1^2 = "
                             f"{w2[0]:.3g} <= 0: the stiffness G is not positive definite")
    return w2, V


def natural_mode_system(system: HillSystem, m: int) -> HillSystem:
    """``system`` projected onto its m lowest natural modes (module notes): blocks m x m,
    G_m = diag(w_j^2), D_m(s) = diag(w_j^2) + V_m^T (D(s) - G) V_m, inertia I; n_resonant w_1 and
    n_highest w_m. The polynomial form (nu = 0) is projected coefficient by coefficient."""
    w2, V = natural_basis(system, m)
    diagonal = np.arange(m)
    Vt = np.ascontiguousarray(V.T)
    full_response = system.diagonal_response

    def unforced(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=complex).ravel()
        if full_response is not None:
            out = np.matmul(Vt[None, :, :] * full_response(s)[:, None, :], V)
        else:
            out = np.matmul(np.matmul(Vt, system.unforced(s) - system.forcing), V)
        out[:, diagonal, diagonal] += w2
        return out

    polynomial = None if system.polynomial is None else tuple(Vt @ c @ V for c in system.polynomial)
    return HillSystem(name=system.name, block_size=m, forcing=np.diag(w2), unforced=unforced,
                      polynomial=polynomial, n_resonant=math.sqrt(w2[0]),
                      n_highest=math.sqrt(w2[-1]), branch_point=system.branch_point,
                      cut_poles=system.cut_poles, inertia=np.eye(m),
                      diagonal_response=None)


def modes_below(system: HillSystem, w: float) -> int:
    """The number of natural frequencies w_j < ``w`` of ``system``: the negative eigenvalues of
    G - w^2 Mass (Sylvester's law of inertia; no eigenvectors)."""
    if system.inertia is None:
        raise ParameterError(f"model {system.name!r} has no inviscid inertia: no natural modes")
    return int(np.count_nonzero(np.linalg.eigvalsh(system.forcing - w * w * system.inertia) < 0))


def natural_basis_pays(probe: HillSystem) -> bool:
    """Whether a point's refinement in space should run in the natural basis: at most CROWDING
    natural frequencies of ``probe`` (the point's system with PROBE_MODES cosine modes) lie below
    the forcing frequency 1 (the harmonic resonance; the subharmonic one, 1/2, lies lower).

    Notes
    -----
    Measured on the seeded 100-point Fig 5.18 sample (validation/bench_sweep.py, one thread, CPU
    time of each point's minimum-tau refinement, each basis refined on its own; the count is that
    of the probe): with at most 32 frequencies below the forcing one (58 points) the natural
    basis was 2.0-30x faster (human 63.6 Hz, sigma = 1.85e9: 23.2 s -> 2.6 s), with 45-55 (5)
    1.3-4.9x, at 63 0.9x (0.73 s against 0.67 s), from 66 on (36) 1.1-100x slower but at one
    point (the high-frequency tones, whose resonance lies among hundreds of natural modes). Only
    speed depends on this choice: both bases converge to the same tau_min within the
    refinement's tolerance (on the sample, the sweep with this plan against the cosine basis
    throughout: every point within its error estimates, at most 9.6e-5 apart; 229 s -> 87 s).
    """
    return probe.inertia is not None and modes_below(probe, 1.0) <= CROWDING
