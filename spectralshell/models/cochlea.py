"""Basilar membrane in the 2D box cochlea: Hill-system physics of M cosine modes (thesis chapter 5).

Derived in ``derivations/cochlea_linear.py`` (results in ``derivations/cochlea_linear_result.md``)
from fields that satisfy the unsteady Stokes equations above and below the membrane, not from the
printed algebra. The membrane displacement h(x, t) = sum_{k=1..M} h_k(t) cos(k x) on x in [0, pi]
(walls without penetration or shear at x = 0, pi; infinitely deep chambers) obeys

    D(s_n) h_n = i tau G (h_{n-1} - h_{n+1}),     D(s) = diag(Z_k(s)) + kappa C,     G = kappa C,

the engine form of (5.9)-(5.10). Z_k is the pressure jump per unit displacement of the mode
cos(k x) (transfer function [[p]] = Z_k(s) h_k), with beta = sqrt(s/nu + k^2), Re beta > 0:

    Z_k(s) = 2 s^2 beta / (k (beta - k)) = 2 nu s beta (beta + k) / k
           = 2 s^2 / k + 2 s (nu k + sqrt(nu) sqrt(s + nu k^2)),

the last form being free of cancellation (used here; the printed (beta - k)(beta + k)^2 beta of
(5.12) loses digits when nu k^2 >> |s|). C is the cosine-Galerkin matrix of the stiffness profile
e^{-alpha x}: C_kj = c_{|k-j|} + c_{k+j} with the Fourier coefficients of e^{-alpha |x|} on
[-pi, pi], c_j = alpha (1 - (-1)^j e^{-alpha pi}) / (pi (alpha^2 + j^2)) (as printed after (5.8)).
C is symmetric positive definite, and C = I at alpha = 0, where the modes decouple into
Z_k(s) + kappa. D(0) = kappa C (Z_k(0) = 0: a steady displacement drives no flow), which is
(5.10).

Inviscid limit nu -> 0: Z_k = 2 s^2/k (added mass 1/k on each side), so D is the matrix polynomial
kappa C + s^2 diag(2/k); at alpha = 0 mode k is the Mathieu equation
h'' + (kappa k / 2)(1 + 2 tau sin t) h = 0.

Corrections to the print (see the result file): the y > 0 branch of v_k^n lacks a factor k; the
printed u_k^n has the opposite overall sign to continuity; the coefficient must use |k| for k < 0
(irrelevant for the cosine system, k >= 1); the s = 0 field has a spurious factor k.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .._validate import require_int_in_range, require_nonnegative, require_positive
from ..errors import ParameterError
from ..params.cochlea import CochleaParams
from ..params.physical import (COCHLEA_MODE_INPUTS, COCHLEA_UNITS, cochlea_mode_scale,
                               cochlea_physical)
from ..params.simulation import COCHLEA_STEPPING
from ..params.registry import Model, PhysicalInput, register
from .base import HillSystem, ModeFamily, ResponseModel


def stiffness_fourier(j: np.ndarray, alpha: float) -> np.ndarray:
    """Fourier coefficients c_j of e^{-alpha |x|} on [-pi, pi] (thesis, after (5.8)).

    Notes
    -----
    c_j = alpha (1 - (-1)^j e^{-alpha pi}) / (pi (alpha^2 + j^2)); for even j the factor
    1 - e^{-alpha pi} is evaluated as -expm1(-alpha pi), so small alpha loses no digits, and
    alpha = 0 gives c_0 = 1, c_j = 0 (the limit).
    """
    alpha = require_nonnegative("alpha", alpha)
    j = np.asarray(j)
    if alpha == 0.0:
        return np.where(j == 0, 1.0, 0.0)
    one_minus = np.where(j % 2 == 0, -np.expm1(-alpha * np.pi), 1.0 + np.exp(-alpha * np.pi))
    return alpha * one_minus / (np.pi * (alpha * alpha + j.astype(float) ** 2))


def coupling_matrix(modes: np.ndarray, alpha: float) -> np.ndarray:
    """C_kj = c_{|k-j|} + c_{k+j} for the cosine modes ``modes`` (k, j >= 1): the coefficient of
    cos(k x) in e^{-alpha x} cos(j x) on [0, pi] (derivation Part 6)."""
    k = np.asarray(modes)
    return stiffness_fourier(np.abs(k[:, None] - k[None, :]), alpha) + \
        stiffness_fourier(k[:, None] + k[None, :], alpha)


def transfer(s: np.ndarray, k: np.ndarray, nu: float) -> np.ndarray:
    """Z_k(s): pressure jump [[p]] per unit displacement of the cosine mode k (broadcast over s, k).

    Notes
    -----
    Z = 2 s^2/k + 2 s (nu k + sqrt(nu) sqrt(s + nu k^2)) (principal roots), equal to
    2 nu s beta (beta + k)/k of (5.9) with beta = sqrt(s/nu + k^2), Re beta > 0. On the
    physical sheet (Re(s + nu k^2) >= 0, which contains the imaginary axis) no two terms cancel; it
    agrees with 30-digit mpmath to ~1e-16 for nu = 1e-9..10 (tests). nu = 0 gives 2 s^2/k.
    """
    s = np.asarray(s, dtype=complex)
    k = np.asarray(k, dtype=float)
    nu = require_nonnegative("nu", nu)
    return 2.0 * s * s / k + 2.0 * s * (nu * k + np.sqrt(nu) * np.sqrt(s + nu * k * k))


def transfer_derivative(s: np.ndarray, k: np.ndarray, nu: float) -> np.ndarray:
    """dZ_k/ds = 4 s/k + 2 nu k + sqrt(nu) (2 r + s/r), r = sqrt(s + nu k^2) (r != 0)."""
    s = np.asarray(s, dtype=complex)
    k = np.asarray(k, dtype=float)
    nu = require_nonnegative("nu", nu)
    if nu == 0.0:
        return 4.0 * s / k + 0.0 * k
    r = np.sqrt(s + nu * k * k)
    return 4.0 * s / k + 2.0 * nu * k + np.sqrt(nu) * (2.0 * r + s / r)


def unforced(s: np.ndarray, *, kappa: float, nu: float, modes: np.ndarray,
             coupling: np.ndarray) -> np.ndarray:
    """D(s) = diag(Z_k(s)) + kappa C for the cosine modes ``modes``, shape (len(s), M, M)."""
    s = np.asarray(s, dtype=complex).ravel()
    modes = np.asarray(modes)
    out = np.broadcast_to(kappa * coupling, (s.size,) + coupling.shape).astype(complex, order="C")
    idx = np.arange(modes.size)
    out[:, idx, idx] += transfer(s[:, None], modes[None, :], nu)
    return out


def natural_frequencies(kappa: float, alpha: float, modes: np.ndarray) -> np.ndarray:
    """Inviscid natural angular frequencies (units of the forcing frequency), ascending.

    Notes
    -----
    det(s^2 diag(2/k) + kappa C) = 0 at s = +-i w: w^2 are the eigenvalues of the symmetric
    kappa diag(sqrt(k/2)) C diag(sqrt(k/2)). At alpha = 0, w_k = sqrt(kappa k / 2).
    """
    modes = np.asarray(modes, dtype=float)
    root = np.sqrt(modes / 2.0)
    w2 = np.linalg.eigvalsh(kappa * root[:, None] * coupling_matrix(modes.astype(int), alpha) * root[None, :])
    return np.sqrt(np.maximum(w2, 0.0))


def hill_system(*, kappa: float, nu: float, alpha: float, n_spatial: int | None = None,
                spatial_mode: int | None = None) -> HillSystem:
    """Hill-system physics of the cochlea model (see the module docstring).

    Parameters
    ----------
    kappa, nu, alpha : the dimensionless parameters of thesis 5.2 (see
        :class:`spectralshell.params.cochlea.CochleaParams`).
    n_spatial : number M of cosine modes k = 1..M (block size M).
    spatial_mode : alpha = 0 only: the single mode k = K (block size 1) instead.

    Notes
    -----
    ``n_resonant`` is the lowest inviscid natural frequency: the lowest-order (hence
    smallest-amplitude) parametric resonances are those of the slowest modes, so truncations start
    above it; stiffer modes resonate only in high-order tongues, and the temporal convergence loop
    raises N past them when they matter. For nu = 0 the matrix polynomial
    (kappa C, 0, diag(2/k)) is supplied.

    Raises
    ------
    ParameterError : kappa <= 0, nu < 0, alpha < 0, neither or both of n_spatial and
        spatial_mode, or spatial_mode with alpha != 0.
    """
    kappa = require_positive("kappa", kappa)
    nu = require_nonnegative("nu", nu)
    alpha = require_nonnegative("alpha", alpha)
    if (n_spatial is None) == (spatial_mode is None):
        raise ParameterError(f"(n_spatial, spatial_mode) = ({n_spatial}, {spatial_mode}) is invalid: "
                             "give exactly one of them")
    if spatial_mode is not None:
        if alpha != 0.0:
            raise ParameterError(f"spatial_mode = {spatial_mode} is invalid with alpha = {alpha:g}: "
                                 "a single mode needs alpha = 0")
        modes = np.array([require_int_in_range("spatial_mode", spatial_mode, 1)])
    else:
        modes = np.arange(1, require_int_in_range("n_spatial", n_spatial, 1) + 1)
    frequencies = natural_frequencies(kappa, alpha, modes)
    return _modes_system(kappa, nu, modes, coupling_matrix(modes, alpha), float(frequencies[0]),
                         float(frequencies[-1]))


def _modes_system(kappa: float, nu: float, modes: np.ndarray, C: np.ndarray,
                  n_resonant: float, n_highest: float | None = None) -> HillSystem:
    """The Hill system D(s) = diag(Z_k(s)) + kappa C, G = kappa C of the wavenumbers ``modes``."""
    G = kappa * C
    polynomial = None
    if nu == 0.0:
        polynomial = (G.copy(), np.zeros_like(G), np.diag(2.0 / modes))
    return HillSystem(name="cochlea", block_size=modes.size, forcing=G,
                      unforced=lambda s: unforced(s, kappa=kappa, nu=nu, modes=modes, coupling=C),
                      polynomial=polynomial, n_resonant=n_resonant, n_highest=n_highest,
                      inertia=np.diag(2.0 / modes),
                      diagonal_response=lambda s: transfer(np.asarray(s, dtype=complex).ravel()[:, None],
                                                           modes[None, :], nu))


def wavenumber_system(wavenumber: float, *, kappa: float, nu: float) -> HillSystem:
    """Uniform stiffness (alpha = 0): the scalar Hill system Z_k(s) + kappa of one cosine wave of
    real wavenumber k > 0, D(s_n) h_n = i tau kappa (h_{n-1} - h_{n+1}).

    The physical modes of the box are the integers k = 1, 2, ... (``hill_system(spatial_mode=k)``
    is the same system); a real k treats the wavenumber as a continuous parameter, as in the
    Ince-Strutt diagrams of tau against k (thesis Fig 5.11). Inviscid (nu = 0): the Mathieu
    equation h'' + (kappa k / 2)(1 + 2 tau sin t) h = 0, natural frequency sqrt(kappa k / 2).
    """
    k = require_positive("wavenumber", wavenumber)
    return _modes_system(require_positive("kappa", kappa), require_nonnegative("nu", nu),
                         np.array([k]), np.eye(1), float(np.sqrt(kappa * k / 2.0)))


def natural_mode_family(*, alpha: float, n_spatial: int):
    """zeta -> (T, T') with T(s) = diag(Z_k(s; nu = zeta)) + C: the unforced operator D(s)/kappa
    in the time unit 1/sqrt(kappa), where s = gamma/sqrt(kappa) and zeta = nu/sqrt(kappa) ((5.14);
    the natural modes depend on zeta and alpha only). T' = diag(dZ_k/ds)."""
    modes = np.arange(1, require_int_in_range("n_spatial", n_spatial, 1) + 1)
    C = coupling_matrix(modes, alpha)
    idx = np.arange(modes.size)

    def family(zeta: float):
        def matrix(s: complex) -> np.ndarray:
            out = C.astype(complex)
            out[idx, idx] += transfer(s, modes, zeta)
            return out

        return matrix, lambda s: np.diag(transfer_derivative(s, modes, zeta))

    return family


def sheet_margin(s: complex, zeta: float, n_spatial: int) -> float:
    """min_k Re sqrt(s/zeta + k^2): > 0 when every mode's field decays away from the membrane
    (the physical sheet), 0 on the branch cut s <= -zeta k^2 of some k."""
    k = np.arange(1, n_spatial + 1)
    return float(np.min(np.sqrt(s / zeta + k * k).real))


def natural_mode_residual_mp(s, *, zeta, alpha, n_spatial: int) -> tuple:
    """(det T(s), d det T/ds) in mpmath at the current ``mpmath.mp.dps``, T = diag(Z_k) + C of
    :func:`natural_mode_family` (Z_k, dZ_k/ds, c_j all evaluated at that precision).

    Notes
    -----
    d det T / ds = det T tr(T^{-1} T') (Jacobi's formula), T' = diag(dZ_k/ds); their ratio is the
    Newton step of det T in trace form (one determinant and one inverse of the M x M matrix).
    Where mpmath's LU factorisation finds T singular to working precision (det returned as 0),
    the pair is (0, 1): a zero Newton step.
    """
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    s, zeta, alpha = mpmath.mpmathify(s), mpmath.mpf(zeta), mpmath.mpf(alpha)
    M = require_int_in_range("n_spatial", n_spatial, 1)
    if alpha == 0:
        c = [mpmath.mpf(1)] + [mpmath.mpf(0)] * (2 * M)
    else:
        odd, even = 1 + mpmath.exp(-alpha * mpmath.pi), -mpmath.expm1(-alpha * mpmath.pi)
        c = [alpha * (odd if j % 2 else even) / (mpmath.pi * (alpha**2 + j * j))
             for j in range(2 * M + 1)]
    T = mpmath.matrix(M, M)
    dZ = []
    root_zeta = mpmath.sqrt(zeta)
    for k in range(1, M + 1):
        for j in range(1, M + 1):
            T[k - 1, j - 1] = c[abs(k - j)] + c[k + j]
        r = mpmath.sqrt(s + zeta * k * k)
        T[k - 1, k - 1] += 2 * s * s / k + 2 * s * (zeta * k + root_zeta * r)
        dZ.append(4 * s / k + 2 * zeta * k + (root_zeta * (2 * r + s / r) if zeta else 0))
    det = mpmath.det(T)
    if det == 0:  # mpmath's LU found T singular to working precision: s is a root
        return det, mpmath.mpf(1)
    inverse = mpmath.inverse(T)
    return det, det * mpmath.fsum(inverse[k, k] * dZ[k] for k in range(M))


def upper_half_contour(*, zeta: float, n_spatial: int, radius: float, depth: float) -> list[complex]:
    """Counter-clockwise polygon around the modes with Im s >= 0 and |Re s|, Im s <= ``radius``.

    Along the real axis it runs on the upper edge of the cut s < -zeta (points x + 0j: principal
    roots give the limit from Im s > 0), with a vertex at each branch point -zeta k^2, and dips
    to Im s = -``depth`` under (-zeta, 0), where T is analytic and real (real modes lie there;
    the dip also holds the mirror images of the modes with 0 < Im s < depth there). For
    :func:`spectralshell.solvers.nonlinear_eigen.count_by_winding`: the region holds every mode of
    the physical sheet with Im s >= 0 inside the box.
    """
    k = np.arange(require_int_in_range("n_spatial", n_spatial, 1), 0, -1)
    R = require_positive("radius", radius)
    cuts = -require_positive("zeta", zeta) * k * k
    depth = require_positive("depth", depth)
    left = max(-zeta, -R)
    return ([complex(-R, 0.0)] + [complex(x, 0.0) for x in cuts[cuts > -R]] +
            [complex(left, -depth), complex(0.0, -depth), 0j, complex(R, 0.0), complex(R, R),
             complex(-R, R)])


#: Width (dimensionless, x in [0, pi]) of the Gaussian pressure load at the base that drives the
#: pure-tone response: a stand-in for the stapes, which the box model has no inlet for.
TONE_WIDTH = 0.05


def base_load(modes: np.ndarray, width: float = TONE_WIDTH) -> np.ndarray:
    """Cosine coefficients (up to a constant) of the load exp(-(x/width)^2) at the base x = 0:
    (2/pi) int_0^inf e^{-(x/w)^2} cos(kx) dx = (w/sqrt(pi)) e^{-(k w)^2/4}; the constant is
    dropped (responses are normalised)."""
    modes = np.asarray(modes, dtype=float)
    return np.exp(-(modes * require_positive("width", width)) ** 2 / 4.0)


def tone_response(*, kappa: float, nu: float, alpha: float, n_spatial: int,
                  frequency: float = 1.0, width: float = TONE_WIDTH) -> np.ndarray:
    """Cosine amplitudes h_k of the passive response (tau = 0) to the base load
    ``base_load`` oscillating as e^{i frequency t}: D(i frequency) h = f (the externally forced
    pure tone of LeVeque, Peskin & Lax, thesis ref. [74])."""
    modes = np.arange(1, require_int_in_range("n_spatial", n_spatial, 1) + 1)
    D = unforced(np.array([1j * require_positive("frequency", frequency)]), kappa=kappa, nu=nu,
                 modes=modes, coupling=coupling_matrix(modes, alpha))[0]
    return np.linalg.solve(D, base_load(modes, width).astype(complex))


def wkb_peak(*, kappa: float, nu: float, alpha: float, frequency: float = 1.0) -> float:
    """Leading-order WKB location (dimensionless x) of the envelope peak of a wave of angular
    frequency ``frequency`` (units of the forcing frequency) on stiffness kappa e^{-alpha x}.

    Notes
    -----
    Derived in derivations/cochlea_wkb.py: local wavenumber k(x) = 2 w^2 e^{alpha x}/kappa
    (inviscid dispersion 2 w^2/k = kappa e^{-alpha x}), amplitude ~ k (wave action), viscous
    decay ~ k^2 sqrt(nu/(2 w)) (Stokes layers, k^2 << w/nu); the peak is where the decay equals
    d ln k/dx = alpha: k_p = sqrt(alpha) (2 w/nu)^{1/4}, x_p = ln(kappa k_p/(2 w^2))/alpha. In
    physical units dx_p/d ln(omega) = -7/(4 lambda_c) for a pure tone (kappa ~ omega^-2,
    nu ~ omega^-1): the log-linear place map (LeVeque, Peskin & Lax).
    """
    w = require_positive("frequency", frequency)
    kp = np.sqrt(require_positive("alpha", alpha)) * (2.0 * w / require_positive("nu", nu)) ** 0.25
    return float(np.log(require_positive("kappa", kappa) * kp / (2.0 * w * w)) / alpha)


# ----------------------------------------------------------------------------- the plug-in


def _hill_system(p: CochleaParams) -> HillSystem:
    if p.n_spatial is None and p.spatial_mode is None:
        raise ParameterError("n_spatial = None is invalid here: this computation needs a fixed "
                             "number of cosine modes (only floquet converges in n_spatial)")
    return hill_system(kappa=p.kappa, nu=p.nu, alpha=p.alpha, n_spatial=p.n_spatial,
                       spatial_mode=p.spatial_mode)


def mode_family(p: CochleaParams) -> ModeFamily:
    """The natural modes of the cochlea with M = n_spatial cosine modes as a
    :class:`ModeFamily`: T(s) = diag(Z_k(s; zeta)) + C (D(gamma)/kappa, s = gamma/sqrt(kappa),
    zeta = nu/sqrt(kappa), thesis (5.14)), started from the inviscid modes s = i w_j (w_j^2 the
    eigenvalues of diag(sqrt(k/2)) C diag(sqrt(k/2))).

    Near the cut s < -zeta (large zeta) the least damped modes become nearly real decays just
    above the cut, thesis Fig 5.7 right: at zeta = 1e-2, alpha = 1.56, M = 20 the three slowest
    have Im s = 2.5e-8, 1.6e-7, 7.5e-7; from zeta ~ 0.013 they pass the branch point -zeta one by
    one and become real decays on (-zeta, 0) (their mirror images leave through the branch
    point onto the other sheet).
    """
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    if p.n_spatial is None or p.spatial_mode is not None:
        raise ParameterError(f"n_spatial = {p.n_spatial!r} is invalid for natural modes: give the "
                             "number of cosine modes M (e.g. 20, as in thesis Fig 5.7)")
    M, alpha = p.n_spatial, p.alpha
    return ModeFamily(
        name="cochlea", zeta=p.nu / np.sqrt(p.kappa),
        at=natural_mode_family(alpha=alpha, n_spatial=M),
        start=1j * natural_frequencies(1.0, alpha, np.arange(1, M + 1)),
        sheet_margin=lambda s, zeta: sheet_margin(s, zeta, M),
        contour=lambda zeta, radius, depth: upper_half_contour(zeta=zeta, n_spatial=M,
                                                               radius=radius, depth=depth),
        residual_mp=lambda s, zeta: natural_mode_residual_mp(s, zeta=zeta, alpha=alpha,
                                                             n_spatial=M),
        gamma_scale=float(np.sqrt(p.kappa)),
        zeta_mp=lambda: mpmath.mpf(p.nu) / mpmath.sqrt(mpmath.mpf(p.kappa)),
        gamma_scale_mp=lambda: mpmath.sqrt(mpmath.mpf(p.kappa)))


def response_model(p: CochleaParams) -> ResponseModel:
    """The cochlea's response envelopes along x in [0, pi] (thesis 5.5): cosine modes
    cos(k x), k = 1..M, the pure tone of :func:`tone_response` (its peak searched beyond
    4 TONE_WIDTH, past the load), and the WKB peak of :func:`wkb_peak` (needs nu > 0 and
    alpha > 0)."""
    if p.spatial_mode is not None:
        raise ParameterError(f"spatial_mode = {p.spatial_mode} is invalid for response: the "
                             "envelope needs n_spatial cosine modes")

    def wkb(frequency: float) -> float | None:
        if p.nu > 0 and p.alpha > 0:
            return wkb_peak(kappa=p.kappa, nu=p.nu, alpha=p.alpha, frequency=frequency)
        return None

    return ResponseModel(
        domain=(0.0, float(np.pi)),
        basis=lambda x, M: np.cos(np.outer(x, np.arange(1, M + 1))),
        tone=lambda M: tone_response(kappa=p.kappa, nu=p.nu, alpha=p.alpha, n_spatial=M),
        tone_start=4 * TONE_WIDTH, wkb_peak=wkb,
        wkb_note="the WKB peak needs nu > 0 and alpha > 0: reported as NaN",
        with_modes=lambda M: dataclasses.replace(p, n_spatial=M))


MODEL = register(Model(
    name="cochlea",
    summary="2D box cochlea: basilar membrane of graded stiffness in viscous fluid (thesis 5)",
    params=CochleaParams, hill_system=_hill_system, mode_family=mode_family,
    spatial=True,
    physical=PhysicalInput(units=COCHLEA_UNITS, convert=cochlea_physical,
                           note="Table 5.1 defaults for the missing ones; omega required"),
    mode_inputs=COCHLEA_MODE_INPUTS, mode_scale=cochlea_mode_scale, response=response_model,
    time_stepping=COCHLEA_STEPPING))
