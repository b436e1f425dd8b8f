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

Natural modes (tau = 0): :func:`modal_system` states det D(gamma) = 0 in beta for the root finder
(two modes with Im gamma >= 0: the Rayleigh oscillation and the fast Stokes-layer mode), with the
asymptotic seeds :func:`oscillatory_limit`, :func:`fast_limit` and :func:`stokes_limit`.
"""

from __future__ import annotations

import cmath
import dataclasses
import functools
import math
from collections.abc import Iterator

import numpy as np

from .._validate import require_positive
from ..errors import ParameterError
from ..params.fibre import FibreParams
from ..params.simulation import FIBRE_STEPPING
from ..params.registry import Model, register
from ..special.cylindrical import k_continuation, ratio_i, ratio_k
from . import mathieu
from .base import (HillSystem, ModalSystem, boundary_layer, continued_roots,
                   modal_system_in_beta)


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
    out = np.broadcast_to(kappa * elastic_matrix(m), (s.size, 2, 2)).astype(complex, order="C")
    live = s != 0
    if live.any():
        sl = s[live]
        beta = np.sqrt(sl / nu)
        s2 = sl * sl
        with boundary_layer(nu):
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


# ----------------------------------------------------------------------------- natural modes
#
# Derived in derivations/fibre_modes.py (results in derivations/fibre_linear_result.md, section 7,
# "Natural modes"). Scaled variables: zeta = nu/sqrt(kappa), sigma = gamma/sqrt(kappa) = zeta beta^2,
# S = sigma^2, x = 1/Q, y = 1/P. In the basis e+- = (1, +-1)/sqrt(2), which diagonalises E,
#
#     det D(gamma)/kappa^2 = Delta(beta) = A+ A- - S^2/m^2,
#     A+ = S (1/m + 2y) + m(m+1),   A- = S (1/m + 2x) + m(m-1),
#
# i.e. Delta = S^2 (2(x+y)/m + 4xy) + 2mS (1 + (m+1)x + (m-1)y) + m^2(m^2-1).

#: Range of zeta = nu/sqrt(kappa) over which the seeds are verified (tests/test_fibre_modes.py).
ZETA_MIN = 1e-10
ZETA_MAX = 1e3
#: Modes on the physical sheet with Im gamma >= 0 (argument-principle counts in the tests).
N_MODES = 2
_EULER_GAMMA = 0.57721566490153286


def _q_second_sheet(m: int, w: complex, q_w: complex, upper: bool) -> complex:
    """Q(beta) at beta = -w, Re w > 0: K_n(w e^{+-i pi}) = (-1)^n K_n(w) -+ i pi I_n(w) (DLMF 10.34.2),

        Q(-w) = (Q(w) - c w / r) / (1 + c),   c = (-1)^m e rho,   e = -+ i pi,

    rho = I_m(w)/K_m(w) (c from :func:`~spectralshell.special.cylindrical.k_continuation`; 0 where
    it underflows: then Q is
    continued as an even function, correct to double precision: by the Wronskian
    I_m K_m' - I_m' K_m = -1/w, K_m overflows or I_m underflows only where rho is below 1e-300),
    r = I_m(w)/I_{m-1}(w).
    The upper sign holds for Im beta >= 0."""
    c = k_continuation(m, w, upper)
    if not cmath.isfinite(c):
        raise OverflowError("I_m/K_m overflows: beta is far into the second sheet")
    r = complex(ratio_i(m - 1, w))
    return (q_w - c * w / r) / (1.0 + c)


def _p_q(m: int, beta: complex) -> tuple[complex, complex, complex, complex]:
    """P, Q and their beta-derivatives (Riccati form of DLMF 10.25.1) at beta != 0, on both sheets.

        beta P' = beta^2 - 2m P - P^2,      beta Q' = Q^2 + 2m Q - beta^2.

    P is even in beta; Q is continued across Re beta = 0 by :func:`_q_second_sheet`."""
    w = beta if beta.real >= 0 else -beta
    P = complex(w * ratio_i(m, w))
    Q = complex(w / ratio_k(m - 1, w))
    if beta.real < 0:
        Q = _q_second_sheet(m, w, Q, beta.imag >= 0)
    b2 = beta * beta
    return P, Q, (b2 - 2 * m * P - P * P) / beta, (Q * Q + 2 * m * Q - b2) / beta


def _delta_from_pq(m, zeta, beta, P, Q, dP, dQ):
    """(Delta, Delta' + Delta g'/g) from P, Q and their derivatives (any number type; m of that type).

    g = I_{m+1}(beta) K_{m-1}(beta)/beta^2 removes the poles of Delta (zeros of I_{m+1} on the
    imaginary axis, of K_{m-1} in Re beta < 0); beta g'/g = beta^2 (1/P - 1/Q) - 4 (DLMF 10.29.2).
    |beta| < m uses the product form, which keeps the near-double Stokes roots well conditioned;
    |beta| >= m the expanded form, which avoids the cancellation of S^2/m^2 at large beta."""
    x, y = 1 / Q, 1 / P
    dx, dy = -dQ * x * x, -dP * y * y
    S = (zeta * beta * beta) ** 2
    dS = 4 * S / beta
    if abs(beta) < m:
        ap, am = S * (1 / m + 2 * y) + m * (m + 1), S * (1 / m + 2 * x) + m * (m - 1)
        dap, dam = dS * (1 / m + 2 * y) + 2 * S * dy, dS * (1 / m + 2 * x) + 2 * S * dx
        delta = ap * am - S * S / (m * m)
        ddelta = dap * am + ap * dam - 2 * S * dS / (m * m)
    else:
        c, dc = 2 * (x + y) / m + 4 * x * y, 2 * (dx + dy) / m + 4 * (dx * y + x * dy)
        b, db = 2 * m * (1 + (m + 1) * x + (m - 1) * y), 2 * m * ((m + 1) * dx + (m - 1) * dy)
        delta = S * S * c + S * b + m * m * (m * m - 1)
        ddelta = 2 * S * dS * c + S * S * dc + dS * b + S * db
    return delta, ddelta + delta * (beta * (y - x) - 4 / beta)


def modal_residual(beta: complex, *, m: int, zeta: float) -> tuple[complex, complex]:
    """(Delta, Newton derivative) of the fibre's dispersion relation in double precision."""
    beta = complex(beta)
    return _delta_from_pq(float(m), zeta, beta, *_p_q(m, beta))


