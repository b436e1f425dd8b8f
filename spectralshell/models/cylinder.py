"""Periodic cylindrical membrane, one Fourier mode (m, k): Hill-system physics (thesis 8.1).

Derived in ``derivations/cylinder.py`` (fields and residuals checked there). The membrane law is
the sphere's (6.1) on the reference cylinder, F = K(t) (X_thetatheta + X_zz), about the
pressurised cylinder ([[p0]] = -K). Unknowns X = (X^r, X^theta, X^z) with
X^r cos(phi) r-hat + X^theta sin(phi) theta-hat + X^z sin(phi) z-hat, phi = m theta + k z
(k = k R). With q = m^2 + k^2,

    E = [[q, m, -k], [m, q, 0], [-k, 0, q]],     D(s) = H(s) + kappa E,     G = kappa E

in D(s_n) X_n = i tau G (X_{n-1} - X_{n+1}); H(s) is the fluid's load per unit displacement
(symmetric: reciprocity). It comes from the interface matrices of each side: V (velocity) and
T (traction sigma . r-hat) at r = 1 per amplitude of the pressure a g(r) and the vortical
potentials A F(r), C F(r) (u = -grad p/s + curl(psi z) + curl curl(chi z)), which depend only on
Lambda = g'(1) (g = I_m(k r)/I_m(k) inside, K_m(k r)/K_m(k) outside) and L = F'(1) (the same
with beta = sqrt(s/nu + k^2)); H(s) = s S^-1 (T_in V_in^-1 - T_out V_out^-1) S with
S = diag(1, -i, -i) (the complex amplitudes of the real basis). D(0) = kappa E (limit).

Decoupling: m = 0 splits torsion X^theta from the sausage pair (X^r, X^z); k = 0 splits X^z from
(X^r, X^theta), which is the 2D fibre (thesis 4) per unit length. ``component`` selects the set.

Inviscid limit nu -> 0: the tangential rows slave X^theta = -m X^r/q, X^z = k X^r/q and the radial
row is the Mathieu equation with lambda0^2 = kappa (q - 1)/M(m, k),
M = I_m(k)/(k I_m'(k)) - K_m(k)/(k K_m'(k)) (added mass; 2/m at k = 0, the fibre's Rayleigh
frequency kappa m (m^2 - 1)/2). ``nu = 0`` therefore reuses the Mathieu model.

Natural modes (tau = 0): det D(gamma) = 0 in beta = sqrt(gamma/nu + k^2) (:func:`modal_system`;
the cut of D is gamma <= -nu k^2, ``HillSystem.branch_point``), from which the Floquet exponents
are continued. Up to zeta = nu/sqrt(kappa) = 0.05 (and at k = 0) one mode per component from
seeds; above it, where :func:`counted` (0.01 <= k <= 40, m <= min(60, 600 k)), as
many as an argument-principle count finds in a box of the
beta plane (a conjugate pair can split into two real decays, so there may be more modes than
components), solved in x = beta - k, where those decays crowd as zeta grows, up to zeta = 1e3
(:func:`zeta_max`).
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Iterator

import numpy as np

from .._validate import invalid
from ..errors import ParameterError
from ..params.cylinder import CYLINDER_UNITS, CylinderParams, cylinder_physical
from ..params.registry import Model, PhysicalInput, register
from ..special.cylindrical import (logderiv_i, logderiv_k, logderiv_k_continued, ratio_i,
                                   ratio_k)
from . import fibre, mathieu
from .base import (HillSystem, ModalSystem, boundary_layer, continued_roots, damped_newton)

_S = np.array([1.0, -1j, -1j])  # complex amplitude of (cos, sin, sin) per real coefficient


def elastic_matrix(m: int, k: float) -> np.ndarray:
    """E(m, k): the membrane load on (X^r, X^theta, X^z) is -K(t) E X (prestress included).

    Notes
    -----
    Eigenvalues q and q +- sqrt(q), q = m^2 + k^2. A rigid translation (m = 1, k = 0,
    X = (1, -1, 0)), a rigid rotation and a rigid axial shift (m = k = 0) are in its kernel.
    """
    q = m * m + k * k
    return np.array([[q, m, -k], [m, q, 0.0], [-k, 0.0, q]], dtype=float)


def components(m: int, k: float, component: str = "coupled") -> list[int]:
    """Indices into (X^r, X^theta, X^z) of the decoupled set ``component`` at (m, k)."""
    if component == "torsion":
        return [1]
    if component == "axial":
        return [2]
    if m == 0:
        return [0, 2]
    if k == 0:
        return [0, 1]
    return [0, 1, 2]


def _interface_entries(m: int, k: float, s, nu, lam, L, Q) -> tuple[list, list]:
    """V, T at r = 1 per amplitude (s a, A, (C + i k s a) nu/s) as 3 x 3 nested lists of entries:
    numpy arrays over s (broadcast by the caller) or mpmath numbers.

    Notes
    -----
    In the amplitudes (a, A, C) of the pressure and the two vortical potentials, the pressure's
    column carries 1/s and, as beta -> k (s -> 0), the gradient part of C's column tends to
    -i k s times it, so that V is nearly singular and H = s T V^-1 loses digits like
    eps nu k^2/|s|. The columns used here are s times the pressure's and the combination
    (C + i k s a) nu/s, in which that cancellation is done in closed form: its entries hold
    Q = (L - Lambda)/(beta^2 - k^2), a divided difference of the logarithmic derivative
    (:func:`_divided_difference`). A change of columns leaves T V^-1 unchanged.
    """
    b2 = s / nu + k * k
    V = [[-lam, 1j * m, 1j * k * Q],
         [-1j * m, -L, 0],
         [-1j * k, 0, -1]]
    du = [[-(k * k + m * m - lam), 1j * m * (L - 1), 1j * k * (1 - Q)],
          [-1j * m * (lam - 1), -(b2 + m * m - L), -m * k * Q],
          [-1j * k * lam, 0, -L - k * k * Q]]
    T = [[2 * nu * d for d in du[0]],
         [nu * (du[1][j] - V[1][j] + 1j * m * V[0][j]) for j in range(3)],
         [nu * (du[2][j] + 1j * k * V[0][j]) for j in range(3)]]
    T[0][0] -= s
    T[0][2] -= 1j * k * nu
    return V, T


def _interface(m: int, k: float, s: np.ndarray, nu: float, lam: np.ndarray | float,
               L: np.ndarray, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """V, T (shape (len(s), 3, 3)): velocity and traction at r = 1 per amplitude
    (:func:`_interface_entries`)."""
    V, T = _interface_entries(m, k, s, nu, lam, L, Q)

    def stacked(rows: list) -> np.ndarray:
        return np.stack([np.stack(np.broadcast_arrays(s, *row)[1:], -1) for row in rows], -2)

    return stacked(V).astype(complex), stacked(T).astype(complex)


def _pressure_logderivs(m: int, k: float) -> tuple[float, float]:
    """(Lambda_in, Lambda_out) = k I_m'(k)/I_m(k), k K_m'(k)/K_m(k); (m, -m) at k = 0, m >= 1."""
    if k == 0.0:
        return float(m), -float(m)
    return float(np.real(logderiv_i(m, k))), float(np.real(logderiv_k(m, k)))


#: |beta - k| below which the divided difference Q comes from a Cauchy integral (in units of k),
#: the circle's radius (in units of k) and its number of nodes (aliasing error ~ 2^-_NODES).
_NEAR = 0.25
_CIRCLE = 0.5
_NODES = 64


def _asymptote(m: int, z, side: int):
    """+-sqrt(m^2 + z^2) (+ inside, - outside): the leading term of the logarithmic derivatives
    z I_m'/I_m and z K_m'/K_m uniformly in m and z (DLMF 10.41.3-4)."""
    return (1 - 2 * side) * np.sqrt(m * m + z * z)


@functools.lru_cache(maxsize=256)
def _circle_values(m: int, k: float, side: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes z_j = k + _CIRCLE k e^(2 pi i j/N) and g(z_j) = y(z_j) -+ sqrt(m^2 + z_j^2), y the
    logarithmic derivative of I_m (side 0) or K_m (side 1)."""
    z = k + _CIRCLE * k * np.exp(2j * np.pi * np.arange(_NODES) / _NODES)
    return z, _remainder(m, side, z)


