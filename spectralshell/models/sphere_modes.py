"""Natural modes of the spherical membrane (tau = 0): the dispersion relation in beta (thesis 7.2).

Notation. gamma = s is the complex rate of a mode X ~ exp(gamma t) (Re gamma: decay rate, Im gamma:
angular frequency); beta = sqrt(gamma / nu), Re beta > 0 on the physical sheet (7.9);
zeta = nu / sqrt(kappa) (7.13); sigma = gamma / sqrt(kappa) = zeta beta^2; qh = (m-1)(m+2);
A0 = (2m+1)/(m(m+1)); lam0^2 = m(m+1)(m-1)(m+2)/(2m+1), so lambda0 = sqrt(kappa) lam0 (7.4);
P = beta i_{m+1}(beta)/i_m(beta), Q = beta k_{m-1}(beta)/k_m(beta) (DLMF 10.47 functions, as in
:mod:`spectralshell.models.sphere` and ``derivations/sphere_linear_result.md``).

Scaling. Every entry of D(s)/kappa is sigma^2 (...) + qh with P and Q functions of
beta = sqrt(sigma/zeta) alone, so the roots are sigma(zeta, m) and gamma = sqrt(kappa) sigma:
(kappa, nu) enter only through zeta, as the thesis states after (7.12).

Dispersion relations. With x = 1/Q and y = 1/P the poloidal determinant collapses (the x^2 and y^2
terms of D_YY D_PsiPsi - D_YPsi D_PsiY cancel and the xy terms add up to (2m+1)^2 xy/(m(m+1))) to

    Delta(beta) = det D(gamma) / kappa^2                                                    (M1)
                = A0 sigma^4 (x + y + (2m+1) x y) + (2m+1) qh sigma^2 (1/(m(m+1)) + x/(m+1) + y/m) + qh^2,

whose roots are those of the printed M of (7.11)-(7.12), i.e. (7.14); the toroidal relation
((6.29) at tau = 0) is

    Delta_T(beta) = D_Phi(gamma) / kappa = zeta^2 beta^2 (2m+1+P+Q) + qh.                        (M2)

Analytic structure in beta. P is even and meromorphic, with poles at the zeros of i_m, which
all lie on the imaginary axis (i_m(z) = i^-m j_m(iz), DLMF 10.47.12, and j_m has only real zeros,
DLMF 10.21(i)); Q is a rational function (DLMF 10.49.12: k_n(z) = (pi/2) e^{-z} times a polynomial
in 1/z, a reverse Bessel polynomial, DLMF 18.34) with poles at the zeros of k_m, all in
Re beta < 0. So (M1) and (M2) are meromorphic in the whole beta-plane: the branch cut of D on
gamma <= 0 is the imaginary beta axis, and continuing across it into Re beta < 0 gives the second
sheet, where the exterior field grows at infinity (roots there are resonances, not modes). (M1)
has poles only at the zeros of P (i_{m+1} = 0, imaginary axis) and of Q (k_{m-1} = 0,
Re beta < 0); it is finite at beta = 0 (D(0) = q I) and analytic in Re beta > 0. Newton's method
works on the entire functions F = Delta i_{m+1}(beta) k_{m-1}(beta) / beta and
F_T = Delta_T beta i_m(beta) k_m(beta), whose steps F/F' = Delta / (Delta' + Delta g'/g) need only

    beta g'/g = beta^2 (1/P - 1/Q) - 4          (poloidal),    beta g'/g = P - Q    (toroidal),

by DLMF 10.51.4-10.51.5 (z i_{n+1}'/i_{n+1} = z i_n/i_{n+1} - (n+2), z k_{n-1}'/k_{n-1} =
(n-1) - z k_n/k_{n-1}), and the derivatives of P and Q come from the Riccati form of the modified
spherical Bessel equation DLMF 10.47.2 (L = z w'/w satisfies z L' = z^2 + n(n+1) - L - L^2):

    beta P' = beta^2 - (2m+1) P - P^2,          beta Q' = Q^2 + (2m+1) Q - beta^2.              (R)

(7.11)-(7.12) are written in the same scaled variables (zeta^2 beta^4 = sigma^2).

Mode structure (m = 2..60, zeta = 1e-7..10, checked in tests/test_sphere_modes.py). With
Im gamma >= 0 the physical sheet holds two poloidal modes and one toroidal mode:

* argument-principle counts of det D and D_Phi over delta <= Re beta, |beta| up to four times
  the largest mode, find exactly the modes found there, and the modes with Re beta < delta are the
  continuation in zeta of the same branches (none crosses the cut; the smallest Re beta/|beta| of
  a branch is rounding, about -7e-15);
* the poloidal pair are the Lamb oscillation (gamma -> i lambda0, (7.4)) and the tangential
  (Psi) relaxation (|gamma| ~ (q^2/(4 nu))^(1/3)); at large zeta both become the steady-Stokes
  relaxations -q/(nu mu_i). The Psi branch reaches the cut first, abruptly (for m = 2:
  Im gamma/|Re gamma| < 0.01 from zeta = 0.23; m = 3, 4: 0.26, 0.27), and becomes the least damped
  mode from zeta = 0.26, 0.28, 0.27 (m = 2, 3, 4); the Lamb branch follows gradually
  (Im gamma/|Re gamma| < 0.01 from zeta = 2.9, 1.3, 0.83);
* near the cut a branch keeps Re beta > 0 but small, of relative order |beta|^(2m-1) or less (the
  odd, Basset-type part of Q starts at beta^(2m+1)): soon its sheet is not resolvable in double
  precision, and for large m at no practical precision; such a mode is, to working accuracy, a
  real exponential;
* the other roots of (M1) we located are on the second sheet: the interior vortical (cavity)
  resonances near beta = +-i j_{m+1,k} (toroidal: j_{m,k}), with Re beta < 0 (e.g. -1.76e-15 at
  m = 2, zeta = 1e-3, from 40-digit arithmetic; 1e-25 to 1e-5 in magnitude elsewhere), the mirror
  images -conj(beta) of the modes (nearly exact roots when the Basset-type part is negligible),
  and roots tied to the zeros of k_{m-1}.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Iterator

import numpy as np

from .._validate import require_choice, require_int_in_range, require_positive
from ..errors import ParameterError
from ..special.spherical_scalar import ratio_i_scalar
from .base import ModalSystem, damped_newton, modal_system_in_beta


def lambda0_squared(m: int, kappa: float) -> float:
    """Inviscid natural frequency squared, lambda0^2 = kappa m(m+1)(m-1)(m+2)/(2m+1) (6.23)."""
    return kappa * m * (m + 1) * (m - 1) * (m + 2) / (2 * m + 1)


__all__ = ["lambda0_squared", "ZETA_MIN", "ZETA_MAX", "poloidal_residual", "toroidal_residual",
           "poloidal_residual_mp", "toroidal_residual_mp", "poloidal_seeds", "toroidal_seeds",
           "inviscid_limit", "psi_relaxation_limit", "stokes_limit", "stokes_matrix",
           "toroidal_limits", "modal_system"]

#: Range of zeta = nu/sqrt(kappa) over which the seeds were verified (tests/test_sphere_modes.py).
ZETA_MIN = 1e-10
ZETA_MAX = 1e3
M_MODES_MAX = 200

# |beta| below which P = beta^2/(2m+3) to double precision: the next term of DLMF 10.53.3 is
# relatively beta^2/((2m+3)(2m+5)) < 1e-16.
_BETA_SERIES = 1e-7


def _p_q(m: int, beta: complex) -> tuple[complex, complex, complex, complex]:
    """P, Q and their beta-derivatives (R) at any beta != 0 (both sheets).

    P is even (i_m(-z) = (-1)^m i_m(z)), so Re beta < 0 uses -beta. Q = beta^2/t_{m-1} with
    t_0 = 1 + beta, t_n = (2n+1) + beta^2/t_{n-1} (DLMF 10.51.4 for k_n, as in
    special/spherical.py); this rational recurrence holds on both sheets.
    """
    b2 = beta * beta
    if abs(beta) < _BETA_SERIES:
        P = b2 / (2 * m + 3)
        dP = 2.0 * beta / (2 * m + 3)
    else:
        z = beta if beta.real >= 0 else -beta
        P = z * ratio_i_scalar(m, z)
        dP = (b2 - (2 * m + 1) * P - P * P) / beta
    t = 1.0 + beta
    for n in range(1, m):
        t = (2 * n + 1) + beta * (beta / t)
    Q = beta * (beta / t)
    dQ = (Q * Q + (2 * m + 1) * Q - b2) / beta
    return P, Q, dP, dQ


# ----------------------------------------------------------------------------- residuals


def _poloidal_from_pq(m, zeta, beta, P, Q, dP, dQ):
    """(Delta, Delta' + Delta g'/g) of (M1) from P, Q and their derivatives (any number type)."""
    qh = (m - 1) * (m + 2)
    a0 = (2 * m + 1) / (m * (m + 1))
    x, y = 1 / Q, 1 / P
    dx, dy = -dQ * x * x, -dP * y * y
    sig = zeta * beta * beta
    s2 = sig * sig
    ds2 = 4 * s2 / beta
    u = x + y + (2 * m + 1) * x * y
    du = dx + dy + (2 * m + 1) * (dx * y + x * dy)
    v = 1 / (m * (m + 1)) + x / (m + 1) + y / m
    dv = dx / (m + 1) + dy / m
    c = (2 * m + 1) * qh
    delta = a0 * s2 * s2 * u + c * s2 * v + qh * qh
    ddelta = a0 * (2 * s2 * ds2 * u + s2 * s2 * du) + c * (ds2 * v + s2 * dv)
    return delta, ddelta + delta * (beta * (y - x) - 4 / beta)


def _toroidal_from_pq(m, zeta, beta, P, Q, dP, dQ):
    """(Delta_T, Delta_T' + Delta_T g'/g) of (M2) from P, Q and their derivatives."""
    qh = (m - 1) * (m + 2)
    z2 = zeta * zeta
    bracket = 2 * m + 1 + P + Q
    delta = z2 * beta * beta * bracket + qh
    ddelta = z2 * (2 * beta * bracket + beta * beta * (dP + dQ))
    return delta, ddelta + delta * (P - Q) / beta


def poloidal_residual(beta: complex, *, m: int, zeta: float) -> tuple[complex, complex]:
    """(Delta, Newton derivative) of the poloidal dispersion relation (M1) in double precision.

    Notes
    -----
    Delta = det D(gamma)/kappa^2 at gamma = nu beta^2, (7.14); the second value is
    Delta' + Delta g'/g, so that Delta divided by it is the Newton step of the entire function
    F = g Delta (module docstring). Valid on both sheets; beta = 0 returns (qh^2, 0) (D(0) = q I).
    """
    beta = complex(beta)
    if beta == 0:
        return complex((m - 1) * (m + 2)) ** 2, 0j
    return _poloidal_from_pq(m, zeta, beta, *_p_q(m, beta))


def toroidal_residual(beta: complex, *, m: int, zeta: float) -> tuple[complex, complex]:
    """(Delta_T, Newton derivative) of the toroidal dispersion relation (M2) in double precision."""
    beta = complex(beta)
    if beta == 0:
        return complex((m - 1) * (m + 2)), 0j
    return _toroidal_from_pq(m, zeta, beta, *_p_q(m, beta))


def _p_q_mp(m: int, beta):
    """P, Q, P', Q' in mpmath at the current precision from mpmath's own I and K of half-integer
    order (i_n/i_{n-1} = I_{n+1/2}/I_{n-1/2}, DLMF 10.47.7; both ratios are single-valued, so
    they hold on both sheets), derivatives from (R)."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    P = beta * mpmath.besseli(m + 1.5, beta) / mpmath.besseli(m + 0.5, beta)
    Q = beta * mpmath.besselk(m - 0.5, beta) / mpmath.besselk(m + 0.5, beta)
    b2 = beta * beta
    dP = (b2 - (2 * m + 1) * P - P * P) / beta
    dQ = (Q * Q + (2 * m + 1) * Q - b2) / beta
    return P, Q, dP, dQ