def modal_residual_mp(beta, *, m: int, zeta: float):
    """:func:`modal_residual` in mpmath (besseli/besselk of integer order, principal branch)."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    beta, mm = mpmath.mpc(beta), mpmath.mpf(m)
    P = beta * mpmath.besseli(m + 1, beta) / mpmath.besseli(m, beta)
    Q = beta * mpmath.besselk(m - 1, beta) / mpmath.besselk(m, beta)
    b2 = beta * beta
    return _delta_from_pq(mm, mpmath.mpf(zeta), beta, P, Q, (b2 - 2 * mm * P - P * P) / beta,
                          (Q * Q + 2 * mm * Q - b2) / beta)


def oscillatory_limit(*, m: int, kappa: float, nu: float) -> complex:
    """Small-nu Rayleigh mode: gamma = i lambda0 - c_m sqrt(i lambda0 nu) - d_m nu + O(nu^(3/2)),
    c_m = (m^2+1)/(2m), d_m = (m^4-3)/(4m^2) (Stokes-layer damping; derivations/fibre_modes.py)."""
    lam0 = math.sqrt(lambda0_squared(m, kappa))
    return (1j * lam0 - (m * m + 1) / (2 * m) * cmath.sqrt(1j * lam0 * nu)
            - (m ** 4 - 3) / (4 * m * m) * nu)


def fast_limit(*, m: int, kappa: float, nu: float) -> complex:
    """Small-nu fast branch: gamma = a^2 (kappa^2/nu)^(1/3) - 2(m^2-1)/(3m) a (kappa nu)^(1/3)
    + O(nu), a = (m^2/2)^(1/3) e^{i pi/3} (|gamma| ~ (kappa^2 m^4/(4 nu))^(1/3), arg 2 pi/3)."""
    a = (m * m / 2.0) ** (1.0 / 3.0) * cmath.exp(1j * math.pi / 3)
    third = 1.0 / 3.0
    return a * a * (kappa * kappa / nu) ** third - 2 * (m * m - 1) / (3 * m) * a * (kappa * nu) ** third


def stokes_limit(*, m: int, kappa: float, nu: float) -> np.ndarray:
    """Large-nu pair near the steady-Stokes double root gamma0 = -kappa m/(4 nu), from the quartic

        A+ A- - sigma^4/m^2 = 0,  A+- = sigma^2 (1/m + 2 c+-) + 4(m+-1) zeta sigma + m(m+-1),

    with 1/P = 2(m+1)/beta^2 + c+, 1/Q = 2(m-1)/beta^2 + c- + o(1): c+ = 1/(2(m+2)),
    c- = 1/(2(m-2)) (m >= 3), c- = -log(beta0/2) - gamma_E (m = 2, the 2D Stokes paradox;
    beta0 = sqrt(gamma0/nu), Im beta0 > 0). Returns the two roots nearest gamma0 (gamma units)."""
    zeta = nu / math.sqrt(kappa)
    sigma0 = -m / (4 * zeta)
    c_plus = 1 / (2 * (m + 2))
    if m == 2:
        c_minus = -cmath.log(cmath.sqrt(sigma0 / zeta) / 2) - _EULER_GAMMA
    else:
        c_minus = 1 / (2 * (m - 2))
    ap = np.array([1 / m + 2 * c_plus, 4 * (m + 1) * zeta, m * (m + 1)], dtype=complex)
    am = np.array([1 / m + 2 * c_minus, 4 * (m - 1) * zeta, m * (m - 1)], dtype=complex)
    quartic = np.polymul(ap, am)
    quartic[0] -= 1 / (m * m)
    roots = np.roots(quartic * (4 * zeta / m) ** np.arange(5))  # in units of |sigma0|
    roots = roots[np.argsort(abs(roots + 1))][:2] * abs(sigma0)
    return math.sqrt(kappa) * roots


#: Smallest relative separation of the two overdamped modes (near the Stokes double root) that
#: the root finder resolves with margin (its duplicate tolerance is 1e-8 in beta).
_SEPARATION_MIN = 1e-6


def zeta_max(m: int) -> float:
    """Largest zeta = nu/sqrt(kappa) for which both modes are resolved: ZETA_MAX for m = 2, else
    where the two overdamped modes, |gamma_+ - gamma_-|/|gamma0| ~ (m/(4 zeta^2)) |d_m|,

        d_m = (1/m + 1/(m+2))/(4(m+1)) - (1/m + 1/(m-2))/(4(m-1))      (from :func:`stokes_limit`),

    come closer than 1e-6 (zeta_max = 316, 204, 72, 3.5 for m = 3, 4, 10, 200).
    For m = 2 the logarithm of the 2D Stokes paradox keeps them 2e-6 apart even at zeta = 1e3."""
    if m == 2:
        return ZETA_MAX
    d = (1 / m + 1 / (m + 2)) / (4 * (m + 1)) - (1 / m + 1 / (m - 2)) / (4 * (m - 1))
    return min(ZETA_MAX, math.sqrt(m * abs(d) / (4 * _SEPARATION_MIN)))


def _first_quadrant(beta: complex, offset: float = 0.0) -> complex:
    """The point with the same |Re|, |Im| in the closed first quadrant (Re at least offset |beta|)."""
    return complex(max(abs(beta.real), offset * abs(beta)), abs(beta.imag))


def modal_seeds(*, m: int, zeta: float) -> Iterator[complex]:
    """Starting points beta for the two modes, best first (lazy), in scaled units (kappa = 1).

    Notes
    -----
    * the asymptotic pair of the regime first: for zeta <= 1/sqrt(m) (|beta0| >= m/2, beta0 the
      Stokes value) the small-nu modes :func:`oscillatory_limit` and :func:`fast_limit`, otherwise
      the two roots of :func:`stokes_limit`;
    * then the other pair, and all four moved off the imaginary axis by 2 % of |beta| (on the
      axis a nearly even residual keeps Newton's iterates);
    * last, for zeta above 0.2/sqrt(m), both small-nu modes continued in zeta from there
      (:func:`_continued`): for large m the crossover |beta| ~ m is where neither asymptotic
      pair is close enough (e.g. m = 200, zeta = 0.044).

    Over m = 2..200, zeta = 1e-10..zeta_max(m), these find both modes
    (tests/test_fibre_modes.py); the regime's pair alone does so away from the crossover.
    """
    small = [oscillatory_limit(m=m, kappa=1.0, nu=zeta), fast_limit(m=m, kappa=1.0, nu=zeta)]
    large = [complex(g) for g in stokes_limit(m=m, kappa=1.0, nu=zeta)]
    ordered = small + large if zeta * math.sqrt(m) <= 1.0 else large + small
    betas = [cmath.sqrt(sigma / zeta) for sigma in ordered]
    for beta in betas:
        yield _first_quadrant(beta)
    for beta in betas:
        yield _first_quadrant(beta, 0.02)
    start = 0.2 / math.sqrt(m)
    if zeta > start:
        yield from _continued(m, zeta, start)


def _continued(m: int, zeta: float, start: float) -> Iterator[complex]:
    """The two small-nu modes at zeta = start, continued to zeta (:func:`continued_roots`)."""
    starts = [cmath.sqrt(sigma / start) for sigma in (oscillatory_limit(m=m, kappa=1.0, nu=start),
                                                       fast_limit(m=m, kappa=1.0, nu=start))]
    for beta in continued_roots(lambda z: functools.partial(modal_residual, m=m, zeta=z), starts,
                                start, zeta):
        yield _first_quadrant(beta)


def modal_system(*, m: int, kappa: float, nu: float) -> ModalSystem:
    """Natural modes of wavenumber m of the unforced fibre as a :class:`ModalSystem` in beta.

    Parameters
    ----------
    m : wavenumber, 2 <= m <= 200.
    kappa, nu : stiffness and viscosity (> 0); zeta = nu/sqrt(kappa) must lie in
        [ZETA_MIN, zeta_max(m)] (:func:`zeta_max`).

    Notes
    -----
    x = beta = sqrt(gamma/nu) (Re beta > 0 on the physical sheet), gamma = nu beta^2; the
    dispersion relation is Delta(beta) = det D(gamma)/kappa^2 (see the block comment above), a
    function of beta and zeta only, so gamma/sqrt(kappa) depends on zeta alone. Delta is analytic in
    Re beta > 0 (its poles are at the zeros of I_{m+1}, on the imaginary axis, and of K_{m-1}, in
    Re beta < 0); K_{m-1}, K_m carry the logarithmic branch point of 2D Stokes flow at beta = 0,
    cut along beta <= 0, so the continuation across the imaginary axis (gamma's cut) is the
    second sheet. n_modes = 2 (N_MODES): argument-principle counts over the first quadrant find
    exactly two roots for every m, zeta tested (tests/test_fibre_modes.py): the Rayleigh
    oscillation (gamma -> i lambda0 as nu -> 0) and the fast Stokes-layer mode
    (|gamma| ~ (kappa^2 m^4/(4 nu))^(1/3)), which become the two overdamped Stokes modes near
    -kappa m/(4 nu) as nu grows. ``count`` in :func:`solvers.modes.find_modes` therefore defaults
    to both.

    Raises
    ------
    ParameterError : m, kappa or nu out of range (nu = 0: the modes are gamma = +-i lambda0, and
        the fast mode has gone to infinity: nothing to solve).
    """
    if nu == 0:
        raise ParameterError("nu = 0 is invalid: must be > 0 for the viscous natural modes (the "
                             "inviscid one is gamma = i lambda0, lambda0^2 = kappa m (m^2 - 1)/2)")
    p = FibreParams(m=m, kappa=kappa, nu=nu)
    zeta = p.nu / math.sqrt(p.kappa)
    top = zeta_max(p.m)
    if not ZETA_MIN <= zeta <= top:
        raise ParameterError(
            f"zeta = nu/sqrt(kappa) = {zeta!r} is invalid: must be in [{ZETA_MIN:g}, {top:.4g}] "
            f"for m = {p.m} (above it the two overdamped modes, both near gamma = -kappa m/(4 nu), "
            "are closer than 1e-6 relative and cannot be told apart)")
    return modal_system_in_beta("fibre", nu=p.nu, n_modes=N_MODES, residual=modal_residual,
                                residual_mp=modal_residual_mp, seeds=modal_seeds, m=p.m, zeta=zeta)


def _hill_system(p: FibreParams) -> HillSystem:
    return hill_system(m=p.m, kappa=p.kappa, nu=p.nu, forcing=p.forcing)


def _modal_system(p: FibreParams) -> ModalSystem:
    return modal_system(m=p.m, kappa=p.kappa, nu=p.nu)


def _inviscid_modes(p: FibreParams, kappa):
    return lambda0_squared(p.m, kappa)


MODEL = register(Model(
    name="fibre",
    summary="circular elastic fibre in viscous fluid, one wavenumber m (thesis 4)",
    params=FibreParams, hill_system=_hill_system, modal_system=_modal_system,
    inviscid_modes=_inviscid_modes,
    inviscid_method="closed form lambda0^2 = kappa m (m^2 - 1)/2 "
                    "(derivations/fibre_linear_result.md, 4a)",
    time_stepping=FIBRE_STEPPING))
