"""Immersed circular fibre, one angular wavenumber m: Hill-system physics (thesis chapter 4).

Derived in ``derivations/fibre_linear.py`` (results in ``derivations/fibre_linear_result.md``)
from the fields, not from the printed (4.24)-(4.25). Unknowns X = (X^r, X^theta) with
X^r cos(m s) r-hat + X^theta sin(m s) theta-hat (the thesis's (4.18d,e)). With
beta = sqrt(s/nu) (principal branch), P = beta I_{m+1}(beta)/I_m(beta),
Q = beta K_{m-1}(beta)/K_m(beta) and E = [[m^2, m], [m, m^2]]:

    D(s) = s^2 [[2/m + 1/P + 1/Q, 1/P - 1/Q], [1/P - 1/Q, 1/P + 1/Q]] + kappa E,
    G    = kappa E                  (forcing = 'both')
    G    = kappa [[m^2, m], [0, 0]]  (forcing = 'pressure': K(t) only in the jump (4.15))
    G    = kappa [[0, 0], [m, m^2]]  (forcing = 'tangential': K(t) only in the jump (4.16))

in D(s_n) X_n = i tau G (X_{n-1} - X_{n+1}). The first term is the hydrodynamic load
[[p]] r-hat - nu [[d_r u]] (symmetric: Lorentz reciprocity; passive on s = i omega); kappa E is
the linearised membrane load of (4.14) including the prestress [[p0]] = -K, which makes a rigid
translation (m = 1, X = (1, -1)) load-free. D(0) = kappa E is the s -> 0 limit
(H(s) = 4 nu s [[m, 1], [1, m]] + o(s)).

Corrections to the print (see the result file): (4.24)-(4.25) agree with D, G in three entries,
but the X^theta terms of (4.25) (D_n and the m^2 tau term) have the wrong sign. The printed
system violates reciprocity, loads a rigid translation and has an inviscid frequency
kappa m(m^2+1)/2 instead of Rayleigh's. (4.24) writes k for m. The display after (4.27) flips the
sign of (X_{n-1} - X_{n+1}); that is harmless, because tau -> -tau is a time shift.

Inviscid limit nu -> 0 (singular: P, Q ~ beta -> infinity, so the tangential stress vanishes). The
tangential row forces X^theta = -X^r/m, and the radial row becomes the Mathieu equation
X'' + lambda0^2 (1 + 2 tau sin t) X = 0 with lambda0^2 = kappa m (m^2 - 1)/2. This is Rayleigh's
frequency of a capillary column with tension K and equal densities. ``nu = 0`` therefore reuses
the Mathieu model. With forcing = 'tangential' the limit is unforced, for tau < 1/2.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .._validate import require_positive
from ..params.fibre import FibreParams
from ..special.cylindrical import ratio_i, ratio_k
from . import mathieu
from .base import HillSystem


def lambda0_squared(m: int, kappa: float) -> float:
    """Inviscid natural frequency squared, lambda0^2 = kappa m (m^2 - 1)/2 (forcing frequency = 1).

    Notes
    -----
    The thesis prints no formula for it. It follows from D(s) as nu -> 0: the determinant of
    [[2 s^2/m + kappa m^2, kappa m], [kappa m, kappa m^2]] vanishes at s^2 = -lambda0^2.
    """
    return kappa * m * (m * m - 1) / 2.0


def elastic_matrix(m: int) -> np.ndarray:
    """E = [[m^2, m], [m, m^2]]: the membrane load on (X^r, X^theta) is -K(t) E X ((4.14), corrected).

    Notes
    -----
    E comes from K(X_ss + r-hat-terms of the perturbed normal) with [[p0]] = -K. Its eigenvalues
    are m(m+1) on (1, 1) and m(m-1) on (1, -1), so E is singular at m = 1 (rigid translation).
    """
    return np.array([[m * m, m], [m, m * m]], dtype=float)


def forcing_matrix(m: int, kappa: float, forcing: str = "both") -> np.ndarray:
    """G: the rows of kappa E whose jump condition carries the pumped stiffness (Fig 4.2 split)."""
    G = kappa * elastic_matrix(m)
    if forcing == "pressure":
        G[1] = 0.0
    elif forcing == "tangential":
        G[0] = 0.0
    return G


def unforced(s: np.ndarray, *, m: int, kappa: float, nu: float) -> np.ndarray:
    """D(s) for nu > 0 (see the module docstring), shape (len(s), 2, 2); D(0) = kappa E (limit).

    Notes
    -----
    1/P = 1/(beta ratio_i(m, beta)) and 1/Q = ratio_k(m-1, beta)/beta come from the
    overflow-free kernels of :mod:`spectralshell.special.cylindrical`. At small beta,
    s^2/P -> 2(m+1) nu s and s^2/Q -> 2(m-1) nu s, without cancellation.

    Raises
    ------
    ParameterError : nu <= 0 (the inviscid limit is :func:`hill_system` with nu = 0), or an s
        whose beta leaves the kernels' domain 1e-150 <= |beta| <= 1e150.
    """
    nu = require_positive("nu", nu)
    s = np.asarray(s, dtype=complex).ravel()
    out = np.broadcast_to(kappa * elastic_matrix(m), (s.size, 2, 2)).astype(complex)
    live = s != 0
    if live.any():
        sl = s[live]
        beta = np.sqrt(sl / nu)
        s2 = sl * sl
        a = s2 / (beta * ratio_i(m, beta))        # s^2 / P
        b = s2 * ratio_k(m - 1, beta) / beta      # s^2 / Q
        out[live, 0, 0] += 2.0 * s2 / m + a + b
        out[live, 0, 1] += a - b
        out[live, 1, 0] += a - b
        out[live, 1, 1] += a + b
    return out


def natural_determinant(s: np.ndarray, *, m: int, kappa: float, nu: float) -> np.ndarray:
    """det D(s) of the unforced fibre (tau = 0); its zeros are the natural modes e^{st}.

    Notes
    -----
    As nu -> 0 the oscillatory zeros tend to s = +-i lambda0, with O(sqrt(nu)) Stokes-layer
    corrections (checked in the derivation for nu = 1e-6 ... 1e-3). For nu = 0 the determinant
    of the inviscid limit, 2 kappa m (s^2 + lambda0^2), is returned.

    Raises
    ------
    ParameterError : invalid m, kappa or nu.
    """
    p = FibreParams(m=m, kappa=kappa, nu=nu)
    s = np.asarray(s, dtype=complex)
    if p.nu == 0.0:
        return 2.0 * p.kappa * p.m * (s * s + lambda0_squared(p.m, p.kappa))
    D = unforced(s.ravel(), m=p.m, kappa=p.kappa, nu=p.nu)
    det = D[:, 0, 0] * D[:, 1, 1] - D[:, 0, 1] * D[:, 1, 0]
    return det.reshape(s.shape)


def hill_system(*, m: int, kappa: float, nu: float, forcing: str = "both") -> HillSystem:
    """Hill-system physics of wavenumber m of the immersed fibre (see the module docstring).

    Notes
    -----
    nu > 0: block size 2, D(s) from :func:`unforced`, G from :func:`forcing_matrix`, and
    ``n_resonant`` = lambda0. nu = 0: the inviscid limit, the Mathieu model with
    kappa -> lambda0^2 (block size 1). With forcing = 'tangential' its forcing is zero (no finite
    marginal tau), because the slaved tangential row carries all of the pumping.

    Raises
    ------
    ParameterError : invalid m (integer 2..200), kappa (> 0), nu (>= 0) or forcing.
    """
    p = FibreParams(m=m, kappa=kappa, nu=nu, forcing=forcing)
    lam2 = lambda0_squared(p.m, p.kappa)
    if p.nu == 0.0:
        inviscid = dataclasses.replace(mathieu.hill_system(kappa=lam2, nu=0.0), name="fibre")
        if p.forcing == "tangential":
            return dataclasses.replace(inviscid, forcing=np.zeros((1, 1)))
        return inviscid
    m_, kappa_, nu_ = p.m, p.kappa, p.nu
    return HillSystem(name="fibre", block_size=2, forcing=forcing_matrix(m_, kappa_, p.forcing),
                      unforced=lambda s: unforced(s, m=m_, kappa=kappa_, nu=nu_),
                      n_resonant=float(np.sqrt(lam2)))