def poloidal_residual_mp(beta, *, m: int, zeta) -> tuple:
    """(M1) and its Newton derivative in mpmath at the current ``mpmath.mp.dps`` (beta != 0)."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    beta = mpmath.mpc(beta)
    zeta = mpmath.mpf(zeta)
    return _poloidal_from_pq(mpmath.mpf(m), zeta, beta, *_p_q_mp(m, beta))


def toroidal_residual_mp(beta, *, m: int, zeta) -> tuple:
    """(M2) and its Newton derivative in mpmath at the current ``mpmath.mp.dps`` (beta != 0)."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    beta = mpmath.mpc(beta)
    zeta = mpmath.mpf(zeta)
    return _toroidal_from_pq(mpmath.mpf(m), zeta, beta, *_p_q_mp(m, beta))


# ----------------------------------------------------------------------------- asymptotic limits


def stokes_matrix(m: int) -> np.ndarray:
    """R0, the steady-Stokes load H(s) = nu s R0 + O(s^2) of the poloidal pair (small beta).

    From P = beta^2/(2m+3) + O(beta^4) (DLMF 10.53.3) and Q = beta^2/(2m-1) + O(beta^4)
    (derivations/sphere_linear_result.md, section 3):
    R0 = [[m(2m-1)/(m+1) + (m+1)(2m+3)/m, -3(2m+1)], [-3(2m+1)/(m(m+1)), 2(2m+1)]].
    """
    return np.array([[m * (2 * m - 1) / (m + 1) + (m + 1) * (2 * m + 3) / m, -3.0 * (2 * m + 1)],
                     [-3.0 * (2 * m + 1) / (m * (m + 1)), 2.0 * (2 * m + 1)]])


