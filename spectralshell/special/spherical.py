"""Ratios of modified spherical Bessel functions for complex argument, free of overflow.

Definitions (DLMF 10.47.7 and 10.47.9; ``n = m`` a non-negative integer)::

    i_m(z) = sqrt(pi / (2 z)) I_{m+1/2}(z)        (regular at z = 0; DLMF's i^(1)_m)
    k_m(z) = sqrt(pi / (2 z)) K_{m+1/2}(z)        (decays as Re z -> +inf)

so that ``i_0(z) = sinh(z)/z`` and ``k_0(z) = (pi/2) e^{-z}/z``.  Note: some books (e.g. Arfken)
use ``sqrt(2/(pi z)) K_{m+1/2}(z)`` for k; that differs from DLMF's k_m by the constant factor
``2/pi`` only, which cancels in every quantity computed here.

Mapping to the thesis notation ``j_m(i beta)`` and ``h_m^(1)(i beta)`` (DLMF 10.47.12 and
10.47.14, which hold for every ``z != 0`` because i_m, j_m are entire and k_m, h^(1)_m are
single-valued for integer m, DLMF 10.49.6, 10.49.12)::

    j_m(i z)     = i^m i_m(z)                   (DLMF 10.47.12: i_m(z) = i^{-m} j_m(i z))
    h^(1)_m(i z) = -(2/pi) i^{-m} k_m(z)        (DLMF 10.47.14: k_m(z) = -(pi/2) i^m h^(1)_m(i z))

Consequently, with ``x = i z``::

    j_{m+1}(x) / j_m(x)      =  i * ratio_i(m, z)
    h^(1)_{m+1}(x) / h^(1)_m(x) = -i * ratio_k(m, z)
    x j_m'(x) / j_m(x)         = logderiv_i(m, z)     (z d/dz = x d/dx)
    x h^(1)_m'(x) / h^(1)_m(x) = logderiv_k(m, z)

Recurrences used (DLMF 10.51.4 and 10.51.5 with g_m = i_m or g_m = (-1)^m k_m)::

    i_{m-1} - i_{m+1} = ((2m+1)/z) i_m            k_{m+1} = k_{m-1} + ((2m+1)/z) k_m
    i_m' = i_{m+1} + (m/z) i_m                     k_m' = -k_{m+1} + (m/z) k_m

hence ``z i_m'/i_m = m + z i_{m+1}/i_m`` and ``z k_m'/k_m = m - z k_{m+1}/k_m``.

Domain: ``Re z >= 0`` (the principal branch of ``beta = sqrt((gamma + i n)/nu)``),
``1e-150 <= |z| <= 1e150`` (or ``z = 0`` where the limit is finite), integer
``0 <= m <= M_MAX``.  Only ratios are returned; the raw functions overflow or underflow in the
parameter ranges of interest and are never formed.  Inputs for which a
reliable value cannot be computed raise :class:`~spectralshell.errors.ParameterError`
(a ``ValueError``); no function returns NaN or inf.
"""

from __future__ import annotations

import numpy as np

from ..errors import ParameterError
from . import _lentz

__all__ = ["M_MAX", "ratio_i", "ratio_k", "ratio_pair", "logderiv_i", "logderiv_k"]

#: Largest degree accepted.  The physics needs m <= 61; the bound keeps the worst-case cost
#: of the continued fraction (about (m+1)(m+2) terms, reached near Re z = 0 with |z| just
#: below (m+1)(m+2)) under about 1 s per point; for m <= 61 it is under 0.1 s.
M_MAX = 200