def _remainder(m: int, side: int, z: np.ndarray) -> np.ndarray:
    """g(z) = y(z) -+ sqrt(m^2 + z^2) = z^2 (rho(z) -+ 1/(sqrt(m^2 + z^2) + m)), y the logarithmic
    derivative of I_m (side 0) or K_m (side 1) and rho = (y -+ m)/z^2 (:func:`_excess_over`).

    Notes
    -----
    Both terms are formed without cancellation, so g keeps an absolute error ~eps |z|^2/(m + |z|)
    where y - asymptote directly loses eps sqrt(m^2 + |z|^2): for |z| << m (small k at large m)
    that is the difference between eps k^2/m and eps m, which the divided difference
    g[k, beta] over |beta - k| ~ k would amplify by 1/k."""
    z = np.asarray(z, dtype=complex)
    sign = 1 - 2 * side
    return z * z * (_excess_over(m, side, z) - sign / (np.sqrt(m * m + z * z) + m))


def _divided_difference(m: int, k: float, side: int, x: np.ndarray,
                        beta: np.ndarray) -> np.ndarray:
    """Q = (L - Lambda)/(beta^2 - k^2) at beta = k + x (Re beta >= 0; both given, each to its own
    digits), L = y(beta), Lambda = y(k), y the
    logarithmic derivative of I_m (side 0) or K_m (side 1), without the cancellation L - Lambda.

    Notes
    -----
    y = +-sqrt(m^2 + z^2) + g(z) with g = O(1) (DLMF 10.41.3-4), so

        Q = +-1/(sqrt(m^2 + beta^2) + sqrt(m^2 + k^2)) + g[k, beta]/(beta + k),

    the first term in closed form and the divided difference g[k, beta] by the Cauchy integral
    (1/N) sum_j g(z_j)/(z_j - beta) over a circle of radius k/2 about k for |x| < k/4 (trapezoidal
    rule: error ~ 2^-N, g analytic within |z - k| < k), else directly as (g(beta) - g(k))/x, g from
    :func:`_remainder` (no cancellation of size m, which 1/k would amplify at small k).
    Subtracting the asymptote matters for m >> k, where y'(k) ~ k/m is small against y ~ m: an
    unsubtracted difference loses a factor m^2/k^2 (measured 1e-11 at m = 25, k = 1)."""
    x, beta = np.asarray(x, dtype=complex), np.asarray(beta, dtype=complex)
    closed = (1 - 2 * side) / (np.sqrt(m * m + beta * beta) + np.sqrt(m * m + k * k))
    g_k = complex(_remainder(m, side, np.array([k]))[0]).real
    out = np.empty(x.shape, dtype=complex)
    near = np.abs(x) < _NEAR * k
    far = ~near
    out[far] = (_remainder(m, side, beta[far]) - g_k) / x[far]
    if near.any():
        z, g = _circle_values(m, float(k), side)
        out[near] = np.mean(g[None, :] / (z[None, :] - beta[near][:, None]), axis=1)
    return closed + out / (beta + k)


#: |beta| below which (in units of max(k, m), m >= 1, physical sheet) the pressure's column of
#: V, T is recombined with the vortical ones (:func:`_origin_column`).
_ORIGIN = 0.5


def _excess_over(m: int, side: int, z: np.ndarray) -> np.ndarray:
    """rho = (y(z) - +-m)/z^2 in closed form, y the logarithmic derivative of I_m (side 0, +m) or
    K_m (side 1, -m, m >= 1): I_{m+1}(z)/(z I_m(z)) and -K_{m-1}(z)/(z K_m(z)) (DLMF 10.29.2)."""
    z = np.asarray(z, dtype=complex)
    if side == 0:
        return np.asarray(ratio_i(m, z), dtype=complex) / z
    if m == 0:  # K_{-1} = K_1
        return -np.asarray(ratio_k(0, z), dtype=complex) / z
    return -1.0 / (z * np.asarray(ratio_k(m - 1, z), dtype=complex))