def inviscid_limit(*, m: int, kappa: float, nu: float) -> complex:
    """Lamb oscillation at small zeta: gamma = i lambda0 - c_m sqrt(i lambda0 nu) + O(nu).

    Notes
    -----
    lambda0^2 = kappa m(m+1)(m-1)(m+2)/(2m+1) (7.4)/(7.5). With the large-argument forms
    P = beta - (m+1) + O(1/beta), Q = beta - m + O(1/beta) (DLMF 10.40.1, 10.49.12) the Psi row of
    D is q + O(nu^(1/2)) and the Y row gives s^2 (A0 + c1/beta) + q = 0, c1 = m/(m+1) + (m+1)/m,
    hence c_m = c1/(2 A0) = (2m^2 + 2m + 1)/(2(2m+1)) (a Stokes-layer correction: Re gamma < 0).
    """
    lam0 = math.sqrt(lambda0_squared(m, kappa))
    c = (2 * m * m + 2 * m + 1) / (2 * (2 * m + 1))
    return 1j * lam0 - c * cmath.sqrt(1j * lam0 * nu)


def psi_relaxation_limit(*, m: int, kappa: float, nu: float) -> complex:
    """Tangential (Psi) relaxation at small zeta: 2 s^(3/2) nu^(1/2) = -q, so
    gamma = (q^2/(4 nu))^(1/3) exp(2 pi i/3), q = kappa (m-1)(m+2).

    Notes
    -----
    At |s| >> lambda0 the Psi row of D is s^2 (1/P + 1/Q) + q = 2 s^2/beta + q + O(s^2/beta^2)
    (derivations/sphere_linear_result.md, section 4(a)); the principal root has arg beta = pi/3.
    """
    q = kappa * (m - 1) * (m + 2)
    return (q * q / (4 * nu)) ** (1 / 3) * cmath.exp(2j * math.pi / 3)