# |z| below which i_{m+1}/i_m = z/(2m+3) to double precision (the next term of the series,
# DLMF 10.53.3, is relatively z^2/((2m+3)(2m+5)) < 1e-200) and the continued fraction's
# coefficients (2m+2k+1)/z would approach overflow.
_Z_TINY = 1e-100
# |z| from which the terminating expansion (DLMF 10.49.8) is used for i_{m+1}/i_m when also
# |z| >= (m+1)(m+2); below it the continued fraction (DLMF 10.33.1) is used.
_Z_CLOSED_MIN = 16.0
# Accepted |z| (besides z = 0 where the limit is finite).  The bounds keep every quantity
# formed below -- z^2, (2m+1)/z, e^{-2z}, the results -- normal floating-point numbers.
_Z_MIN = 1e-150
_Z_MAX = 1e150


# ----------------------------------------------------------------------------- validation


def _invalid(name: str, value: object, allowed: str) -> ParameterError:
    return ParameterError(f"{name} = {value!r} is invalid: must be {allowed}")


def _check_m(m: object) -> np.ndarray:
    """Return ``m`` as an int64 array, or raise ParameterError naming ``m``."""
    allowed = f"an integer in [0, {M_MAX}]"
    try:
        arr = np.asarray(m)
    except Exception:  # pragma: no cover - exotic objects
        raise _invalid("m", m, allowed) from None
    if arr.dtype.kind not in "iuf":
        raise _invalid("m", m, allowed)
    flat = arr.ravel()
    if arr.dtype.kind == "f":
        bad = ~np.isfinite(flat)
        bad[~bad] = flat[~bad] != np.round(flat[~bad])
        if bad.any():
            raise _invalid("m", flat[bad][0].item(), allowed)
    bad = (flat < 0) | (flat > M_MAX)
    if bad.any():
        raise _invalid("m", flat[bad][0].item(), allowed)
    return arr.astype(np.int64)


def _check_z(z: object, *, allow_zero: bool) -> np.ndarray:
    """Return ``z`` as a complex128 array, or raise ParameterError naming ``z``."""
    allowed = (
        f"a complex number with Re z >= 0 and {_Z_MIN:g} <= |z| <= {_Z_MAX:g}"
        + (" (or z = 0)" if allow_zero else "")
    )
    try:
        arr = np.asarray(z)
        if arr.dtype.kind not in "iufc" or arr.dtype.kind == "b":
            raise TypeError
        arr = arr.astype(np.complex128)
    except (TypeError, ValueError):
        raise _invalid("z", z, allowed) from None
    flat = arr.ravel()
    bad = ~np.isfinite(flat)
    ok = ~bad
    az = np.abs(flat[ok])
    bad[ok] = (flat[ok].real < 0) | (az > _Z_MAX) | ((az < _Z_MIN) & ((az != 0) | (not allow_zero)))
    if bad.any():
        raise _invalid("z", complex(flat[bad][0]), allowed)
    return arr


def _prepare(m: object, z: object, *, allow_zero: bool):
    m_arr = _check_m(m)
    z_arr = _check_z(z, allow_zero=allow_zero)
    try:
        m_b, z_b = np.broadcast_arrays(m_arr, z_arr)
    except ValueError:
        raise ParameterError(
            f"z = <array of shape {z_arr.shape}> is invalid: "
            f"must be broadcastable with m of shape {m_arr.shape}"
        ) from None
    return m_b.ravel(), z_b.ravel(), m_b.shape


def _finish(out: np.ndarray, z: np.ndarray, shape: tuple) -> np.ndarray | np.complex128:
    bad = ~np.isfinite(out)
    if bad.any():  # defensive: the algorithms below are not expected to produce this
        raise _invalid("z", complex(z[bad][0]), "a point with a finite result (please report)")
    out = out.reshape(shape)
    return out[()] if out.ndim == 0 else out


# ----------------------------------------------------------------------------- kernels


