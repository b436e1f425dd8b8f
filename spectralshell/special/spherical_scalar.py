"""Scalar i_{m+1}(z)/i_m(z) for one complex z: the ratio of :mod:`.spherical` without numpy.

A root finder evaluates the ratio a few times per root, where the per-call overhead of the
vectorised kernels of :mod:`.spherical` would dominate. Same definitions (DLMF 10.47) and domain
(Re z >= 0, z != 0, 0 <= m <= 200); about 1e-14 relative, tested against mpmath.
"""

from __future__ import annotations

import cmath
import functools
import math

from ..errors import ParameterError

__all__ = ["ratio_i_scalar"]

# The terminating expansion DLMF 10.49.8 is tried from |z| = 16 (as in special/spherical.py) and
# accepted when its rounding-error bound, eps * (sum of |terms|) / |sum|, is below 500 eps.
_CLOSED_MIN = 16.0
_CLOSED_COND = 500.0
_CF_LEVELS_MAX = 2_000_000


@functools.lru_cache(maxsize=None)
def _closed_coefficients(n: int) -> tuple[float, ...]:
    """a_k(n+1/2) / n^k for k = n, n-1, ..., 0 (Horner order; DLMF 10.49.1). The scaling by n^k
    keeps them finite for every n <= 200 (unscaled, a_n(n+1/2) = (2n)!/(n! 2^n) overflows)."""
    out, c = [1.0], 1.0
    for k in range(1, n + 1):
        c *= (n + k) * (n - k + 1) / (2.0 * k * n)
        out.append(c)
    return tuple(reversed(out))


def _closed_sums(n: int, w: complex, aw: float, both: bool) -> tuple[complex, complex, float]:
    """sum_k a_k(n+1/2) w^k (if ``both``, else 0), sum_k (-1)^k a_k(n+1/2) w^k and
    sum_k a_k(n+1/2) |w|^k, by Horner's rule in n w."""
    coeffs = _closed_coefficients(n)
    x, ax = n * w, n * aw
    q, size = 0j, 0.0
    for c in coeffs:
        q = q * -x + c
        size = size * ax + c
    if not both:
        return 0j, q, size
    p = 0j
    for c in coeffs:
        p = p * x + c
    return p, q, size


def _ratio_i_closed(m: int, z: complex) -> tuple[complex, float]:
    """i_{m+1}(z)/i_m(z) from DLMF 10.49.8 with e^z cancelled, and its relative error bound / eps.

    i_n(z) = (e^z/(2z)) [Q_n(z) - (-1)^n e^{-2z} P_n(z)], P_n = sum_k a_k(n+1/2) z^{-k},
    Q_n = sum_k (-1)^k a_k(n+1/2) z^{-k}; Re z >= 0 keeps |e^{-2z}| <= 1, and for Re z >= 25 the
    P_n terms (relative size <= e^{-50} times the error bound) are dropped.
    """
    w = 1.0 / z
    aw = abs(w)
    both = z.real < 25.0
    e2 = cmath.exp(-2.0 * z) if both else 0j
    ae = abs(e2)
    p0, q0, s0 = _closed_sums(m, w, aw, both)
    p1, q1, s1 = _closed_sums(m + 1, w, aw, both)
    sign = 1.0 if m % 2 == 0 else -1.0
    num = q1 + sign * e2 * p1
    den = q0 - sign * e2 * p0
    if num == 0 or den == 0:
        return 0j, math.inf
    cond = (1.0 + ae) * (s1 / abs(num) + s0 / abs(den))
    return num / den, cond


def _cf_levels(m: int, z: complex) -> int:
    """Depth K of the continued fraction DLMF 10.33.1 for i_{m+1}/i_m that reaches double precision.

    The tail error is damped by prod_n |i_{n+1}/i_n|^2 over the K levels, and by the Debye form
    (DLMF 10.41.3) i_{n+1}/i_n ~ exp(-asinh((n+1)/z)); K is the depth at which
    2 sum Re asinh((n+1)/z) exceeds 40 (e^-40 ~ 4e-18), plus a 25 % margin and 16 levels.
    """
    total, k, h = 0.0, 0, 4
    while total < 40.0:
        total += 2.0 * h * cmath.asinh((m + k + 1.0 + 0.5 * h) / z).real
        k += h
        if k > _CF_LEVELS_MAX:
            raise ParameterError(f"beta = {z!r} is invalid: must be a point where the continued "
                                 f"fraction for i_(m+1)/i_m (m = {m}) converges in "
                                 f"{_CF_LEVELS_MAX} levels")
        h = min(2 * h, 64) if total < 20.0 else 4
    return int(1.25 * k) + 16


def _ratio_i_cf(m: int, z: complex, levels: int) -> complex:
    """i_{m+1}(z)/i_m(z) by the backward recurrence r_{n-1} = 1/((2n+1)/z + r_n) (DLMF 10.33.1),
    started ``levels`` orders up from the Debye estimate r_N = z/(N + 3/2 + sqrt((N+3/2)^2 + z^2))."""
    n_top = m + levels
    w = 1.0 / z
    a = n_top + 1.5
    r = z / (a + cmath.sqrt(a * a + z * z))
    for n in range(n_top, m, -1):
        r = 1.0 / ((2 * n + 1) * w + r)
    return r


def ratio_i_scalar(m: int, z: complex) -> complex:
    """i_{m+1}(z)/i_m(z) for Re z >= 0, z != 0, to about 1e-14 relative (away from its poles).

    The terminating expansion is used when |z| >= 16 and its terms stay small: their largest
    size, about exp((m+1)^2 (1 + cos arg z)/(2|z|)), predicts the error bound, which is then
    checked (<= 500 eps); otherwise the continued fraction, whose depth is of order
    |z|/(m cos arg z) + |z| - m there (a few tens to a few hundred levels).
    """
    az = abs(z)
    if az >= _CLOSED_MIN and (m + 1) ** 2 * (1.0 + z.real / az) <= 12.0 * az:
        r, cond = _ratio_i_closed(m, z)
        if cond <= _CLOSED_COND:
            return r
    return _ratio_i_cf(m, z, _cf_levels(m, z))