def stokes_limit(*, m: int, kappa: float, nu: float) -> np.ndarray:
    """Overdamped poloidal relaxations at large zeta: gamma_i = -q/(nu mu_i), mu_i = eig R0
    (ascending, least damped first), from det(q I + nu s R0) = 0 (:func:`stokes_matrix`)."""
    q = kappa * (m - 1) * (m + 2)
    mu = np.sort(np.linalg.eigvals(stokes_matrix(m)).real)[::-1]
    return -q / (nu * mu)


def toroidal_limits(*, m: int, kappa: float, nu: float) -> tuple[complex, float]:
    """Toroidal mode at small and at large zeta, from (M2).

    Notes
    -----
    Small zeta: P + Q = 2 beta - 1 + O(1/beta) gives 2 nu s beta = -q, i.e.
    gamma = (q/2)^(2/3) nu^(-1/3) exp(2 pi i/3). Large zeta: P, Q = O(beta^2) give
    nu s (2m+1) = -q, i.e. gamma = -q/((2m+1) nu) (steady-Stokes torsional relaxation).
    """
    q = kappa * (m - 1) * (m + 2)
    small = (q / 2) ** (2 / 3) * nu ** (-1 / 3) * cmath.exp(2j * math.pi / 3)
    return small, -q / ((2 * m + 1) * nu)


