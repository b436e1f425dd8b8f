"""Tests of spectralshell.special.spherical against mpmath (40 digits) and DLMF identities.

Oracle: i_m(z) = sqrt(pi/(2z)) I_{m+1/2}(z), k_m(z) = sqrt(pi/(2z)) K_{m+1/2}(z) (DLMF 10.47.7,
10.47.9), evaluated with ``mpmath.besseli`` / ``mpmath.besselk`` at ``mp.dps = 40`` (set locally
with ``mpmath.workdps(40)``); the prefactor cancels in every ratio, so the oracle ratios are
I_{m+3/2}/I_{m+1/2} and K_{m+3/2}/K_{m+1/2}.  The double-precision z is converted exactly to
``mpmath.mpc``, so oracle and code see the same point.

Tolerance 1e-12 (relative): on the required grid (|ph z| <= 0.49 pi) all four quantities are
well conditioned (condition number |z d/dz log f| <= ~1e3), so a backward-stable double
algorithm should reach ~1e-14; the observed worst case is ~5e-15.  1e-12 leaves a factor ~200
for platform libm differences, while any cancellation, premature truncation of the continued
fraction or wrong branch of the closed form shows up as errors of 1e-8 or worse.
"""

from __future__ import annotations

import cmath
import math

import mpmath
import numpy as np
import pytest

from spectralshell.errors import ParameterError
from spectralshell.special.spherical import (
    M_MAX,
    logderiv_i,
    logderiv_k,
    ratio_i,
    ratio_k,
)

EPS = np.finfo(float).eps
RTOL = 1e-12

RADII = [1e-8, 1e-5, 1e-2, 0.5, 3.0, 30.0, 300.0, 3e4, 6e5]
PHASES = [0.0, math.pi / 8, math.pi / 4, 0.49 * math.pi, -math.pi / 4]
DEGREES = [0, 1, 2, 5, 20, 60]
FUNCS = {"ratio_i": ratio_i, "ratio_k": ratio_k, "logderiv_i": logderiv_i, "logderiv_k": logderiv_k}


def _z(r: float, phase: float) -> complex:
    return complex(cmath.rect(r, phase))


def _oracle(m: int, z: complex) -> dict[str, mpmath.mpc]:
    """mpmath (40 digits): the four quantities, and the condition numbers of the i-quantities.

    ratio_i = I_{m+3/2}/I_{m+1/2}, ratio_k = K_{m+3/2}/K_{m+1/2} (DLMF 10.47.7, 10.47.9);
    logderiv_i = m + z ratio_i, logderiv_k = m - z ratio_k (DLMF 10.51.5).  Condition numbers
    kappa = |z d/dz log f| via L_m = z i_m'/i_m:  kappa(ratio_i) = |L_{m+1} - L_m|,
    kappa(logderiv_i) = |z ratio_i (1 + L_{m+1} - L_m) / L_m|.
    """
    with mpmath.workdps(40):
        zm = mpmath.mpc(z)
        i0, i1, i2 = (mpmath.besseli(m + 0.5 + j, zm) for j in range(3))
        k0, k1 = mpmath.besselk(m + 0.5, zm), mpmath.besselk(m + 1.5, zm)
        ri, rk = i1 / i0, k1 / k0
        l0, l1 = m + zm * ri, (m + 1) + zm * i2 / i1
        return {
            "ratio_i": ri,
            "ratio_k": rk,
            "logderiv_i": l0,
            "logderiv_k": m - zm * rk,
            "kappa_ratio_i": abs(l1 - l0),
            "kappa_logderiv_i": abs(zm * ri * (1 + l1 - l0) / l0),
        }


def _relerr(got: complex, ref: mpmath.mpc) -> float:
    with mpmath.workdps(40):
        return float(abs(mpmath.mpc(complex(got)) - ref) / abs(ref))


@pytest.fixture(scope="module")
def grid():
    """The required grid and its mpmath oracle values (computed once, ~1 s)."""
    pts = [(m, _z(r, ph)) for r in RADII for ph in PHASES for m in DEGREES]
    return pts, [_oracle(m, z) for m, z in pts]


