"""Ratios of modified Bessel functions I_m, K_m for complex argument, free of overflow.

Definitions (DLMF 10.25): I_m(z) is regular at z = 0 and grows like e^z / sqrt(2 pi z);
K_m(z) decays like sqrt(pi / (2 z)) e^{-z} as Re z -> +inf; m is a non-negative integer.

Mapping to the thesis notation J_m(i beta), H_m(i beta) = H^(1)_m(i beta) of chapter 4
(DLMF 10.27.6 and 10.27.8, valid for -pi < ph z <= pi/2, which contains Re z >= 0)::

    J_m(i z)     = i^m I_m(z)
    H^(1)_m(i z) = (2 / pi) i^{-m-1} K_m(z)

hence, with x = i z, J_{m+1}(x)/J_m(x) = i ratio_i(m, z) and H_{m+1}(x)/H_m(x) = -i ratio_k(m, z).

Recurrences used (DLMF 10.29.1 and 10.29.2)::

    I_{m-1} - I_{m+1} = (2m/z) I_m            K_{m+1} - K_{m-1} = (2m/z) K_m
    I_m' = I_{m+1} + (m/z) I_m                 K_m' = -K_{m+1} + (m/z) K_m

so z I_m'/I_m = m + z I_{m+1}/I_m and z K_m'/K_m = m - z K_{m+1}/K_m.

Domain: Re z >= 0 (the principal branch of beta = sqrt((gamma + i n)/nu)),
1e-150 <= |z| <= 1e150 (or z = 0 where the limit is finite), integer 0 <= m <= M_MAX. Only
ratios are returned; I_m and K_m themselves overflow or underflow in this range and are never
formed. Invalid input raises :class:`~spectralshell.errors.ParameterError` (a ``ValueError``)
naming the argument; no function returns NaN or inf. Validation (and its messages) is shared with
:mod:`spectralshell.special.spherical`.
"""

from __future__ import annotations

import cmath
import math

import numpy as np

from .spherical import M_MAX, _finish, _invalid, _prepare, ratio_i_continued_fraction

__all__ = ["M_MAX", "ratio_i", "ratio_k", "logderiv_i", "logderiv_k", "k_continuation",
           "logderiv_k_continued"]

# |z| below which I_{m+1}/I_m = z/(2(m+1)) to double precision: the next term of the power series
# (DLMF 10.25.2) is relatively z^2/(4(m+1)(m+2)) < 1e-200.
_Z_TINY = 1e-100
# |z| from which the Hankel expansions (DLMF 10.40.2, 10.40.5) are used. With
# |z| >= max(_Z_ASYMPTOTIC, (m+1)^2) the terms a_k(nu)/z^k (nu <= m+1) fall at least like
# 1/(2^k k!) and keep falling until k ~ 2|z|, so ASYMPTOTIC_TERMS terms reach one ulp and the
# least term, ~e^{-2|z|} < 1e-21, is far below it.
_Z_ASYMPTOTIC = 25.0
_ASYMPTOTIC_TERMS = 40
_EPS = np.finfo(float).eps


# ----------------------------------------------------------------------------- kernels