def ratio_i_continued_fraction(order: np.ndarray, z: np.ndarray, label: str) -> np.ndarray:
    """I_{order+1}(z)/I_order(z) for real orders >= 0 by the continued fraction DLMF 10.33.1
    (modified Lentz); shared by the spherical and cylindrical kernels.

    I_nu/I_{nu-1} = 1/(b_1 + 1/(b_2 + ...)), b_k = 2(nu + k - 1)/z with nu = order + 1, so
    b_k = 2(order + k)/z, summed to a relative change of one ulp. The tail converges once k
    exceeds about |z|; the cap allows 2|z| + 500 terms. Compiled (``_lentz.c``): a Hill
    truncation needs the ratio at a few points, ~60 terms each, where a vectorised numpy loop
    costs ~9 us of call overhead per term. ``label`` names the ratio (and its order) in the
    error message.
    """
    out = np.empty(z.shape, dtype=np.complex128)
    order = np.ascontiguousarray(np.broadcast_to(order, z.shape), dtype=float).ravel()
    flat = np.ascontiguousarray(z, dtype=np.complex128).ravel()
    failed = _lentz.ratio_i(order, flat, out.reshape(-1))
    if failed >= 0:
        raise _invalid("z", complex(flat[failed]), f"a point where the continued fraction for "
                       f"{label} (order {float(order[failed]):g}) converges within "
                       f"{2.0 * abs(flat[failed]) + 500.0:.0f} terms")
    return out


def _ratio_i_cf(m: np.ndarray, z: np.ndarray) -> np.ndarray:
    """i_{m+1}(z)/i_m(z) = I_{m+3/2}(z)/I_{m+1/2}(z) (the factor sqrt(pi/(2z)) cancels)."""
    return ratio_i_continued_fraction(m.astype(float) + 0.5, z, "i_(m+1)/i_m")