@pytest.mark.parametrize("name", list(FUNCS))
def test_against_mpmath_on_grid(grid, name):
    """Every function vs mpmath 40-digit besseli/besselk ratios on the required grid.

    Oracle: mpmath.besseli(m+1.5, z)/mpmath.besseli(m+0.5, z) etc. (see module docstring);
    |z| in {1e-8 .. 6e5}, ph z in {0, pi/8, pi/4, 0.49 pi, -pi/4}, m in {0,1,2,5,20,60}.
    Evaluated in one vectorised call, which also exercises broadcasting.
    """
    pts, refs = grid
    m = np.array([p[0] for p in pts])
    z = np.array([p[1] for p in pts])
    got = FUNCS[name](m, z)
    assert got.dtype == np.complex128 and got.shape == z.shape
    errs = [_relerr(g, ref[name]) for g, ref in zip(got, refs)]
    worst = int(np.argmax(errs))
    msg = f"{name}: rel. error {errs[worst]:.3g} at m={m[worst]}, z={z[worst]}"
    assert errs[worst] <= RTOL, msg


@pytest.mark.parametrize("y", [0.5, 3.0, 30.0, 300.0, 3e4, 6e5])
def test_imaginary_axis_within_conditioning(y):
    """On Re z = 0 (beta for n = 0, gamma < 0) vs mpmath, error bounded by the conditioning.

    Oracle: as in the grid test, at z = i y.  There i_m(iy) = i^m j_m(y) (DLMF 10.47.12) has
    real zeros, so ratio_i and logderiv_i have poles nearby and relative errors up to about
    kappa * eps (kappa = |z d/dz log f|) are intrinsic; the k-quantities have no zeros or poles
    (k_m has none in Re z >= 0) and must meet the plain 1e-12.
    """
    z = complex(0.0, y)
    for m in DEGREES:
        ref = _oracle(m, z)
        for name in ("ratio_k", "logderiv_k"):
            assert _relerr(FUNCS[name](m, z), ref[name]) <= RTOL, (name, m, z)
        for name in ("ratio_i", "logderiv_i"):
            tol = RTOL + 20 * float(ref["kappa_" + name]) * EPS
            assert _relerr(FUNCS[name](m, z), ref[name]) <= tol, (name, m, z)


@pytest.mark.parametrize(
    "m, z",
    [(M_MAX, 0.99 * (M_MAX + 1) * (M_MAX + 2) * 1j), (M_MAX, 5e3 * cmath.exp(0.3j)), (61, 3.8e3j)],
)
def test_longest_continued_fractions(m, z):
    """Worst cases of the continued fraction (|z| just below (m+1)(m+2), near Re z = 0) vs mpmath.

    Oracle: mpmath besseli/besselk ratios at 40 digits; tolerance as in the imaginary-axis test.
    """
    ref = _oracle(m, z)
    for name in FUNCS:
        tol = RTOL + 20 * float(ref.get("kappa_" + name, 0)) * EPS
        assert _relerr(FUNCS[name](m, z), ref[name]) <= tol, (name, m, z)


def test_elementary_closed_forms():
    """m = 0, 1 against the elementary forms of DLMF 10.49.9 and 10.49.13, in mpmath.

    i_0 = sinh z/z, i_1 = (z cosh z - sinh z)/z^2, i_2 = ((z^2+3) sinh z - 3z cosh z)/z^3,
    k_0 = (pi/2) e^{-z}/z, k_1 = (pi/2) e^{-z}(1/z + 1/z^2),
    k_2 = (pi/2) e^{-z}(1/z + 3/z^2 + 3/z^3).
    """
    for r in (0.1, 1.0, 7.0, 40.0):
        for ph in (0.0, 0.3, -0.7, 1.5):
            z = _z(r, ph)
            with mpmath.workdps(40):
                w = mpmath.mpc(z)
                s, c = mpmath.sinh(w), mpmath.cosh(w)
                i0, i1 = s / w, (w * c - s) / w**2
                i2 = ((w**2 + 3) * s - 3 * w * c) / w**3
                refs = {
                    ("ratio_i", 0): i1 / i0,
                    ("ratio_i", 1): i2 / i1,
                    ("ratio_k", 0): 1 + 1 / w,
                    ("ratio_k", 1): (1 / w + 3 / w**2 + 3 / w**3) / (1 / w + 1 / w**2),
                }
            for (name, m), ref in refs.items():
                assert _relerr(FUNCS[name](m, z), ref) <= RTOL, (name, m, z)