def _origin_column(m: int, k: float, side: int, beta: np.ndarray, L: np.ndarray, Q: np.ndarray,
                   nu: float) -> tuple[np.ndarray, np.ndarray]:
    """The pressure's column of V and T (shape (len(beta), 3)) replaced by
    (c_0 - (i m/L) c_1 - i k c_2)/beta^2 (c_j the columns of :func:`_interface_entries`), for
    m >= 1 and |beta| < max(k, m)/2 on the physical sheet.

    Notes
    -----
    As beta -> 0 (the branch point gamma = -nu k^2) the columns of V become dependent:
    det V = (k^2 (L^2 - m^2) - beta^2 (Lambda L - m^2))/(beta^2 - k^2) = O(beta^2), and
    T V^-1 lost digits like eps (k/beta)^2 (measured 4e-10 at beta = 0.01 k, 5e-4 at 1e-5 k,
    m = 25, k = 0.5, against 30-digit mpmath). For |beta| ~ k << m they are dependent too
    (L, Lambda = +-m + O(k^2/m)): D lost digits like eps m^2/k^2 near beta ~ k (6.7e-10 of max |D|
    at m = 10, k = 0.01, nu = 100). With w = (1, -i m/L, -i k), V w = (beta^2 v, 0, 0)
    and T w = beta^2 (-nu (2v + 1), i m nu (2v + 1/L), i k nu (Q + v)), where

        v = (s m (Q - 2 rho) + beta^2 rho (Q - rho))/L,

    s = +1 inside, -1 outside, rho = (L - s m)/beta^2 in closed form and Q the divided difference
    (:func:`_divided_difference`; Q - rho = k^2 (rho - rho_k)/(beta^2 - k^2) is O(k^2/m^2) and
    enters multiplied by beta^2 rho, so its cancellation is harmless; at k = 0, Q = rho), so that
    nothing cancels. A change of columns leaves T V^-1 unchanged.
    """
    sign = 1 - 2 * side
    b2 = beta * beta
    rho = _excess_over(m, side, beta)
    v = (sign * m * (Q - 2 * rho) + b2 * rho * (Q - rho)) / L
    zero = np.zeros_like(v)
    V = np.stack([v, zero, zero], -1)
    T = np.stack([-nu * (2 * v + 1), 1j * m * nu * (2 * v + 1 / L), 1j * k * nu * (Q + v)], -1)
    return V, T


def fluid_load(s: np.ndarray, *, m: int, k: float, nu: float) -> np.ndarray:
    """H(s) (shape (len(s), 3, 3), s != 0): the fluid's load on (X^r, X^theta, X^z) in the real basis.

    Notes
    -----
    The pressure-vortical cancellation as s -> 0 (beta -> k) is done in closed form
    (:func:`_interface_entries`), with x = beta - k = (s/nu)/(beta + k) taken from s, not from
    beta, so H keeps its relative accuracy as s -> 0 (checked against 40-digit mpmath).

    Raises
    ------
    ParameterError : an s whose beta = sqrt(s/nu + k^2) leaves the Bessel kernels' domain.
    """
    s = np.asarray(s, dtype=complex).ravel()
    beta = np.sqrt(s / nu + k * k)
    return _fluid_load_at(s, beta, (s / nu) / (beta + k), m=m, k=k, nu=nu)


def _fluid_load_at(s: np.ndarray, beta: np.ndarray, x: np.ndarray, *, m: int, k: float,
                   nu: float) -> np.ndarray:
    """H(s) at beta = k + x with beta^2 = s/nu + k^2 on either sheet: the principal one
    (Re beta >= 0, the exterior field decays) or, for Re beta < 0, its continuation across the
    imaginary beta axis (:func:`~spectralshell.special.cylindrical.logderiv_k_continued`;
    I_m(beta r) is even up to sign, so only K_m carries the sheet). x = beta - k is passed
    separately so that a caller who knows it better than beta - k keeps its digits."""
    lam_in, lam_out = _pressure_logderivs(m, k)
    second = beta.real < 0
    with boundary_layer(nu):
        L_in = np.atleast_1d(logderiv_i(m, np.where(second, -beta, beta))).astype(complex)
        L_out = np.empty(beta.shape, dtype=complex)
        L_out[~second] = logderiv_k(m, beta[~second])
        L_out[second] = [logderiv_k_continued(m, b) for b in beta[second]]
    # Q = (L - Lambda)/(beta^2 - k^2) without its cancellation on the physical sheet: a divided
    # difference for k > 0, rho = (L -+ m)/beta^2 in closed form at k = 0 (Lambda = +-m)
    Q_in, Q_out = (L_in - lam_in) / (s / nu), (L_out - lam_out) / (s / nu)
    first = ~second
    if first.any():
        for side, Q in ((0, Q_in), (1, Q_out)):
            Q[first] = (_divided_difference(m, k, side, x[first], beta[first]) if k > 0
                        else _excess_over(m, side, beta[first]))
    Vi, Ti = _interface(m, k, s, nu, lam_in, L_in, Q_in)
    Vo, To = _interface(m, k, s, nu, lam_out, L_out, Q_out)
    origin = ((np.abs(beta) < _ORIGIN * max(k, m)) & ~second if m >= 1
              else np.zeros(beta.shape, bool))
    if origin.any():  # the branch point beta = 0: the columns recombined (_origin_column)
        for side, V, T, L, Q in ((0, Vi, Ti, L_in, Q_in), (1, Vo, To, L_out, Q_out)):
            V[origin, :, 0], T[origin, :, 0] = _origin_column(m, k, side, beta[origin],
                                                              L[origin], Q[origin], nu)
    # Z = T V^-1 on each side, as (V^T)^-1 T^T transposed
    Z = (np.linalg.solve(np.swapaxes(Vi, 1, 2), np.swapaxes(Ti, 1, 2))
         - np.linalg.solve(np.swapaxes(Vo, 1, 2), np.swapaxes(To, 1, 2)))
    Z = np.swapaxes(Z, 1, 2)
    return s[:, None, None] * Z * _S[None, None, :] / _S[None, :, None]


def unforced(s: np.ndarray, *, m: int, k: float, kappa: float, nu: float,
             component: str = "coupled") -> np.ndarray:
    """D(s) = H(s) + kappa E on the set ``component``, shape (len(s), b, b); D(0) = kappa E."""
    s = np.asarray(s, dtype=complex).ravel()
    beta = np.sqrt(s / nu + k * k)
    # x = beta - k without the cancellation, = s/(nu (beta + k)); 0 at s = 0 with k = 0
    x = np.divide(s / nu, beta + k, out=np.zeros_like(beta), where=beta + k != 0)
    return _unforced_at(s, beta, x, m=m, k=k, kappa=kappa, nu=nu, component=component)