# ----------------------------------------------------------------------------- seeds


def _pmul(a: list[float], b: list[float]) -> list[float]:
    """Product of two polynomials (ascending coefficients)."""
    out = [0.0] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            out[i + j] += x * y
    return out


def _padd(*polys: list[float]) -> list[float]:
    """Sum of polynomials (ascending coefficients)."""
    out = [0.0] * max(len(p) for p in polys)
    for p in polys:
        for i, x in enumerate(p):
            out[i] += x
    return out


def _pscale(c: float, p: list[float], shift: int = 0) -> list[float]:
    """c beta^shift p(beta)."""
    return [0.0] * shift + [c * x for x in p]


def _rational_model(m: int, zeta: float, component: str) -> list[float]:
    """Ascending coefficients of (M1) or (M2) with P, Q replaced by the [3/2] approximants

        P ~ beta^2 p1/p2,  p1 = beta + m + 2,  p2 = beta^2 + (2m+3) beta + (m+2)(2m+3),
        Q ~ beta^2 q1/q2,  q1 = beta + m - 1,  q2 = beta^2 + (2m-1) beta + (m-1)(2m-1),

    multiplied by p2 q2 / beta^4 (poloidal, degree 9) or p2 q2 (toroidal, degree 7). Each
    approximant is exact to O(beta^2) at 0 (P ~ beta^2/(2m+3), Q ~ beta^2/(2m-1), DLMF 10.53.3
    and 10.49.12), has no beta^3 term (P is even; the odd part of Q starts at beta^(2m+1)), and is
    exact to O(1) at infinity (P ~ beta - (m+1), Q ~ beta - m, DLMF 10.40.1); for m = 2 the Q form
    is exact (Q = beta^2 (1 + beta)/(beta^2 + 3 beta + 3)).
    """
    p1, p2 = [m + 2.0, 1.0], [(m + 2.0) * (2 * m + 3), 2 * m + 3.0, 1.0]
    q1, q2 = [m - 1.0, 1.0], [(m - 1.0) * (2 * m - 1), 2 * m - 1.0, 1.0]
    qh = (m - 1.0) * (m + 2)
    p1q2, q1p2, p2q2 = _pmul(p1, q2), _pmul(q1, p2), _pmul(p2, q2)
    if component == "toroidal":
        return _padd(_pscale(zeta * zeta * (2 * m + 1), p2q2, 2),
                     _pscale(zeta * zeta, _padd(p1q2, q1p2), 4), _pscale(qh, p2q2))
    a0 = (2 * m + 1) / (m * (m + 1))
    c = (2 * m + 1) * qh * zeta * zeta
    return _padd(_pscale(zeta ** 4 * a0, _padd(p1q2, q1p2), 6),
                 _pscale(zeta ** 4 * a0 * (2 * m + 1), p2q2, 4),
                 _pscale(c / (m * (m + 1)), _pmul(p1, q1), 4),
                 _pscale(c / (m + 1), p1q2, 2), _pscale(c / m, q1p2, 2),
                 _pscale(qh * qh, _pmul(p1, q1)))


def _rational_roots(m: int, zeta: float, component: str) -> list[complex]:
    """Roots beta with Im beta > 0 of :func:`_rational_model`, from the eigenvalues of the
    companion matrix in the scaled variable beta sqrt(zeta) (sqrt(zeta) beta = sqrt(sigma) is of
    order one for the Lamb mode; numpy's eigen-solver balances the rest)."""
    coeffs = _rational_model(m, zeta, component)
    rho = 1.0 / math.sqrt(zeta)
    scaled = [c * rho ** k for k, c in enumerate(coeffs)]
    n = len(scaled) - 1
    companion = np.zeros((n, n))
    companion[np.arange(1, n), np.arange(n - 1)] = 1.0
    companion[:, -1] = [-c / scaled[-1] for c in scaled[:-1]]
    roots = np.linalg.eigvals(companion) * rho
    return [complex(r) for r in roots if r.imag > 0 and np.isfinite(r)]


