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

Natural modes (tau = 0): det D(gamma) = 0 in beta = sqrt(gamma/nu + k^2) (:func:`modal_system`,
one mode per component; the cut of D is gamma <= -nu k^2, ``HillSystem.branch_point``), from which
the Floquet exponents are continued.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Iterator

import mpmath
import numpy as np

from .._validate import invalid
from ..errors import ParameterError
from ..params.cylinder import CYLINDER_UNITS, CylinderParams, cylinder_physical
from ..params.registry import Model, PhysicalInput, register
from ..special.cylindrical import logderiv_i, logderiv_k, logderiv_k_continued
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


def _interface_entries(m: int, k: float, s, nu, lam, L) -> tuple[list, list]:
    """V, T at r = 1 per amplitude (a, A, C) as 3 x 3 nested lists of entries: numpy arrays over
    s (broadcast by the caller) or mpmath numbers."""
    b2 = s / nu + k * k
    V = [[-lam / s, 1j * m, 1j * k * L],
         [-1j * m / s, -L, -m * k],
         [-1j * k / s, 0, -b2]]
    du = [[-(k * k + m * m - lam) / s, 1j * m * (L - 1), 1j * k * (b2 + m * m - L)],
          [-1j * m * (lam - 1) / s, -(b2 + m * m - L), -m * k * (L - 1)],
          [-1j * k * lam / s, 0, -b2 * L]]
    T = [[2 * nu * d for d in du[0]],
         [nu * (du[1][j] - V[1][j] + 1j * m * V[0][j]) for j in range(3)],
         [nu * (du[2][j] + 1j * k * V[0][j]) for j in range(3)]]
    T[0][0] -= 1
    return V, T