def _unforced_at(s: np.ndarray, beta: np.ndarray, x: np.ndarray, *, m: int, k: float,
                 kappa: float, nu: float, component: str) -> np.ndarray:
    """:func:`unforced` at beta = k + x on either sheet (:func:`_fluid_load_at`)."""
    idx = components(m, k, component)
    E = kappa * elastic_matrix(m, k)[np.ix_(idx, idx)]
    out = np.broadcast_to(E, (s.size, len(idx), len(idx))).astype(complex, order="C")
    live = s != 0
    if live.any():
        out[live] += _fluid_load_at(s[live], beta[live], x[live], m=m, k=k,
                                    nu=nu)[:, idx][:, :, idx]
    return out


def added_mass(m: int, k: float) -> float:
    """M(m, k) = I_m(k)/(k I_m'(k)) - K_m(k)/(k K_m'(k)): inviscid fluid inertia per radial
    displacement (2/m at k = 0)."""
    lam_in, lam_out = _pressure_logderivs(m, k)
    return 1.0 / lam_in - 1.0 / lam_out


def lambda0_squared(m: int, k: float, kappa: float) -> float:
    """Inviscid natural frequency squared, kappa (m^2 + k^2 - 1)/M(m, k) (forcing frequency = 1)."""
    return kappa * ((m * m - 1.0) + k * k) / added_mass(m, k)


def hill_system(*, m: int, k: float, kappa: float, nu: float,
                component: str = "coupled") -> HillSystem:
    """Hill-system physics of the mode (m, k) of the cylinder (see the module docstring).

    Raises
    ------
    ParameterError : invalid m, k, kappa, nu or component (:class:`CylinderParams`).
    """
    p = CylinderParams(m=m, k=k, kappa=kappa, nu=nu, component=component)
    idx = components(p.m, p.k, p.component)
    if p.nu == 0.0:
        lam2 = lambda0_squared(p.m, p.k, p.kappa)
        return dataclasses.replace(mathieu.hill_system(kappa=lam2, nu=0.0), name="cylinder")
    G = p.kappa * elastic_matrix(p.m, p.k)[np.ix_(idx, idx)]
    resonant = np.sqrt(lambda0_squared(p.m, p.k, p.kappa)) if p.component == "coupled" else 0.0
    m_, k_, kappa_, nu_, c_ = p.m, p.k, p.kappa, p.nu, p.component
    return HillSystem(name="cylinder", block_size=len(idx), forcing=G,
                      unforced=lambda s: unforced(s, m=m_, k=k_, kappa=kappa_, nu=nu_, component=c_),
                      n_resonant=float(resonant), branch_point=-p.nu * p.k * p.k)


def _hill_system(p: CylinderParams) -> HillSystem:
    return hill_system(m=p.m, k=p.k, kappa=p.kappa, nu=p.nu, component=p.component)


# ----------------------------------------------------------------------------- natural modes
#
# The dispersion relation det D(gamma) = 0 in beta = sqrt(gamma/nu + k^2), gamma = nu (beta^2 - k^2):
# the Bessel functions of beta r carry the branch point beta = 0 (gamma = -nu k^2) and the cut
# gamma <= -nu k^2, which opens into the imaginary beta axis; Re beta > 0 is the physical sheet
# (the exterior field decays) and maps onto the gamma-plane cut along (-inf, -nu k^2]. The
# pressure's I_m(k r), K_m(k r) do not depend on gamma. An overdamped mode with
# -nu k^2 < gamma < 0 has a real beta in (0, k): on the physical sheet, off the cut.

#: Range of zeta = nu/sqrt(kappa) over which the modes are offered (:func:`zeta_max` gives the
#: upper end for each m and k; ZETA_MAX is its largest value).
ZETA_MIN = 1e-8
ZETA_MAX = 1e3
#: Where the seeds' continuation in zeta starts (k = 0): below ZETA_START_CHECKED the asymptotic
#: seeds alone find every mode; above it, for k > 0, the count-driven finder takes over.
ZETA_START = 0.04
ZETA_START_CHECKED = 0.05
#: k = 0 (the fibre pair, axial): (largest m of a tier, its upper end of zeta), checked on grids.
_ZETA_TOPS = ((25, 0.3), (60, 0.15))
#: Where the count-driven finder offers zeta above ZETA_START_CHECKED up to ZETA_COUNTED:
#: K_COUNTED[0] <= k <= K_COUNTED[1], m <= M_COUNTED and m <= M_PER_K k (checked on grids of
#: (m, k, zeta), tests/test_cylinder_modes.py, error estimates against 30-digit mpmath roots).
#: Since D keeps its entries to ~1e-14 of max |D| on the physical sheet for every m and k
#: (:data:`_ENTRY_EPS`) the error estimates stay below 1e-13 |gamma| for the counted roots
#: (m = 60 at k = 0.1, 1, 40; m = 30 at k = 0.05; m = 6 at k = 0.01). Beyond m = 600 k the
#: modes that leave the counted box for the cut are met on the second sheet, where D keeps less
#: (up to eps m^2/k^2): 5.7e-10 |gamma| at m = 25, k = 0.01, zeta = 100, and at m = 60, k = 0.01,
#: zeta = 1e3 the finder did not find every counted root; below k = 0.01 that sheet's rounding
#: grows like 1/k^2 too. There, and for m > 60 (not checked on grids), the seeds' range applies.
K_COUNTED = (0.01, 40.0)
M_COUNTED = 60
M_PER_K = 600.0
ZETA_COUNTED = 1e3
#: Relative step of the 4-point derivative of the determinant in beta (error ~ step^4).
_STEP = 1e-3


