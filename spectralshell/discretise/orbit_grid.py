"""Space-time grid, real spherical-harmonic basis and index map of a time-periodic membrane orbit.

Used by the direct (non-perturbative) solve of the nonlinear inviscid membrane problem
(:mod:`spectralshell.solvers.nonlinear_orbit`, thesis 7.3). Conventions, written once here:

* Angles: polar ``theta`` in [0, pi], azimuth ``phi`` (the thesis calls them eta/phi and xi/theta).
* Real orthonormal harmonics, no Condon-Shortley phase::

      Yr_{n,l}(theta, phi) = c_{n,l} Pt_n^l(cos theta) cos(l phi),   l >= 0,
      Pt_n^l(x) = (1 - x^2)^{l/2} d^l P_n / dx^l,
      c_{n,l}^2 = (2 - delta_{l0}) (2n+1)/(4 pi) (n-l)!/(n+l)!,

  so that int Yr_{n,l} Yr_{n',l'} dOmega = delta delta, and Yr_{m,0} = Y_{m,0}, Yr_{m,k} =
  sqrt(2) (-1)^k Re Y_{m,k} for the complex Y of the thesis (6.7). Only cos(l phi) occurs: the
  orbits computed are even in phi (initial shape even in phi).
* Time: tau = lambda t in [0, 2 pi); the radius is a cosine series in tau (even), the potentials sine
  series (odd): the problem is reversible and the orbit starts at rest.

Symmetries used to shrink the unknowns (exact for the orbit through 1 + eps Yr_{m,k}):

* l is a multiple of k (l = 0 only if k = 0);
* z -> -z multiplies Yr_{n,l} by (-1)^(n+l). If m + k is even the orbit is z-symmetric: n + l even.
  If m + k is odd, z -> -z together with tau -> tau + pi is a symmetry: n + l + j even.
* k >= 1: phi -> phi + pi/k together with tau -> tau + pi is a symmetry: l/k + j even.

These rules exclude the rigid translation (degree 1) at j = 0 in every case.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import sph_harm_y

__all__ = ["allowed", "mode_list", "real_harmonics", "OrbitGrid", "make_grid"]


def allowed(n: int, l: int, j: int, *, m: int, k: int) -> bool:
    """Whether (degree n, order l, time harmonic j) can occur in the orbit through Yr_{m,k}."""
    if l > n:
        return False
    if k == 0:
        if l != 0:
            return False
    else:
        if l % k:
            return False
        if (l // k + j) % 2:
            return False
    if (m + k) % 2 == 0:
        return (n + l) % 2 == 0
    return (n + l + j) % 2 == 0


def mode_list(*, m: int, k: int, n_max: int, j_max: int, j_min: int = 0) -> list[tuple[int, int, int]]:
    """All allowed (n, l, j) with n <= n_max and j_min <= j <= j_max, in (n, l, j) order."""
    l_max = n_max if k else 0
    return [(n, l, j) for n in range(n_max + 1) for l in range(0, l_max + 1)
            for j in range(j_min, j_max + 1) if allowed(n, l, j, m=m, k=k)]


def real_harmonics(n: int, l: int, theta: np.ndarray, phi: np.ndarray):
    """Yr_{n,l}, d Yr/d theta and (1/sin theta) d Yr/d phi on the grid theta x phi (shape (T, P)).

    d/dtheta of the normalised Pb_n^l = c Pt_n^l (no Condon-Shortley phase):
    dPb^l/dtheta = (sqrt((n+l)(n-l+1)) Pb^{l-1} - sqrt((n-l)(n+l+1)) Pb^{l+1})/2, with
    Pb^{-1} = -Pb^{1} (DLMF 14.10.1 in normalised form; checked by finite differences in the tests).
    """
    th = np.asarray(theta, dtype=float)[:, None]
    ph = np.asarray(phi, dtype=float)[None, :]

    def pb(ll):
        if ll < 0:
            return -pb(-ll)
        if ll > n:
            return np.zeros_like(th)
        return ((-1) ** ll) * sph_harm_y(n, ll, th, 0.0).real

    scale = np.sqrt(2.0) if l > 0 else 1.0
    p = pb(l)
    dp = 0.5 * (np.sqrt((n + l) * (n - l + 1.0)) * pb(l - 1) - np.sqrt((n - l) * (n + l + 1.0)) * pb(l + 1))
    val = scale * p * np.cos(l * ph)
    dth = scale * dp * np.cos(l * ph)
    dph_sin = -scale * l * (p / np.sin(th)) * np.sin(l * ph)
    return val, dth, dph_sin


@dataclass(frozen=True, kw_only=True, eq=False)
class OrbitGrid:
    """Collocation grid tau x theta x phi with quadrature weights and basis tables.

    ``Y[i]``, ``Yth[i]``, ``Yph[i]`` hold Yr, d/dtheta Yr and (1/sin) d/dphi Yr of ``modes[i]``
    (shape (T, P)); ``w`` holds the angular quadrature weights (Gauss-Legendre in cos theta times
    the trapezoidal rule in phi; exact for band-limited products up to the stated degrees).
    """

    m: int
    k: int
    n_max: int
    j_max: int
    modes: tuple[tuple[int, int], ...]
    tau: np.ndarray
    theta: np.ndarray
    phi: np.ndarray
    w: np.ndarray
    Y: np.ndarray
    Yth: np.ndarray
    Yph: np.ndarray


def make_grid(*, m: int, k: int, n_max: int, j_max: int, n_theta: int | None = None,
              n_phi: int | None = None, n_tau: int | None = None) -> OrbitGrid:
    """Grid for the orbit through Yr_{m,k}, degrees <= n_max and time harmonics <= j_max.

    Defaults de-alias the cubic-and-rational nonlinearity generously: n_theta = 2 n_max + 8 Gauss
    points, n_phi = 4 (n_max // k) + 4 points on one period 2 pi/k (k > 0; 1 for k = 0),
    n_tau = 4 j_max + 4.
    """
    n_theta = n_theta or 2 * n_max + 8
    n_phi = n_phi or (1 if k == 0 else 4 * (n_max // k) + 4)
    n_tau = n_tau or 4 * j_max + 4
    x, wx = np.polynomial.legendre.leggauss(n_theta)
    theta = np.arccos(x)
    # every order l is a multiple of k: one period 2 pi/k in phi suffices; the trapezoidal weight
    # 2 pi/n_phi then integrates over the full circle (k periods of width 2 pi/(k n_phi) each)
    phi = 2 * np.pi * np.arange(n_phi) / (n_phi * max(k, 1))
    w = np.outer(wx, np.full(n_phi, 2 * np.pi / n_phi))
    modes = sorted({(n, l) for (n, l, _) in mode_list(m=m, k=k, n_max=n_max, j_max=j_max)})
    tabs = [real_harmonics(n, l, theta, phi) for (n, l) in modes]
    Y = np.array([t[0] for t in tabs])
    Yth = np.array([t[1] for t in tabs])
    Yph = np.array([t[2] for t in tabs])
    tau = 2 * np.pi * np.arange(n_tau) / n_tau
    return OrbitGrid(m=m, k=k, n_max=n_max, j_max=j_max, modes=tuple(modes), tau=tau, theta=theta,
                     phi=phi, w=w, Y=Y, Yth=Yth, Yph=Yph)