def _bessel_poly_sums(n: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return P = sum_k a_k(n+1/2) z^{-k} and Q = sum_k (-1)^k a_k(n+1/2) z^{-k} (DLMF 10.49.1).

    Terms are generated by tau_0 = 1, tau_k = tau_{k-1} (n+k)(n-k+1) / (2 k z); they vanish
    for k > n.  Intended for |z| >= n(n+1), where |tau_k| decreases at least geometrically
    (ratio <= 1/2), so there is no overflow and cancellation costs at most a factor ~5.
    """
    nf = n.astype(float)
    p = np.ones(z.shape, dtype=np.complex128)
    q = np.ones(z.shape, dtype=np.complex128)
    tau = np.ones(z.shape, dtype=np.complex128)
    kmax = int(n.max()) if n.size else 0
    for k in range(1, kmax + 1):
        fac = np.maximum((nf + k) * (nf - k + 1.0), 0.0) / (2.0 * k)
        tau = tau * fac / z
        p += tau
        q += tau if k % 2 == 0 else -tau
    return p, q


def _ratio_i_closed(m: np.ndarray, z: np.ndarray) -> np.ndarray:
    """i_{m+1}(z)/i_m(z) from the terminating expansion DLMF 10.49.8, e^{z} cancelled.

    i_n(z) = (e^z / (2z)) [Q_n(z) + (-1)^{n+1} e^{-2z} P_n(z)] with P_n, Q_n from
    :func:`_bessel_poly_sums`.  e^{-2z} has modulus <= 1 for Re z >= 0 (no overflow; its
    underflow to 0 is harmless).  Used for |z| >= max(16, (m+1)(m+2)).
    """
    e2 = np.exp(-2.0 * z)
    sgn = np.where(m % 2 == 0, 1.0, -1.0)
    p0, q0 = _bessel_poly_sums(m, z)
    p1, q1 = _bessel_poly_sums(m + 1, z)
    return (q1 + sgn * e2 * p1) / (q0 - sgn * e2 * p0)


def _ratio_i_all(m: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Dispatch i_{m+1}/i_m over the three regimes (tiny, continued fraction, closed form)."""
    out = np.empty(z.shape, dtype=np.complex128)
    az = np.abs(z)
    tiny = az < _Z_TINY
    closed = ~tiny & (az >= np.maximum(_Z_CLOSED_MIN, (m + 1.0) * (m + 2.0)))
    cf = ~tiny & ~closed
    out[tiny] = z[tiny] / (2.0 * m[tiny] + 3.0)
    if closed.any():
        out[closed] = _ratio_i_closed(m[closed], z[closed])
    if cf.any():
        out[cf] = _ratio_i_cf(m[cf], z[cf])
    return out


def _zk_ratio_all(m: np.ndarray, z: np.ndarray) -> np.ndarray:
    """t_m = z k_{m+1}(z)/k_m(z) by forward recurrence (stable: k_m is dominant as m grows).

    t_0 = 1 + z (DLMF 10.49.12: k_1/k_0 = 1 + 1/z), t_n = (2n+1) + z^2 / t_{n-1}
    (DLMF 10.51.4 with g_n = (-1)^n k_n).  k_m has no zeros in Re z >= 0, so t_n != 0.
    z^2/t is formed as z*(z/t) to avoid overflow; at z = 0 it gives t_n = 2n + 1.
    """
    t = 1.0 + z
    mmax = int(m.max()) if m.size else 0
    for n in range(1, mmax + 1):
        act = m >= n
        t = np.where(act, (2.0 * n + 1.0) + z * (z / np.where(act, t, 1.0)), t)
    return t


# ----------------------------------------------------------------------------- public API


def ratio_i(m, z):
    """Return i_{m+1}(z) / i_m(z), ratio of regular modified spherical Bessel functions.

    Parameters: ``m`` integer(s) in [0, M_MAX]; ``z`` complex, Re z >= 0,
    1e-150 <= |z| <= 1e150 or z = 0 (value 0).  Broadcasts; returns complex128 (a numpy
    scalar for scalar inputs).

    Method and identities:

    * |z| < 1e-100: leading term z/(2m+3) of the power series DLMF 10.53.3.
    * |z| < max(16, (m+1)(m+2)): Gauss continued fraction DLMF 10.33.1 for
      I_{m+3/2}/I_{m+1/2} (= i_{m+1}/i_m by DLMF 10.47.7), evaluated by modified Lentz with a
      relative tolerance of one ulp and a cap of 2|z| + 500 terms.
    * otherwise: the terminating expansion DLMF 10.49.8 (coefficients 10.49.1) for i_m and
      i_{m+1}, the common factor e^z/(2z) cancelled, so only e^{-2z} (|.| <= 1) appears.

    Near the imaginary axis i_m(iy) = i^m j_m(y) has zeros, where this ratio has poles; the
    relative error there is bounded by about kappa * eps, kappa = |z d/dz log(ratio)| being
    the condition number (the continued fraction is backward stable in z; the closed form
    is more accurate still because e^{-2z} is evaluated from the exact z).

    Raises ParameterError (ValueError) for invalid m or z.
    """
    mm, zz, shape = _prepare(m, z, allow_zero=True)
    return _finish(_ratio_i_all(mm, zz), zz, shape)


def ratio_k(m, z):
    """Return k_{m+1}(z) / k_m(z), ratio of decaying modified spherical Bessel functions.

    Parameters: ``m`` integer(s) in [0, M_MAX]; ``z`` complex, Re z >= 0,
    1e-150 <= |z| <= 1e150 (z = 0 is a pole, ~ (2m+1)/z).  Broadcasts; returns complex128.

    Method and identities: forward recurrence in m of t_n = z k_{n+1}/k_n,
    t_0 = 1 + z (DLMF 10.49.12, k_0 = (pi/2) e^{-z}/z, k_1 = (pi/2) e^{-z}(1/z + 1/z^2)),
    t_n = (2n+1) + z^2/t_{n-1} (DLMF 10.51.4 with g_n = (-1)^n k_n:
    k_{n+1} = k_{n-1} + ((2n+1)/z) k_n); result t_m / z.  The factor e^{-z} never appears,
    and forward recurrence is stable because k_m is the dominant solution in Re z >= 0.
    Limits: (2m+1)/z as z -> 0 (DLMF 10.52.2); 1 + (m+1)/z + O(z^-2) as z -> inf.

    Raises ParameterError (ValueError) for invalid m or z.
    """
    mm, zz, shape = _prepare(m, z, allow_zero=False)
    return _finish(_zk_ratio_all(mm, zz) / zz, zz, shape)


def ratio_pair(m: int, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(:func:`ratio_i` (m, z), :func:`ratio_k` (m - 1, z)) for a 1-d complex128 ``z`` that the
    caller knows to lie in the domain (Re z >= 0, 1e-150 <= |z| <= 1e150; e.g. the sphere's
    beta = sqrt(s / nu) at Fourier frequencies |s| <= 513 and a validated nu) and an integer
    1 <= m <= M_MAX: the same kernels without the per-call checks of m and z, which cost about
    a third of a fluid-load table (issue 25); the results are still checked finite. Equal to
    the two checked calls bitwise (tests/test_sphere_fluid_cache.py)."""
    degrees = np.full(z.shape, m, dtype=np.int64)
    shape = z.shape
    return (_finish(_ratio_i_all(degrees, z), z, shape),
            _finish(_zk_ratio_all(degrees - 1, z) / z, z, shape))


def logderiv_i(m, z):
    """Return z i_m'(z) / i_m(z), the scaled logarithmic derivative of the regular function.

    Identity: z i_m'/i_m = m + z i_{m+1}/i_m (DLMF 10.51.5, g_m' = g_{m+1} + (m/z) g_m with
    g = i^(1)), the ratio from :func:`ratio_i`.  Equals x j_m'(x)/j_m(x) at x = i z
    (DLMF 10.47.12).  Limits: m + z^2/(2m+3) as z -> 0 (DLMF 10.53.3); z - 1 + O(1/z) as
    z -> inf in |ph z| < pi/2 (DLMF 10.49.8).  z = 0 allowed (value m).

    Raises ParameterError (ValueError) for invalid m or z.
    """
    mm, zz, shape = _prepare(m, z, allow_zero=True)
    return _finish(mm + zz * _ratio_i_all(mm, zz), zz, shape)


def logderiv_k(m, z):
    """Return z k_m'(z) / k_m(z), the scaled logarithmic derivative of the decaying function.

    Identity: z k_m'/k_m = m - z k_{m+1}/k_m (DLMF 10.51.5 with g_m = (-1)^m k_m:
    k_m' = -k_{m+1} + (m/z) k_m), with z k_{m+1}/k_m from the recurrence of :func:`ratio_k`.
    Equals x h^(1)_m'(x)/h^(1)_m(x) at x = i z (DLMF 10.47.14).  Limits: -(m+1) as z -> 0
    (DLMF 10.52.2); -z - 1 + O(1/z) as z -> inf (DLMF 10.49.12).  z = 0 allowed (value -(m+1)).

    Raises ParameterError (ValueError) for invalid m or z.
    """
    mm, zz, shape = _prepare(m, z, allow_zero=True)
    return _finish(mm - _zk_ratio_all(mm, zz), zz, shape)


def spherical_jn_zeros(m: int, z_max: float) -> np.ndarray:
    """The positive zeros z < ``z_max`` of the spherical Bessel function j_m (increasing), to
    rounding: sign changes on a grid of step 1/2 (consecutive zeros of J_{m+1/2}, m >= 0, lie
    at least pi apart), each refined by Brent's method. i_m(beta) vanishes at beta = +- i z."""
    from scipy.optimize import brentq
    from scipy.special import spherical_jn

    m = int(_check_m(m))
    x = np.arange(0.5, float(z_max) + 0.5, 0.5)
    f = spherical_jn(m, x)
    found = [brentq(lambda t: spherical_jn(m, t), a, b, xtol=1e-15, rtol=1e-15)
             for a, b, fa, fb in zip(x[:-1], x[1:], f[:-1], f[1:]) if fa * fb < 0]
    return np.array([z for z in found if z < z_max])