def zeta_max(m: int, k: float, component: str = "coupled") -> float:
    """Largest zeta = nu/sqrt(kappa) at which the modes of (m, k, component) are offered.

    * 0.01 <= k <= 40 with m <= min(60, 600 k) (:func:`counted`; the count-driven finder
      above zeta = 0.05, :func:`modal_system`): 1e3. The number of modes is the argument-principle count in a box
      of the beta plane, so it may exceed the number b of components (four at m = 1, k = 2,
      zeta = 1: a conjugate pair of overdamped modes splits into two real decays in
      -nu k^2 < gamma < 0). Checked on grids of m, k and zeta in {0.06, ..., 1e3} against counts
      on a box twice as large and against 30-digit roots (tests/test_cylinder_modes.py).
    * otherwise (the seeds, and at k = 0 their continuation in zeta, find b modes):
      max(0.05, min(z_m, 2/k^2)) (z_m alone at k = 0), z_m = 0.3 for m <= 25, 0.15 for m <= 60
      and 0.05 above (the continuation loses a mode near the cut at zeta 0.2-0.3 for m = 35..60
      and at some zeta in 0.1-0.3 for m = 100, 200; beyond 2/k^2 the modes can outnumber the
      components); the fibre pair also stops at :func:`spectralshell.models.fibre.zeta_max`
      (not reached below 0.3). Below k = 0.01, and beyond m = 600 k or m = 60, the modes that
      leave the box for the cut are met on the continuation across it, whose rounding grows like
      m^2/k^2 (:data:`K_COUNTED`).
    """
    if counted(m, k):
        return ZETA_COUNTED
    tier = next((end for largest, end in _ZETA_TOPS if m <= largest), ZETA_START_CHECKED)
    if k > 0:
        return max(ZETA_START_CHECKED, min(tier, 2.0 / k**2))
    if component == "coupled":
        tier = min(tier, fibre.zeta_max(m))
    return tier


def counted(m: int, k: float) -> bool:
    """Whether the count-driven finder serves (m, k) above zeta = ZETA_START_CHECKED."""
    return m <= M_COUNTED and m <= M_PER_K * k and K_COUNTED[0] <= k <= K_COUNTED[1]


def natural_matrix(beta: np.ndarray, *, m: int, k: float, kappa: float, nu: float,
                   component: str = "coupled") -> np.ndarray:
    """D(gamma)/kappa at gamma = nu (beta^2 - k^2) for each beta, shape (len(beta), b, b): on the
    physical sheet for Re beta > 0, continued across the imaginary axis (the cut) for
    Re beta < 0; its determinant vanishes at the natural modes e^{gamma t}."""
    beta = np.asarray(beta, dtype=complex).ravel()
    return natural_matrix_shifted(beta - k, m=m, k=k, kappa=kappa, nu=nu, component=component)


def natural_matrix_shifted(x: np.ndarray, *, m: int, k: float, kappa: float, nu: float,
                           component: str = "coupled") -> np.ndarray:
    """:func:`natural_matrix` at beta = k + x, with gamma = nu x (x + 2k) and the divided
    differences of :func:`_interface_entries` taken from x itself: the overdamped modes of large
    zeta crowd at beta -> k (gamma ~ 2 nu k x), where beta alone would lose the digits of x."""
    x = np.asarray(x, dtype=complex).ravel()
    return _unforced_at(nu * x * (x + 2 * k), k + x, x, m=m, k=k, kappa=kappa, nu=nu,
                        component=component) / kappa


def _four_point(f: list, h) -> object:
    """f'(x) from f at x + h, x - h, x + ih, x - ih (analytic f; error ~ h^4 f^(5))."""
    return (f[0] - f[1] - 1j * (f[2] - f[3])) / (4 * h)


def modal_residual(beta: complex, *, m: int, k: float, kappa: float, nu: float,
                   component: str = "coupled") -> tuple[complex, complex]:
    """(det D/kappa^b, its beta-derivative) at gamma = nu (beta^2 - k^2), in double precision.

    The derivative is the 4-point difference with step 1e-3 |beta| (relative error ~1e-12, enough
    for Newton's method, whose root is that of the determinant itself)."""
    beta = complex(beta)
    h = _STEP * abs(beta)
    points = beta + h * np.array([0, 1, -1, 1j, -1j])
    det = np.linalg.det(natural_matrix(points, m=m, k=k, kappa=kappa, nu=nu, component=component))
    return complex(det[0]), complex(_four_point(list(det[1:]), h))


def _stencil_scale(x: complex, k: float) -> float:
    """min(|x|, |beta|, max(|Re beta|, 1e-5 min(k, |beta|))) at beta = k + x: the difference
    stencil of the derivative stays well inside the distance to beta = k (where the roots
    crowd), to the branch point beta = 0 and, down to 1e-8 k, to the cut Re beta = 0 (on which
    roots can sit, 1e-6 k from the counting box's edge); nearer the cut it reaches across it
    onto the continuation (analytic there), so that a root on the cut still has a derivative
    accurate to ~1e-8."""
    beta = k + x
    return np.minimum(np.minimum(abs(x), abs(beta)),
                      np.maximum(abs(beta.real), 1e-5 * np.minimum(k, abs(beta))))


def modal_residual_shifted(x: complex, *, m: int, k: float, kappa: float, nu: float,
                           component: str = "coupled") -> tuple[complex, complex]:
    """:func:`modal_residual` in x = beta - k (:func:`natural_matrix_shifted`): the 4-point
    derivative with step 1e-3 :func:`_stencil_scale`, so that the roots crowding at x -> 0
    stay resolved and the stencil does not reach across the cut."""
    f, fp = modal_residuals_shifted(np.array([x], dtype=complex), m=m, k=k, kappa=kappa, nu=nu,
                                    component=component)
    return complex(f[0]), complex(fp[0])


def modal_residuals_shifted(x: np.ndarray, *, m: int, k: float, kappa: float, nu: float,
                            component: str = "coupled") -> tuple[np.ndarray, np.ndarray]:
    """:func:`modal_residual_shifted` at each of the points x (one batch of matrices)."""
    x = np.asarray(x, dtype=complex).ravel()
    h = _STEP * _stencil_scale(x, k)
    points = x[:, None] + h[:, None] * np.array([0, 1, -1, 1j, -1j])[None, :]
    det = np.linalg.det(natural_matrix_shifted(points.ravel(), m=m, k=k, kappa=kappa, nu=nu,
                                               component=component)).reshape(points.shape)
    return det[:, 0], _four_point([det[:, j] for j in range(1, 5)], h)