def _interface(m: int, k: float, s: np.ndarray, nu: float, lam: np.ndarray | float,
               L: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """V, T (shape (len(s), 3, 3)): velocity and traction at r = 1 per amplitude (a, A, C)."""
    V, T = _interface_entries(m, k, s, nu, lam, L)

    def stacked(rows: list) -> np.ndarray:
        return np.stack([np.stack(np.broadcast_arrays(s, *row)[1:], -1) for row in rows], -2)

    return stacked(V).astype(complex), stacked(T).astype(complex)


def _pressure_logderivs(m: int, k: float) -> tuple[float, float]:
    """(Lambda_in, Lambda_out) = k I_m'(k)/I_m(k), k K_m'(k)/K_m(k); (m, -m) at k = 0, m >= 1."""
    if k == 0.0:
        return float(m), -float(m)
    return float(np.real(logderiv_i(m, k))), float(np.real(logderiv_k(m, k)))


def fluid_load(s: np.ndarray, *, m: int, k: float, nu: float) -> np.ndarray:
    """H(s) (shape (len(s), 3, 3), s != 0): the fluid's load on (X^r, X^theta, X^z) in the real basis.

    Notes
    -----
    As s -> 0 (beta -> k) the pressure and vortical fields nearly coincide, and the relative
    error of H grows like eps nu k^2 / |s| (measured against 40-digit mpmath); H itself is O(s),
    so D = H + kappa E keeps its accuracy relative to kappa E.

    Raises
    ------
    ParameterError : an s whose beta = sqrt(s/nu + k^2) leaves the Bessel kernels' domain.
    """
    s = np.asarray(s, dtype=complex).ravel()
    return _fluid_load_at(s, np.sqrt(s / nu + k * k), m=m, k=k, nu=nu)


def _fluid_load_at(s: np.ndarray, beta: np.ndarray, *, m: int, k: float, nu: float) -> np.ndarray:
    """H(s) at beta with beta^2 = s/nu + k^2 on either sheet: the principal one (Re beta >= 0, the
    exterior field decays) or, for Re beta < 0, its continuation across the imaginary beta axis
    (:func:`~spectralshell.special.cylindrical.logderiv_k_continued`; I_m(beta r) is even up to
    sign, so only K_m carries the sheet)."""
    lam_in, lam_out = _pressure_logderivs(m, k)
    second = beta.real < 0
    with boundary_layer(nu):
        L_in = np.atleast_1d(logderiv_i(m, np.where(second, -beta, beta))).astype(complex)
        L_out = np.empty(beta.shape, dtype=complex)
        L_out[~second] = logderiv_k(m, beta[~second])
        L_out[second] = [logderiv_k_continued(m, b) for b in beta[second]]
    Vi, Ti = _interface(m, k, s, nu, lam_in, L_in)
    Vo, To = _interface(m, k, s, nu, lam_out, L_out)
    # Z = T V^-1 on each side, as (V^T)^-1 T^T transposed
    Z = (np.linalg.solve(np.swapaxes(Vi, 1, 2), np.swapaxes(Ti, 1, 2))
         - np.linalg.solve(np.swapaxes(Vo, 1, 2), np.swapaxes(To, 1, 2)))
    Z = np.swapaxes(Z, 1, 2)
    return s[:, None, None] * Z * _S[None, None, :] / _S[None, :, None]


def unforced(s: np.ndarray, *, m: int, k: float, kappa: float, nu: float,
             component: str = "coupled") -> np.ndarray:
    """D(s) = H(s) + kappa E on the set ``component``, shape (len(s), b, b); D(0) = kappa E."""
    s = np.asarray(s, dtype=complex).ravel()
    return _unforced_at(s, np.sqrt(s / nu + k * k), m=m, k=k, kappa=kappa, nu=nu,
                        component=component)


def _unforced_at(s: np.ndarray, beta: np.ndarray, *, m: int, k: float, kappa: float, nu: float,
                 component: str) -> np.ndarray:
    """:func:`unforced` at beta on either sheet (:func:`_fluid_load_at`)."""
    idx = components(m, k, component)
    E = kappa * elastic_matrix(m, k)[np.ix_(idx, idx)]
    out = np.broadcast_to(E, (s.size, len(idx), len(idx))).astype(complex)
    live = s != 0
    if live.any():
        out[live] += _fluid_load_at(s[live], beta[live], m=m, k=k, nu=nu)[:, idx][:, :, idx]
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

#: Range of zeta = nu/sqrt(kappa) over which the seeds find every mode and the count was checked
#: by the argument principle (tests/test_cylinder_modes.py), for m <= 200, k <= 10; the upper end
#: depends on m and k (:func:`zeta_max`), ZETA_MAX is its largest value.
ZETA_MIN = 1e-8
ZETA_MAX = 0.3
#: Where the seeds' continuation in zeta starts: below ZETA_START_CHECKED the asymptotic seeds
#: alone find every mode.
ZETA_START = 0.04
ZETA_START_CHECKED = 0.05
#: (largest m of a tier, its upper end of zeta) above ZETA_START_CHECKED (checked on grids).
_ZETA_TOPS = ((25, 0.3), (60, 0.15))
#: Relative step of the 4-point derivative of the determinant in beta (error ~ step^4).
_STEP = 1e-3


def zeta_max(m: int, k: float, component: str = "coupled") -> float:
    """Largest zeta = nu/sqrt(kappa) at which the modes of (m, k, component) are offered:
    max(0.05, min(z_m, 2/k^2)) with z_m = 0.3 for m <= 25, 0.15 for m <= 60 and 0.05 above (the
    continuation in zeta loses a mode near the cut at zeta 0.2-0.3 for m = 35..60 and at some
    zeta in 0.1-0.3 for m = 100, 200).

    Above it the number of modes on the physical sheet can exceed the number b of components (a
    conjugate pair of overdamped modes splits into two real decays in -nu k^2 < gamma < 0: four
    modes at m = 1, k = 2, zeta = 1 and at m = 1, k = 10, zeta = 0.3), which the root finder,
    looking for b modes, does not yet certify; up to 0.05 the asymptotic seeds alone were
    checked for m <= 200, k <= 10, and up to the end here also the continuation in zeta
    (tests/test_cylinder_modes.py). At k = 0 the fibre pair also stops at
    :func:`spectralshell.models.fibre.zeta_max` (not reached below 0.3)."""
    tier = next((end for largest, end in _ZETA_TOPS if m <= largest), ZETA_START_CHECKED)
    top = max(ZETA_START_CHECKED, min(tier, 2.0 / k**2)) if k > 0 else tier
    if k == 0 and component == "coupled":
        top = min(top, fibre.zeta_max(m))
    return top


def natural_matrix(beta: np.ndarray, *, m: int, k: float, kappa: float, nu: float,
                   component: str = "coupled") -> np.ndarray:
    """D(gamma)/kappa at gamma = nu (beta^2 - k^2) for each beta, shape (len(beta), b, b): on the
    physical sheet for Re beta > 0, continued across the imaginary axis (the cut) for
    Re beta < 0; its determinant vanishes at the natural modes e^{gamma t}."""
    beta = np.asarray(beta, dtype=complex).ravel()
    return _unforced_at(nu * (beta * beta - k * k), beta, m=m, k=k, kappa=kappa, nu=nu,
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


def _logderivs_mp(m: int, z) -> tuple:
    """(z I_m'(z)/I_m(z), z K_m'(z)/K_m(z)) in mpmath (DLMF 10.29.2); (m, -m) at z = 0."""
    if z == 0:
        return mpmath.mpf(m), -mpmath.mpf(m)
    return (m + z * mpmath.besseli(m + 1, z) / mpmath.besseli(m, z),
            m - z * mpmath.besselk(m + 1, z) / mpmath.besselk(m, z))


def natural_determinant_mp(beta, *, m: int, k: float, kappa: float, nu: float,
                           component: str = "coupled"):
    """det D(gamma)/kappa^b at gamma = nu (beta^2 - k^2) in mpmath at the current precision
    (beta on the physical sheet, gamma != 0): :func:`natural_matrix` with mpmath's Bessel
    functions."""
    beta, k_, nu_ = mpmath.mpc(beta), mpmath.mpf(k), mpmath.mpf(nu)
    s = nu_ * (beta * beta - k_ * k_)
    lam = _logderivs_mp(m, k_)
    L = _logderivs_mp(m, beta)
    Z = []
    for side in range(2):
        V, T = (mpmath.matrix(a) for a in _interface_entries(m, k_, s, nu_, lam[side], L[side]))
        Z.append(T * mpmath.inverse(V))
    idx = components(m, k, component)
    E = elastic_matrix(m, k)
    D = mpmath.matrix(len(idx), len(idx))
    for a, i in enumerate(idx):
        for c, j in enumerate(idx):
            D[a, c] = s * (Z[0][i, j] - Z[1][i, j]) * _S[j] / _S[i] / kappa + E[i, j]
    return mpmath.det(D)


def modal_residual_mp(beta, *, m: int, k: float, kappa: float, nu: float,
                      component: str = "coupled"):
    """:func:`modal_residual` in mpmath: the derivative by the 4-point difference with step
    10^(-dps/3) |beta| (error ~10^(-4 dps/3))."""
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


def modal_system(*, m: int, k: float, kappa: float, nu: float,
                 component: str = "coupled") -> ModalSystem:
    """Natural modes of the mode (m, k) of the cylinder as a :class:`ModalSystem` in beta.

    Notes
    -----
    x = beta = sqrt(gamma/nu + k^2) (Re beta > 0 on the physical sheet), gamma = nu (beta^2 - k^2),
    residual det D(gamma)/kappa^b (:func:`modal_residual`, :func:`modal_residual_mp`), seeds
    :func:`modal_seeds`. n_modes is the number b of components of the set (3 coupled, 2 for the
    sausage pair (m = 0) and the fibre pair (k = 0), 1 for torsion or axial): one oscillation
    (gamma -> i lambda0 as nu -> 0) for a set containing X^r, one Stokes-layer relaxation per
    tangential component. Argument-principle counts of det D over the first beta-quadrant find
    exactly b roots (tests/test_cylinder_modes.py); at k = 0 the pair is the fibre's.

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
        raise invalid("zeta", zeta, f"in [{ZETA_MIN:g}, {top:.4g}] for m = {p.m}, k = {p.k:g} "
                      "(zeta = nu/sqrt(kappa): the range over which the mode count is verified)")
    fixed = {"m": p.m, "k": p.k, "kappa": p.kappa, "nu": p.nu, "component": p.component}
    nu_, k2 = p.nu, p.k * p.k

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