def _uniform_model(beta: complex, m: int, zeta: float, component: str) -> tuple[complex, complex]:
    """(M1) or (M2) and its derivative with P, Q replaced by the uniform (Debye-type) approximants
    P ~ beta^2/(m+1+sqrt((m+2)^2+beta^2)), Q ~ beta^2/(m+sqrt((m-1)^2+beta^2)): the limits of
    :func:`_rational_model`, plus the turning-point structure of DLMF 10.41 at |beta| ~ m (which
    matters for large m). Being even in beta, it has no Basset-type part."""
    r1 = cmath.sqrt((m + 2) ** 2 + beta * beta)
    r2 = cmath.sqrt((m - 1) ** 2 + beta * beta)
    d1, d2 = m + 1 + r1, m + r2
    b2 = beta * beta
    P, Q = b2 / d1, b2 / d2
    dP = 2 * beta / d1 - b2 * (beta / r1) / (d1 * d1)
    dQ = 2 * beta / d2 - b2 * (beta / r2) / (d2 * d2)
    if component == "toroidal":
        delta, fp = _toroidal_from_pq(m, zeta, beta, P, Q, dP, dQ)
        return delta, fp - delta * (P - Q) / beta
    delta, fp = _poloidal_from_pq(m, zeta, beta, P, Q, dP, dQ)
    return delta, fp - delta * (beta * (1 / P - 1 / Q) - 4 / beta)


def _refine_uniform(beta: complex, m: int, zeta: float, component: str) -> complex | None:
    """Damped Newton on :func:`_uniform_model` from beta (relative tolerance 1e-8)."""
    return damped_newton(lambda b: _uniform_model(b, m, zeta, component), beta, rtol=1e-8)


def _fold(beta: complex, offset: float = 0.0) -> complex:
    """The point of the closed first quadrant with the same |Re|, |Im| (Re at least offset |beta|).

    The approximate models are even in beta, so their roots come in pairs +-beta, +-conj(beta);
    the mode is the member in the first quadrant. The offset moves a seed off the imaginary axis,
    on which a nearly even function keeps Newton's iterates (and would miss a root just off it).
    """
    return complex(max(abs(beta.real), offset * abs(beta)), abs(beta.imag))


# Regimes of the seeds, by r = |beta_L|/m, beta_L the Lamb seed: the small-zeta formulas are within
# about 3 % of the modes for r >= 4, the Stokes ones within 2 % for r <= 0.3 (m = 2..60; at most a
# few Newton steps either way).
_SMALL_ZETA_R = 4.0
_LARGE_ZETA_R = 0.3


def _seed_stream(m: int, zeta: float, component: str, small: list[complex], large: list[complex],
                 ratio: float) -> Iterator[complex]:
    """Candidates, best first; duplicates (1e-6 relative) are skipped.

    Asymptotic seeds come first in their regime; then the roots of the rational model refined on
    the uniform model, the same moved off the axis, the unrefined roots, and the asymptotic seeds
    moved off the axis.
    """
    seen: list[complex] = []

    def fresh(b: complex | None) -> bool:
        if b is None or b == 0 or not cmath.isfinite(b) or any(abs(b - s) <= 1e-6 * abs(b) for s in seen):
            return False
        seen.append(b)
        return True

    def refined(b: complex) -> complex:
        r = _refine_uniform(_fold(b), m, zeta, component)
        return _fold(b) if r is None else _fold(r)

    first = small if ratio >= _SMALL_ZETA_R else large if ratio <= _LARGE_ZETA_R else []
    for b in first:
        if fresh(_fold(b)):
            yield seen[-1]
    roots = sorted(_rational_roots(m, zeta, component), key=lambda r: r.real < 0)
    polished = []
    for r in roots:
        polished.append(refined(r))
        if fresh(polished[-1]):
            yield polished[-1]
    for b in polished + roots + small + large:
        if fresh(_fold(b, 0.02)):
            yield seen[-1]


def _beta_of(sigma: complex, zeta: float) -> complex:
    return cmath.sqrt(sigma / zeta)