EXTREME_Z = [1e-150, 1e-120, 1e-8j, 1e-150j, 3e-9 * cmath.exp(0.7j), 1.0, 1e3j, 6e5, 6e5j,
             6e5 * cmath.exp(-0.78j), 1e6j, 4.0e4j, 1e150, 1e150j, 1e150 * cmath.exp(0.5j)]


@pytest.mark.parametrize("name", list(FUNCS))
def test_finite_for_extreme_inputs(name):
    """No overflow/underflow to inf/NaN at the edges of the domain (m up to M_MAX).

    Oracle: none needed -- the outputs must simply be finite (numpy.isfinite) and, where the
    limit z -> 0 is finite, z = 0 itself must be accepted.
    """
    m = np.array([0, 1, 60, 61, M_MAX])[:, None]
    z = np.array(EXTREME_Z + ([0j] if name != "ratio_k" else []))[None, :]
    out = FUNCS[name](m, z)
    assert out.shape == (m.size, z.size)
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("m", [0, 1, 2, 5, 20, 60, M_MAX])
@pytest.mark.parametrize("r", [1e-120, 1e-9])
@pytest.mark.parametrize("ph", [0.0, math.pi / 4, -math.pi / 3, math.pi / 2])
def test_small_z_limits(m, r, ph):
    """z -> 0 against the limiting forms DLMF 10.52.1 and 10.52.2.

    i_m ~ z^m/(2m+1)!!, (2/pi) k_m ~ (2m-1)!!/z^{m+1}, hence ratio_i ~ z/(2m+3),
    ratio_k ~ (2m+1)/z, logderiv_i -> m, logderiv_k -> -(m+1); the relative corrections are
    O(|z|) (O(|z|) only for ratio_k with m = 0, where ratio_k = 1 + 1/z exactly; else O(|z|^2)).
    """
    z = _z(r, ph)
    tol = 4 * r + 4 * EPS
    assert abs(ratio_i(m, z) / (z / (2 * m + 3)) - 1) <= tol
    assert abs(ratio_k(m, z) / ((2 * m + 1) / z) - 1) <= tol
    assert abs(logderiv_i(m, z) - m) <= tol * max(m, 1)
    assert abs(logderiv_k(m, z) + (m + 1)) <= tol * (m + 1)


def test_zero_argument_values():
    """Values at z = 0 are the limits of DLMF 10.52.1-10.52.2; ratio_k has a pole there."""
    m = np.arange(0, 62)
    assert np.all(ratio_i(m, 0) == 0)
    assert np.all(logderiv_i(m, 0) == m)
    assert np.all(logderiv_k(m, 0) == -(m + 1))
    with pytest.raises(ParameterError, match=r"^z = 0j is invalid"):
        ratio_k(3, 0)


@pytest.mark.parametrize("m", [0, 1, 5, 20, 60])
@pytest.mark.parametrize("r", [1e6, 1e8, 1e12])
@pytest.mark.parametrize("ph", [0.0, math.pi / 4, -math.pi / 4, 0.49 * math.pi])
def test_large_z_limits(m, r, ph):
    """|z| -> inf against the leading terms of DLMF 10.49.8 and 10.49.12.

    i_m ~ (e^z/(2z))(1 - a_1/z + ...), k_m ~ (pi/2)(e^{-z}/z)(1 + a_1/z + ...), a_1 = m(m+1)/2
    (DLMF 10.49.1), hence ratio_i = 1 - (m+1)/z + O(z^-2), ratio_k = 1 + (m+1)/z + O(z^-2),
    logderiv_i = z - 1 + O(1/z), logderiv_k = -z - 1 + O(1/z).  The O(z^-2) coefficients are
    below (m+1)^2 in modulus, which sets the tolerance.
    """
    z = _z(r, ph)
    tol = 4 * (m + 1) ** 2 / r**2 + 8 * EPS
    assert abs(ratio_i(m, z) / (1 - (m + 1) / z) - 1) <= tol
    assert abs(ratio_k(m, z) / (1 + (m + 1) / z) - 1) <= tol
    assert abs(logderiv_i(m, z) / (z - 1) - 1) <= tol
    assert abs(logderiv_k(m, z) / (-z - 1) - 1) <= tol