def modal_residual_shifted_mp(x, *, m: int, k: float, kappa: float, nu: float,
                              component: str = "coupled"):
    """:func:`modal_residual_shifted` in mpmath (:func:`natural_determinant_shifted_mp`), the
    derivative's step 10^(-dps/3) :func:`_stencil_scale`."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    x = mpmath.mpc(x)
    h = mpmath.mpf(10) ** (-(mpmath.mp.dps // 3)) * _stencil_scale(complex(x), k)
    det = [natural_determinant_shifted_mp(x + d, m=m, k=k, kappa=kappa, nu=nu,
                                          component=component)
           for d in (0, h, -h, 1j * h, -1j * h)]
    return det[0], _four_point(det[1:], h)


#: Relative accuracy of the entries of D (against max |D|) on the physical sheet, eps_D: with the
#: remainders g and the pressure's column free of cancellation (:func:`_remainder`,
#: :func:`_origin_column` for |beta| < max(k, m)/2) measured at most 77 eps over m = 1..100,
#: k = 1e-3..40, nu = 0.06..1e3 against 30-digit mpmath (was up to 3e6 eps at m = 10, k = 0.01,
#: nu = 100: V's columns are dependent to O(k^2/m^2) for |beta| ~ k << m). The continuation
#: across the cut (Re beta < 0) keeps less: measured up to eps_D m^2/k^2 (2.3e-6 at m = 60,
#: k = 1e-3), so :func:`modal_noise_shifted` takes eps_D (1 + 4 m^2/k^2) there.
_ENTRY_EPS = 128 * 2.220446049250313e-16


def _cofactors(D: np.ndarray) -> np.ndarray:
    """The cofactor matrix of a b x b matrix (b <= 3), d det D/d D_ij, from its minors (defined
    at a singular D too)."""
    b = D.shape[0]
    if b == 1:
        return np.ones((1, 1), dtype=complex)
    C = np.empty_like(D)
    for i in range(b):
        for j in range(b):
            minor = np.delete(np.delete(D, i, 0), j, 1)
            C[i, j] = (-1) ** (i + j) * np.linalg.det(minor)
    return C


def modal_noise_shifted(x: complex, *, m: int, k: float, kappa: float, nu: float,
                        component: str = "coupled") -> float:
    """An absolute bound on the error in x of a root at x caused by the rounding of D:
    eps_D max|D| sum_ij |C_ij| / |d det/dx| (C the cofactors, eps_D the entries' relative
    accuracy, _ENTRY_EPS, or _ENTRY_EPS (1 + 4 m^2/k^2) across the cut); at least 64 eps |x|."""
    fixed = {"m": m, "k": k, "kappa": kappa, "nu": nu, "component": component}
    D = natural_matrix_shifted(np.array([x]), **fixed)[0]
    _, fp = modal_residual_shifted(x, **fixed)
    eps_d = _ENTRY_EPS * (1 + 4 * m * m / (k * k) if (k + complex(x)).real < 0 else 1)
    spread = eps_d * np.abs(D).max() * np.abs(_cofactors(D)).sum()
    return float(max(spread / abs(fp), 64 * 2.220446049250313e-16 * abs(x)))


def _logderivs_mp(m: int, z) -> tuple:
    """(z I_m'(z)/I_m(z), z K_m'(z)/K_m(z)) in mpmath (DLMF 10.29.2); (m, -m) at z = 0."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    if z == 0:
        return mpmath.mpf(m), -mpmath.mpf(m)
    return (m + z * mpmath.besseli(m + 1, z) / mpmath.besseli(m, z),
            m - z * mpmath.besselk(m + 1, z) / mpmath.besselk(m, z))


def natural_determinant_mp(beta, *, m: int, k: float, kappa: float, nu: float,
                           component: str = "coupled"):
    """det D(gamma)/kappa^b at gamma = nu (beta^2 - k^2) in mpmath at the current precision
    (beta on the physical sheet, gamma != 0): :func:`natural_matrix` with mpmath's Bessel
    functions."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    return natural_determinant_shifted_mp(mpmath.mpc(beta) - k, m=m, k=k, kappa=kappa, nu=nu,
                                          component=component)


def natural_matrix_shifted_mp(x, *, m: int, k: float, kappa: float, nu: float,
                              component: str = "coupled"):
    """:func:`natural_matrix_shifted` (beta = k + x, x != 0) in mpmath, accurate to about the
    current precision: the Bessel functions and the divided difference
    Q = (L - Lambda)/(x (x + 2k)) are evaluated with the digits that the cancellation L - Lambda
    costs added (log10((1 + k)/|x|)) and, as beta -> 0, those that the near-dependence of V's
    columns costs (2 log10(k/|beta|), :func:`_origin_column`); the matrix is rounded back to
    the current precision."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    x = mpmath.mpc(x)
    extra = max(0, int(mpmath.ceil(mpmath.log10((1 + k) / abs(x))))) + 5
    if abs(k + x) < k:  # the columns' dependence at the branch point beta = 0 (_origin_column)
        extra += int(mpmath.ceil(2 * mpmath.log10(k / abs(k + x))))
    idx = components(m, k, component)
    D = mpmath.matrix(len(idx), len(idx))
    with mpmath.extradps(extra):
        k_, nu_ = mpmath.mpf(k), mpmath.mpf(nu)
        b2k = x * (x + 2 * k_)
        s = nu_ * b2k
        lam = _logderivs_mp(m, k_)
        L = _logderivs_mp(m, k_ + x)
        Z = []
        for side in range(2):
            Q = (L[side] - lam[side]) / b2k
            V, T = (mpmath.matrix(a) for a in _interface_entries(m, k_, s, nu_, lam[side],
                                                                 L[side], Q))
            Z.append(T * mpmath.inverse(V))
        E = elastic_matrix(m, k)
        for a, i in enumerate(idx):
            for c, j in enumerate(idx):
                D[a, c] = +(s * (Z[0][i, j] - Z[1][i, j]) * _S[j] / _S[i] / kappa + E[i, j])
    return D