def poloidal_seeds(*, m: int, zeta: float) -> Iterator[complex]:
    """Starting points beta for the poloidal modes (M1), best first (lazy).

    Notes
    -----
    * small zeta (|beta_L| >= 4m): sigma = i lam0 - c_m sqrt(i lam0 zeta) (:func:`inviscid_limit`)
      and sigma = (qh^2/(4 zeta))^(1/3) e^(2 pi i/3) (:func:`psi_relaxation_limit`), with
      sigma = gamma/sqrt(kappa) = zeta beta^2;
    * large zeta (|beta_L| <= 0.3 m): sigma_i = -qh/(zeta mu_i), mu_i = eig R0 (:func:`stokes_limit`);
    * in between, and as fallbacks: the roots of the rational model (:func:`_rational_model`, a
      degree-9 polynomial), folded into the first quadrant (:func:`_fold`).

    The rational-model roots are refined on the uniform model (:func:`_uniform_model`), which
    agrees with (M1) in both limits and through the crossover at |beta| ~ m for large m.
    """
    lamb = _beta_of(inviscid_limit(m=m, kappa=1.0, nu=zeta), zeta)
    small = [lamb, _beta_of(psi_relaxation_limit(m=m, kappa=1.0, nu=zeta), zeta)]
    large = [_beta_of(complex(g), zeta) for g in stokes_limit(m=m, kappa=1.0, nu=zeta)]
    return _seed_stream(m, zeta, "poloidal", small, large, abs(lamb) / m)


def toroidal_seeds(*, m: int, zeta: float) -> Iterator[complex]:
    """Starting points beta for the toroidal mode (M2), best first (lazy): as
    :func:`poloidal_seeds`, with the limits of :func:`toroidal_limits`
    (sigma = (qh/2)^(2/3) zeta^(-1/3) e^(2 pi i/3) and sigma = -qh/((2m+1) zeta)) and the
    degree-7 polynomial of the rational model."""
    small, large = (_beta_of(complex(g), zeta) for g in toroidal_limits(m=m, kappa=1.0, nu=zeta))
    return _seed_stream(m, zeta, "toroidal", [small], [large], abs(small) / m)


# ----------------------------------------------------------------------------- the system


def modal_system(*, m: int, kappa: float, nu: float, component: str = "poloidal") -> ModalSystem:
    """Natural modes of degree m of the spherical membrane as a :class:`ModalSystem` in beta.

    Parameters
    ----------
    m : degree, 2 <= m <= 200 (seeds verified for m <= 60).
    kappa, nu : stiffness and viscosity (> 0); zeta = nu/sqrt(kappa) must lie in
        [ZETA_MIN, ZETA_MAX].
    component : 'poloidal' ((M1), two modes) or 'toroidal' ((M2), one mode).

    Notes
    -----
    gamma = nu beta^2 (7.9); sheet margin Re beta; residuals (M1)/(M2) via :func:`poloidal_residual`
    and friends; the mode count n_modes comes from the argument-principle checks in the tests.

    Raises
    ------
    ParameterError : m, kappa, nu, component or zeta out of range (nu = 0 has the exact inviscid
        modes gamma = +-i lambda0 (7.4) and no toroidal mode: nothing to solve).
    """
    m = require_int_in_range("m", m, 2, M_MODES_MAX)
    kappa = require_positive("kappa", kappa)
    if nu == 0:
        raise ParameterError("nu = 0 is invalid: must be > 0 for the viscous natural modes (the "
                             "inviscid ones are gamma = +-i lambda0, lambda0^2 = kappa m(m+1)(m-1)"
                             "(m+2)/(2m+1), thesis (7.4))")
    nu = require_positive("nu", nu)
    component = require_choice("component", component, ("poloidal", "toroidal"))
    zeta = nu / math.sqrt(kappa)
    if not ZETA_MIN <= zeta <= ZETA_MAX:
        raise ParameterError(f"zeta = nu/sqrt(kappa) = {zeta!r} is invalid: must be in "
                             f"[{ZETA_MIN:g}, {ZETA_MAX:g}]")
    if component == "toroidal":
        residual, residual_mp, seeds, n_modes = toroidal_residual, toroidal_residual_mp, toroidal_seeds, 1
    else:
        residual, residual_mp, seeds, n_modes = poloidal_residual, poloidal_residual_mp, poloidal_seeds, 2
    return modal_system_in_beta("sphere", nu=nu, n_modes=n_modes, residual=residual,
                                residual_mp=residual_mp, seeds=seeds, m=m, zeta=zeta)