RECUR_Z = [
    _z(r, ph) for r in (1e-6, 0.3, 4.0, 55.0, 900.0, 5e3, 2e5) for ph in (0.0, 0.6, -1.2, 1.56)
]


@pytest.mark.parametrize("m", [1, 2, 7, 30, 60, 61])
def test_recurrence_identities(m):
    """DLMF 10.51.4-10.51.5 tie consecutive degrees together.

    With g_n = i_n or (-1)^n k_n:  g_{m-1} - g_{m+1} = ((2m+1)/z) g_m (10.51.4) gives
      1/ratio_i(m-1) - ratio_i(m) = (2m+1)/z,   ratio_k(m) - 1/ratio_k(m-1) = (2m+1)/z;
    g_m' = g_{m-1} - ((m+1)/z) g_m (10.51.5, first form) gives
      logderiv_i(m) = z/ratio_i(m-1) - (m+1),   logderiv_k(m) = -z/ratio_k(m-1) - (m+1),
    while the code uses the second form of 10.51.5 (g_m' = g_{m+1} + (m/z) g_m).  Each check is
    relative to the sum of the moduli of its terms (the identities cancel for large |z|).
    """
    z = np.array(RECUR_Z)
    ri0, ri1 = ratio_i(m - 1, z), ratio_i(m, z)
    rk0, rk1 = ratio_k(m - 1, z), ratio_k(m, z)
    c = (2 * m + 1) / z
    tol = 1e-13
    assert np.all(abs(1 / ri0 - ri1 - c) <= tol * (abs(1 / ri0) + abs(ri1) + abs(c)))
    assert np.all(abs(rk1 - 1 / rk0 - c) <= tol * (abs(rk1) + abs(1 / rk0) + abs(c)))
    li, lk = logderiv_i(m, z), logderiv_k(m, z)
    assert np.all(abs(li - (z / ri0 - (m + 1))) <= tol * (abs(li) + abs(z / ri0) + m + 1))
    assert np.all(abs(lk - (-z / rk0 - (m + 1))) <= tol * (abs(lk) + abs(z / rk0) + m + 1))
    assert np.allclose(li, m + z * ri1, rtol=1e-15, atol=0)
    assert np.allclose(lk, m - z * rk1, rtol=1e-15, atol=0)


@pytest.mark.parametrize("m", [0, 3, 20])
@pytest.mark.parametrize("z", [0.5, 3j, 30 * cmath.exp(0.4j), 7 * cmath.exp(-1.1j)])
def test_mapping_to_thesis_j_and_h(m, z):
    """The docstring's translation to j_m(i z) and h^(1)_m(i z) (DLMF 10.47.12, 10.47.14).

    Oracle (mpmath, 40 digits), x = i z: j_n(x) = sqrt(pi/(2x)) besselj(n+1/2, x),
    h^(1)_n(x) = sqrt(pi/(2x)) hankel1(n+1/2, x) (DLMF 10.47.3, 10.47.5), and
    x f_m'(x)/f_m(x) = m - x f_{m+1}(x)/f_m(x) (DLMF 10.51.2), for f = j, h^(1).
    Claimed: j_{m+1}/j_m = i ratio_i, h_{m+1}/h_m = -i ratio_k, x j'/j = logderiv_i,
    x h'/h = logderiv_k.
    """
    with mpmath.workdps(40):
        x = 1j * mpmath.mpc(z)
        rj = mpmath.besselj(m + 1.5, x) / mpmath.besselj(m + 0.5, x)
        rh = mpmath.hankel1(m + 1.5, x) / mpmath.hankel1(m + 0.5, x)
        refs = {
            "ratio_i": -1j * rj,
            "ratio_k": 1j * rh,
            "logderiv_i": m - x * rj,
            "logderiv_k": m - x * rh,
        }
    for name, ref in refs.items():
        assert _relerr(FUNCS[name](m, z), ref) <= RTOL, (name, m, z)