def _hankel_sums(nu: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """S+ = sum_k a_k(nu) z^-k and S- = sum_k (-1)^k a_k(nu) z^-k (DLMF 10.40.1, 10.17.1).

    a_0 = 1, a_k = a_{k-1} (4 nu^2 - (2k-1)^2) / (8 k). Terms stop being added once they fall below
    one ulp of the partial sum (for |z| >= max(25, nu^2) this happens before the least term).
    """
    nuf = nu.astype(float)
    plus = np.ones(z.shape, dtype=np.complex128)
    minus = np.ones(z.shape, dtype=np.complex128)
    term = np.ones(z.shape, dtype=np.complex128)
    live = np.ones(z.shape, dtype=bool)
    for k in range(1, _ASYMPTOTIC_TERMS + 1):
        term = np.where(live, term * ((4.0 * nuf * nuf - (2.0 * k - 1.0) ** 2) / (8.0 * k)) / z, 0.0)
        plus += term
        minus += term if k % 2 == 0 else -term
        live &= np.abs(term) > _EPS * np.minimum(np.abs(plus), np.abs(minus))
        if not live.any():
            break
    return plus, minus


def _ratio_i_asymptotic(m: np.ndarray, z: np.ndarray) -> np.ndarray:
    """I_{m+1}/I_m from DLMF 10.40.5 with the common factor e^z / sqrt(2 pi z) cancelled.

    sqrt(2 pi z) e^{-z} I_nu(z) ~ S-(nu) + c_nu e^{-2z} S+(nu), c_nu = +-i e^{+-i nu pi}
    (upper signs for Im z >= 0, lower for Im z < 0, the choice valid up to ph z = +-pi/2). For
    integer nu, c_{m+1} = -c_m. The e^{-2z} term (|.| <= 1) matters near the imaginary axis,
    where I_m(iy) = i^m J_m(y) oscillates.
    """
    sign = np.where(z.imag >= 0, 1.0, -1.0)
    c_m = sign * 1j * np.where(m % 2 == 0, 1.0, -1.0)
    e2 = np.exp(-2.0 * z)
    p0, q0 = _hankel_sums(m, z)
    p1, q1 = _hankel_sums(m + 1, z)
    return (q1 - c_m * e2 * p1) / (q0 + c_m * e2 * p0)


def _ratio_i_cf(m: np.ndarray, z: np.ndarray) -> np.ndarray:
    """I_{m+1}/I_m by the continued fraction DLMF 10.33.1 (modified Lentz)."""
    return ratio_i_continued_fraction(m.astype(float), z, "I_(m+1)/I_m")


def _ratio_i_all(m: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Dispatch I_{m+1}/I_m over the three regimes (tiny, continued fraction, asymptotic)."""
    out = np.empty(z.shape, dtype=np.complex128)
    az = np.abs(z)
    tiny = az < _Z_TINY
    asym = ~tiny & (az >= np.maximum(_Z_ASYMPTOTIC, (m + 1.0) ** 2))
    cf = ~tiny & ~asym
    out[tiny] = z[tiny] / (2.0 * (m[tiny] + 1.0))
    if asym.any():
        out[asym] = _ratio_i_asymptotic(m[asym], z[asym])
    if cf.any():
        out[cf] = _ratio_i_cf(m[cf], z[cf])
    return out


def _k1_over_k0(z: np.ndarray) -> np.ndarray:
    """K_1(z)/K_0(z): exponentially scaled AMOS values (scipy ``kve``) for |z| < 25, where they
    agree with mpmath to 2e-15 on Re z >= 0 down to |z| = 1e-150 (tests/test_special_cylindrical.py);
    the Hankel expansion S+(1)/S+(0) (DLMF 10.40.2) above."""
    out = np.empty(z.shape, dtype=np.complex128)
    big = np.abs(z) >= _Z_ASYMPTOTIC
    if big.any():
        p1, _ = _hankel_sums(np.ones(big.sum(), dtype=np.int64), z[big])
        p0, _ = _hankel_sums(np.zeros(big.sum(), dtype=np.int64), z[big])
        out[big] = p1 / p0
    small = ~big
    if small.any():
        zs = z[small]
        import scipy.special as sc  # lazy: ~0.2 s to import (the CLI's start-up)

        out[small] = sc.kve(1, zs) / sc.kve(0, zs)
    return out


def _k_ratio_all(m: np.ndarray, z: np.ndarray) -> np.ndarray:
    """r_m = K_{m+1}/K_m by forward recurrence r_n = 2n/z + 1/r_{n-1} from r_0 = K_1/K_0.

    (DLMF 10.29.1: K_{n+1} = K_{n-1} + (2n/z) K_n.) Forward recurrence is stable because K_n is
    the dominant solution as n grows; K_n has no zeros in Re z >= 0, so r_n != 0.
    """
    r = _k1_over_k0(z)
    mmax = int(m.max()) if m.size else 0
    for n in range(1, mmax + 1):
        act = m >= n
        r = np.where(act, 2.0 * n / z + 1.0 / np.where(act, r, 1.0), r)
    return r


# ----------------------------------------------------------------------------- public API


def ratio_i(m, z):
    """Return I_{m+1}(z) / I_m(z), ratio of regular modified Bessel functions.

    Parameters: ``m`` integer(s) in [0, M_MAX]; ``z`` complex, Re z >= 0, 1e-150 <= |z| <= 1e150
    or z = 0 (value 0). Broadcasts; returns complex128 (a numpy scalar for scalar input).

    Notes
    -----
    * |z| < 1e-100: z/(2(m+1)), the leading term of the power series DLMF 10.25.2.
    * |z| < max(25, (m+1)^2): Gauss continued fraction DLMF 10.33.1, modified Lentz, one-ulp
      stopping test, at most 2|z| + 500 terms.
    * otherwise: Hankel expansion DLMF 10.40.5 including the exponentially small e^{-2z} term,
      which is O(1) near the imaginary axis.

    Near the imaginary axis I_m(iy) = i^m J_m(y) has zeros where this ratio has poles; there the
    relative error is bounded by about cond * eps, cond = |z d/dz log(ratio)|.

    Raises
    ------
    ParameterError : invalid m or z.
    """
    mm, zz, shape = _prepare(m, z, allow_zero=True)
    return _finish(_ratio_i_all(mm, zz), zz, shape)


def ratio_k(m, z):
    """Return K_{m+1}(z) / K_m(z), ratio of decaying modified Bessel functions.

    Parameters: ``m`` integer(s) in [0, M_MAX]; ``z`` complex, Re z >= 0, 1e-150 <= |z| <= 1e150
    (z = 0 is a pole). Broadcasts; returns complex128.

    Notes
    -----
    Forward recurrence r_n = 2n/z + 1/r_{n-1} (DLMF 10.29.1) from r_0 = K_1/K_0, which comes from
    scipy's exponentially scaled ``kve`` (AMOS) for |z| < 25 and from the Hankel expansion
    DLMF 10.40.2 above. Limits: 2m/z for m >= 1 and 1/(z(-log(z/2) - gamma_E)) for m = 0 as
    z -> 0 (DLMF 10.30.2, 10.30.3); 1 + (2m+1)/(2z) + O(z^-2) as z -> inf.

    Raises
    ------
    ParameterError : invalid m or z.
    """
    mm, zz, shape = _prepare(m, z, allow_zero=False)
    return _finish(_k_ratio_all(mm, zz), zz, shape)


def logderiv_i(m, z):
    """Return z I_m'(z) / I_m(z) = m + z I_{m+1}(z)/I_m(z) (DLMF 10.29.2).

    Equals x J_m'(x)/J_m(x) at x = i z (DLMF 10.27.6). Limits: m + z^2/(2(m+1)) as z -> 0;
    z - 1/2 + O(1/z) as z -> inf in |ph z| < pi/2. z = 0 allowed (value m).

    Raises
    ------
    ParameterError : invalid m or z.
    """
    mm, zz, shape = _prepare(m, z, allow_zero=True)
    return _finish(mm + zz * _ratio_i_all(mm, zz), zz, shape)


def logderiv_k(m, z):
    """Return z K_m'(z) / K_m(z) = m - z K_{m+1}(z)/K_m(z) (DLMF 10.29.2).

    Equals x H^(1)_m'(x)/H^(1)_m(x) at x = i z (DLMF 10.27.8). Limits: -m as z -> 0 for m >= 1
    (DLMF 10.30.2); -z - 1/2 + O(1/z) as z -> inf.

    Raises
    ------
    ParameterError : invalid m or z (z = 0 is excluded: for m = 0 the limit is 0 only
        logarithmically).
    """
    mm, zz, shape = _prepare(m, z, allow_zero=False)
    return _finish(mm - zz * _k_ratio_all(mm, zz), zz, shape)


# ----------------------------------------------------------------------------- second sheet


def k_continuation(m: int, w: complex, upper: bool) -> complex:
    """c with K_m(w e^{+-i pi}) = (-1)^m K_m(w) (1 + c), Re w > 0: the continuation of K_m across
    the imaginary axis onto the second sheet (DLMF 10.34.2, integer m),

        c = (-1)^m e I_m(w)/K_m(w),      e = -i pi (upper sign, for Im(-w) >= 0), +i pi (lower).

    I_m/K_m comes from scipy's exponentially scaled ``ive``/``kve`` (AMOS); c = 0 where I_m
    underflows, and an I_m/K_m beyond double range raises OverflowError (w far into the sheet).
    """
    import scipy.special as sc  # lazy: ~0.2 s to import

    i_scaled, k_scaled = complex(sc.ive(m, w)), complex(sc.kve(m, w))
    if i_scaled == 0 or not cmath.isfinite(k_scaled) or k_scaled == 0:
        return 0j
    e = -1j * math.pi if upper else 1j * math.pi
    sign = -1.0 if m % 2 else 1.0
    return sign * e * i_scaled / k_scaled * cmath.exp(w.real + w)  # I/K = (ive/kve) e^{|Re w| + w}


def logderiv_k_continued(m: int, z: complex) -> complex:
    """Return z K_m'(z)/K_m(z) on both sheets of K_m: :func:`logderiv_k` for Re z >= 0, and for
    Re z < 0 its analytic continuation across the imaginary axis (from Im z >= 0 across the
    positive half, otherwise across the negative half; mpmath's principal branch agrees).

    With w = -z and c from :func:`k_continuation`, K_m(z) = (-1)^m K_m(w) (1 + c) and

        z K_m'(z)/K_m(z) = (w K_m'/K_m (w) + c w I_m'/I_m (w)) / (1 + c),

    evaluated as (L_K/c + L_I)/(1/c + 1) when |c| > 1 (L_I alone once 1/c underflows).

    Raises
    ------
    ParameterError : invalid m or z (as :func:`logderiv_k` at w).
    """
    z = complex(z)
    if z.real >= 0:
        return complex(logderiv_k(m, z))
    w = -z
    lk, li = complex(logderiv_k(m, w)), complex(logderiv_i(m, w))
    try:
        c = k_continuation(m, w, z.imag >= 0)
    except OverflowError:
        return li
    if abs(c) <= 1.0:
        return (lk + c * li) / (1.0 + c)
    return (lk / c + li) / (1.0 / c + 1.0)