def natural_determinant_shifted_mp(x, *, m: int, k: float, kappa: float, nu: float,
                                   component: str = "coupled"):
    """det of :func:`natural_matrix_shifted_mp`: :func:`natural_determinant_mp` at beta = k + x."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    D = natural_matrix_shifted_mp(x, m=m, k=k, kappa=kappa, nu=nu, component=component)
    with mpmath.extradps(10):
        det = mpmath.det(D)
    return +det


def modal_residual_mp(beta, *, m: int, k: float, kappa: float, nu: float,
                      component: str = "coupled"):
    """:func:`modal_residual` in mpmath: the derivative by the 4-point difference with step
    10^(-dps/3) |beta| (error ~10^(-4 dps/3))."""
    import mpmath  # here, not at module level: start-up time (bench_startup.py)
    beta = mpmath.mpc(beta)
    h = mpmath.mpf(10) ** (-(mpmath.mp.dps // 3)) * abs(beta)
    det = [natural_determinant_mp(beta + d, m=m, k=k, kappa=kappa, nu=nu, component=component)
           for d in (0, h, -h, 1j * h, -1j * h)]
    return det[0], _four_point(det[1:], h)


def _asymptotic_modes(m: int, k: float, kappa: float, nu: float, component: str) -> list[complex]:
    """Starting values of gamma, one per mode of the set ``component``, from the two limits.

    * small zeta: the inviscid oscillation gamma = i lambda0 (for a set containing X^r) and, per
      tangential component, the Stokes-layer relaxation 2 nu beta gamma = -kappa q (each side's
      shear stress is nu beta gamma per unit tangential displacement at large beta, the tangential
      stiffness is q, X^r is held by the added mass), gamma = (kappa q/(2 sqrt nu))^(2/3) e^(2 pi i/3);
    * large zeta: the steady-Stokes relaxations det(kappa E + gamma H(s0)/s0) = 0, with H(s0)/s0
      the viscous resistance at a small s0 (for k > 0 the modes lie in -nu k^2 < gamma < 0).
    """
    idx = components(m, k, component)
    q = m * m + k * k
    tangential = len(idx) - (0 in idx)
    small = [1j * np.sqrt(lambda0_squared(m, k, kappa))] if 0 in idx else []
    small += [(kappa * q / (2 * np.sqrt(nu))) ** (2 / 3) * np.exp(2j * np.pi / 3)] * tangential
    s0 = 1e-6 * nu * max(k * k, 1.0)
    resistance = fluid_load(np.array([s0]), m=m, k=k, nu=nu)[0][np.ix_(idx, idx)] / s0
    E = kappa * elastic_matrix(m, k)[np.ix_(idx, idx)]
    large = list(np.linalg.eigvals(-np.linalg.solve(resistance, E)))
    return [complex(g) for g in small + large]


def _deflated_seeds(m: int, k: float, kappa: float, nu: float, component: str) -> Iterator[complex]:
    """The roots that deflated Newton's method reaches from each value of
    :func:`_asymptotic_modes` in turn (each root found so far and its images -beta, +-conj(beta)
    divided out of the determinant, so that the nearly equal Stokes-layer values of the two
    tangential components lead to two different modes)."""
    fixed = {"m": m, "k": k, "kappa": kappa, "nu": nu, "component": component}
    known: list[complex] = []

    def deflated(beta: complex) -> tuple[complex, complex]:
        f, fp = modal_residual(beta, **fixed)
        return f, fp - f * sum(1 / (beta - r) for r in known)

    for gamma in _asymptotic_modes(m, k, kappa, nu, component):
        beta = np.sqrt(complex(gamma) / nu + k * k)
        root = damped_newton(deflated, complex(abs(beta.real), abs(beta.imag)), rtol=1e-12,
                             max_iter=60, failures=(ParameterError, ZeroDivisionError))
        if root is None or root.real <= 0:
            continue
        known += [root, root.conjugate(), -root, -root.conjugate()]
        yield root


def _shifted_seeds(*, m: int, k: float, kappa: float, nu: float,
                   component: str) -> Iterator[complex]:
    """Starting points x = beta - k of the count-driven finder: the roots of
    :func:`_deflated_seeds`, then the asymptotic estimates of :func:`_asymptotic_modes`
    themselves (at large zeta some lie on the cut, the imaginary beta axis, where the modes
    that have reached it are)."""
    for beta in _deflated_seeds(m, k, kappa, nu, component):
        yield beta - k
    for gamma in _asymptotic_modes(m, k, kappa, nu, component):
        beta = np.sqrt(complex(gamma) / nu + k * k)
        yield complex(abs(beta.real), abs(beta.imag)) - k


def modal_seeds(*, m: int, k: float, kappa: float, nu: float,
                component: str = "coupled") -> Iterator[complex]:
    """Starting points beta for the natural modes, best first (lazy).

    * at k = 0 (the fibre pair) the fibre's seeds (:func:`spectralshell.models.fibre.modal_seeds`,
      the same beta = sqrt(gamma/nu));
    * the deflated roots from the asymptotic limits (:func:`_deflated_seeds`);
    * for zeta = nu/sqrt(kappa) above ZETA_START, those roots at ZETA_START continued in zeta
      (:func:`~spectralshell.models.base.continued_roots`, on both sheets of the residual): from
      zeta ~ 0.07 the modes of large m reach the cut, where the asymptotic seeds can miss one.
    """
    zeta = nu / np.sqrt(kappa)
    if k == 0 and component == "coupled":
        yield from fibre.modal_seeds(m=m, zeta=zeta)
    yield from _deflated_seeds(m, k, kappa, nu, component)
    if zeta > ZETA_START:
        scale = np.sqrt(kappa)
        starts = list(_deflated_seeds(m, k, kappa, ZETA_START * scale, component))
        yield from continued_roots(
            lambda z: functools.partial(modal_residual, m=m, k=k, kappa=kappa, nu=z * scale,
                                        component=component), starts, ZETA_START, zeta)


#: The counting box's left edge Re beta = _CUT_GAP k (just off the cut, the imaginary beta axis)
#: and its size in units of the largest asymptotic |beta| (:func:`_counting_box`).
_CUT_GAP = 1e-6
_BOX = 3.0


def _counting_box(m: int, k: float, kappa: float, nu: float,
                  component: str) -> tuple[float, float, float]:
    """The rectangle of x = beta - k in which the count-driven finder counts and finds the modes:
    _CUT_GAP k <= Re beta <= B, |Im beta| <= B, B = _BOX max(k, |beta| of each asymptotic
    estimate of :func:`_asymptotic_modes`); a root closer to the cut than _CUT_GAP k is a decay
    on the cut to working accuracy and is not offered."""
    gammas = np.array(_asymptotic_modes(m, k, kappa, nu, component))
    size = _BOX * max(k, float(np.abs(np.sqrt(gammas / nu + k * k)).max()))
    return (-k + _CUT_GAP * k, size - k, size)


def modal_system(*, m: int, k: float, kappa: float, nu: float,
                 component: str = "coupled") -> ModalSystem:
    """Natural modes of the mode (m, k) of the cylinder as a :class:`ModalSystem` in beta.

    Notes
    -----
    Up to zeta = nu/sqrt(kappa) = 0.05, and at k = 0: x = beta = sqrt(gamma/nu + k^2)
    (Re beta > 0 on the physical sheet), gamma = nu (beta^2 - k^2), residual det D(gamma)/kappa^b
    (:func:`modal_residual`, :func:`modal_residual_mp`), seeds :func:`modal_seeds`. n_modes is
    the number b of components of the set (3 coupled, 2 for the sausage pair (m = 0) and the
    fibre pair (k = 0), 1 for torsion or axial): one oscillation (gamma -> i lambda0 as
    nu -> 0) for a set containing X^r, one Stokes-layer relaxation per tangential component.
    Argument-principle counts of det D over the first beta-quadrant find exactly b roots there
    (tests/test_cylinder_modes.py); at k = 0 the pair is the fibre's.

    Above zeta = 0.05 with k > 0: x = beta - k, gamma = nu x (x + 2k)
    (:func:`modal_residual_shifted`: the overdamped modes crowd at beta -> k as zeta grows,
    gamma ~ 2 nu k x, and x keeps their digits), with a counting ``region``
    (:func:`_counting_box`): the root finder counts the roots in it by the argument principle and
    finds that many, so the number of modes is the count's (four at m = 1, k = 2, zeta = 1).
    Roots nearer the cut than the box (Re beta < 1e-6 k) that the finder meets are listed,
    flagged ``uncounted`` (on the cut to within their error, or resolved on the physical sheet
    within 1e-6 k of it); the other modes are exactly the counted roots. The count stops short
    of the cut because det D has poles on it as well as zeros: at large m it is real on the
    imaginary beta axis to within |J_m(b)/Y_m(b)| (K_m(i b) ~ Y_m(b) for b < m), so both sit on
    the axis to any working precision (m = 25, k = 0.5, zeta = 0.5: three decays on the cut at
    beta = 5.001i, 5.056i, 7.211i, poles next to the zeros of J_25 at 30.78, 35.56, 39.76, and a
    winding number of -2 over |Re beta| <= 1e-6 k, 0.005 <= Im beta <= 39.9); a count across
    the cut would need the poles counted apart. Error estimates include
    :func:`modal_noise_shifted`.

    Raises
    ------
    ParameterError : invalid parameters (:class:`CylinderParams`), nu = 0 (the one inviscid mode
        is gamma = i lambda0) or zeta = nu/sqrt(kappa) outside [ZETA_MIN, :func:`zeta_max`].
    """
    p = CylinderParams(m=m, k=k, kappa=kappa, nu=nu, component=component)
    if p.nu == 0:
        raise invalid("nu", p.nu, "> 0 for the viscous natural modes (the inviscid one is "
                      "gamma = i lambda0, lambda0^2 = kappa (m^2 + k^2 - 1)/M(m, k))")
    zeta = p.nu / np.sqrt(p.kappa)
    top = zeta_max(p.m, p.k, p.component)
    if not ZETA_MIN <= zeta <= top:
        why = "" if counted(p.m, p.k) or p.k == 0 else (
            f"; up to {ZETA_COUNTED:g} only for {K_COUNTED[0]:g} <= k <= {K_COUNTED[1]:g} with "
            f"m <= min({M_COUNTED}, {M_PER_K:g} k), outside which the modes met across the cut "
            "are not resolved to 1e-10")
        raise invalid("zeta", zeta, f"in [{ZETA_MIN:g}, {top:.4g}] for m = {p.m}, k = {p.k:g} "
                      f"(zeta = nu/sqrt(kappa): the range over which the mode count is verified"
                      f"{why})")
    fixed = {"m": p.m, "k": p.k, "kappa": p.kappa, "nu": p.nu, "component": p.component}
    nu_, k_, k2 = p.nu, p.k, p.k * p.k
    if counted(p.m, p.k) and zeta > ZETA_START_CHECKED:
        return ModalSystem(
            name="cylinder", n_modes=len(components(p.m, p.k, p.component)),
            residual=functools.partial(modal_residual_shifted, **fixed),
            residual_mp=functools.partial(modal_residual_shifted_mp, **fixed),
            seeds=functools.partial(_shifted_seeds, **fixed),
            to_gamma=lambda x: nu_ * x * (x + 2 * k_), sheet_margin=lambda x: x.real + k_,
            region=_counting_box(p.m, k_, p.kappa, nu_, p.component),
            determinant=lambda x: np.linalg.det(natural_matrix_shifted(x, **fixed)),
            residuals=functools.partial(modal_residuals_shifted, **fixed),
            noise=functools.partial(modal_noise_shifted, **fixed), branch=-k_)

    return ModalSystem(name="cylinder", n_modes=len(components(p.m, p.k, p.component)),
                       residual=functools.partial(modal_residual, **fixed),
                       residual_mp=functools.partial(modal_residual_mp, **fixed),
                       seeds=functools.partial(modal_seeds, **fixed),
                       to_gamma=lambda beta: nu_ * (beta * beta - k2),
                       sheet_margin=lambda beta: beta.real)


def _modal_system(p: CylinderParams) -> ModalSystem:
    return modal_system(m=p.m, k=p.k, kappa=p.kappa, nu=p.nu, component=p.component)


def _inviscid_modes(p: CylinderParams, kappa):
    return lambda0_squared(p.m, p.k, kappa)


MODEL = register(Model(
    name="cylinder",
    summary="periodic cylindrical membrane in viscous fluid, one mode (m, k R) (thesis 8.1)",
    params=CylinderParams, hill_system=_hill_system, modal_system=_modal_system,
    inviscid_modes=_inviscid_modes,
    inviscid_method="closed form lambda0^2 = kappa (m^2 + k^2 - 1)/M(m, k) (derivations/cylinder.py)",
    physical=PhysicalInput(units=CYLINDER_UNITS, convert=cylinder_physical,
                           note="rho, mu, radius, sigma, omega required together; period L with "
                                "j gives k = 2 pi j R/L")))