def test_scalar_in_scalar_out_and_broadcasting():
    """Scalars give numpy complex scalars; (M,1) x (N,) broadcasts to (M,N) (numpy semantics)."""
    for f in FUNCS.values():
        out = f(2, 1.5)
        assert isinstance(out, np.complex128)
        assert f(np.arange(4)[:, None], np.array([0.5, 2j, 30.0])).shape == (4, 3)
    assert ratio_i(2.0, 1.5) == ratio_i(2, 1.5)  # integral floats are accepted as m


INVALID = [
    ("m", -1, 1.0),
    ("m", 2.5, 1.0),
    ("m", np.array([1, 2, 3.5]), 1.0),
    ("m", True, 1.0),
    ("m", M_MAX + 1, 1.0),
    ("m", float("nan"), 1.0),
    ("m", "three", 1.0),
    ("z", 1, float("nan")),
    ("z", 1, complex(1.0, float("nan"))),
    ("z", 1, complex(float("inf"), 0.0)),
    ("z", 1, -1.0 + 2.0j),
    ("z", 1, np.array([1.0, -0.5])),
    ("z", 1, 1e-200),
    ("z", 1, 1e200j),
    ("z", 1, "beta"),
    ("z", np.arange(2), np.ones(3)),
]


@pytest.mark.parametrize("name", list(FUNCS))
@pytest.mark.parametrize("param, m, z", INVALID)
def test_invalid_input_raises_value_error_naming_parameter(name, param, m, z):
    """Invalid m or z raise ParameterError (a ValueError): "<param> = <value> is invalid: ...".

    Oracle: the message format of spectralshell._validate / spectralshell.errors.
    """
    with pytest.raises(ValueError, match=rf"^{param} = .* is invalid: must be ") as info:
        FUNCS[name](m, z)
    assert isinstance(info.value, ParameterError)


def test_compiled_continued_fraction_against_mpmath_and_its_failure_path():
    """The compiled Lentz kernel behind both Bessel modules (``special/_lentz.c``), called
    directly on one array of mixed orders (integer: the fibre's I_{m+1}/I_m; half-integer: the
    sphere's) and arguments from |z| = 1e-3 to 3000, near the imaginary axis included, against
    mpmath besseli ratios at 30 digits; a non-finite z is reported as a ParameterError naming z."""
    from spectralshell.special.spherical import ratio_i_continued_fraction

    rng = np.random.default_rng(7)
    order = np.concatenate([rng.integers(0, 61, 40).astype(float), rng.integers(0, 61, 40) + 0.5])
    z = 10.0 ** rng.uniform(-3, np.log10(3000), 80) * np.exp(1j * rng.uniform(-0.49, 0.49, 80) * np.pi)
    got = ratio_i_continued_fraction(order, z, "test")
    with mpmath.workdps(30):
        for nu, x, value in zip(order, z, got):
            ref = mpmath.besseli(nu + 1, mpmath.mpc(x)) / mpmath.besseli(nu, mpmath.mpc(x))
            # condition of the ratio: |z d/dz log ratio| <= |z| + 2 nu + 2 (DLMF 10.29.2)
            tol = 1e-14 * (abs(x) + 2 * nu + 2)
            assert float(abs(mpmath.mpc(complex(value)) - ref) / abs(ref)) <= tol, (nu, x)
    with pytest.raises(ParameterError, match=r"^z = .* is invalid: .*continued fraction for test"):
        ratio_i_continued_fraction(np.array([0.5, 0.5]), np.array([1.0, np.inf + 0j]), "test")
