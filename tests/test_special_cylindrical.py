"""Tests of spectralshell.special.cylindrical against mpmath (30 digits) and DLMF identities.

Oracle: ``mpmath.besseli`` / ``mpmath.besselk`` of integer order at ``mp.dps = 30`` (set locally
with ``mpmath.workdps(30)``); the double-precision z is converted exactly to ``mpmath.mpc``, so
oracle and code see the same point. Snippet: ``mpmath.besseli(m + 1, z) / mpmath.besseli(m, z)``.

Tolerance 1e-12 (relative) for the K-quantities, which have no zeros or poles in Re z >= 0, and
1e-12 + 20 cond eps for the I-quantities, cond = |z d/dz log f| (I_m(iy) = i^m J_m(y) has real
zeros, so near the imaginary axis the problem itself is ill conditioned). Observed errors are a
few ulp away from those zeros; truncating a continued fraction or an expansion too early, or a
wrong branch of the Hankel expansion, shows up as 1e-8 or worse.
"""

from __future__ import annotations

import cmath
import math

import mpmath
import numpy as np
import pytest

from spectralshell.errors import ParameterError
import scipy.special as sc

from spectralshell.special.cylindrical import (M_MAX, _hankel_sums, _ratio_i_asymptotic, _ratio_i_cf,
                                               logderiv_i, logderiv_k, ratio_i, ratio_k)

EPS = np.finfo(float).eps
RTOL = 1e-12
FUNCS = {"ratio_i": ratio_i, "ratio_k": ratio_k, "logderiv_i": logderiv_i, "logderiv_k": logderiv_k}

RADII = [1e-150, 1e-8, 1e-2, 0.5, 3.0, 10.0, 100.0, 3e4, 6e5]
PHASES = [0.0, math.pi / 8, math.pi / 4, 0.49 * math.pi, -math.pi / 4]
DEGREES = [0, 1, 2, 5, 20, 60]


def _z(r: float, phase: float) -> complex:
    return complex(cmath.rect(r, phase))


def _oracle(m: int, z: complex) -> dict[str, object]:
    """The four quantities at 30 digits, and condition numbers of the I-quantities.

    ratio_i = I_{m+1}/I_m, ratio_k = K_{m+1}/K_m; logderiv_i = m + z ratio_i, logderiv_k =
    m - z ratio_k (DLMF 10.29.2). With L_m = z I_m'/I_m: cond(ratio_i) = |L_{m+1} - L_m| + 1,
    cond(logderiv_i) = |z ratio_i (1 + L_{m+1} - L_m) / L_m| (0 if L_m = 0).
    """
    with mpmath.workdps(30):
        zm = mpmath.mpc(z)
        i0, i1, i2 = (mpmath.besseli(m + j, zm) for j in range(3))
        k0, k1 = mpmath.besselk(m, zm), mpmath.besselk(m + 1, zm)
        ri, rk = i1 / i0, k1 / k0
        l0, l1 = m + zm * ri, (m + 1) + zm * i2 / i1
        return {"ratio_i": ri, "ratio_k": rk, "logderiv_i": l0, "logderiv_k": m - zm * rk,
                "kappa_ratio_i": abs(l1 - l0) + 1,
                "kappa_logderiv_i": abs(zm * ri * (1 + l1 - l0) / l0) if l0 != 0 else 0}


def _relerr(got: complex, ref) -> float:
    with mpmath.workdps(30):
        return float(abs(mpmath.mpc(complex(got)) - ref) / abs(ref))


def _tol(name: str, ref: dict) -> float:
    return RTOL + 20 * float(ref.get("kappa_" + name, 0)) * EPS


@pytest.fixture(scope="module")
def grid():
    """The required grid and its mpmath oracle values (computed once, a few seconds)."""
    pts = [(m, _z(r, ph)) for r in RADII for ph in PHASES for m in DEGREES]
    return pts, [_oracle(m, z) for m, z in pts]


@pytest.mark.parametrize("name", list(FUNCS))
def test_against_mpmath_on_grid(grid, name):
    """Every function vs mpmath at 30 digits on |z| in {1e-150 .. 6e5}, ph z in {0, pi/8, pi/4,
    0.49 pi, -pi/4}, m in {0 .. 60}, in one vectorised call (which also exercises broadcasting and
    the regime dispatch). (mpmath's besselk is slow for complex |z| ~ 15..50, so the switch at
    |z| = 25 has its own, smaller test.)"""
    pts, refs = grid
    m = np.array([p[0] for p in pts])
    z = np.array([p[1] for p in pts])
    got = FUNCS[name](m, z)
    assert got.dtype == np.complex128 and got.shape == z.shape
    excess = [_relerr(g, ref[name]) / _tol(name, ref) for g, ref in zip(got, refs)]
    worst = int(np.argmax(excess))
    assert excess[worst] <= 1, f"{name}: error {excess[worst]:.3g} x tolerance at m={m[worst]}, z={z[worst]}"


@pytest.mark.parametrize("z", [_z(r, ph) for r in (24.9, 25.1) for ph in (math.pi / 4, 0.49 * math.pi)])
def test_against_mpmath_at_the_switch(z):
    """Both sides of |z| = 25, where K_1/K_0 switches from scipy's kve to the Hankel expansion and
    ratio_i (m <= 4) from the continued fraction to the Hankel expansion."""
    for m in (0, 4):
        ref = _oracle(m, z)
        for name in FUNCS:
            assert _relerr(FUNCS[name](m, z), ref[name]) <= _tol(name, ref), (name, m, z)


@pytest.mark.parametrize("y", [1e-120, 0.5, 3.0, 30.0, 300.0, 3e4, 6e5])
def test_imaginary_axis(y):
    """Re z = 0 (beta on the branch cut of sqrt(s/nu), s < 0) vs mpmath, both signs of Im z; the
    Hankel expansion needs its e^{-2z} term here (DLMF 10.40.5)."""
    for z in (complex(0.0, y), complex(0.0, -y)):
        for m in DEGREES:
            ref = _oracle(m, z)
            for name in FUNCS:
                assert _relerr(FUNCS[name](m, z), ref[name]) <= _tol(name, ref), (name, m, z)


@pytest.mark.parametrize("z", [1e-150, 1e-3 * cmath.exp(1.2j), 3.0, 150 * cmath.exp(0.3j), 1e3j,
                               4e4 * cmath.exp(-0.7j), 5e4j, 6e5])
def test_largest_order(z):
    """m = M_MAX = 200, including the longest continued fractions (|z| just below (m+1)^2, where
    the Hankel expansion takes over) and the imaginary axis."""
    ref = _oracle(M_MAX, z)
    for name in FUNCS:
        assert _relerr(FUNCS[name](M_MAX, z), ref[name]) <= _tol(name, ref), (name, z)


@pytest.mark.parametrize("m", [0, 1, 2, 5, 20, 60, M_MAX])
@pytest.mark.parametrize("r", [1e-150, 1e-120, 1e-9])
@pytest.mark.parametrize("ph", [0.0, math.pi / 4, -math.pi / 3, math.pi / 2])
def test_small_z_limits(m, r, ph):
    """z -> 0 against DLMF 10.30.1-10.30.3: I_m ~ (z/2)^m/m!, so ratio_i ~ z/(2(m+1)) (relative
    correction O(z^2)); K_m ~ (1/2)(m-1)! (2/z)^m for m >= 1, so ratio_k ~ 2m/z, and
    K_1/K_0 ~ 1/(z(-log(z/2) - gamma_E)) for m = 0 (corrections O(z^2 log z))."""
    z = _z(r, ph)
    tol = 10 * r + 8 * EPS
    assert abs(ratio_i(m, z) / (z / (2 * (m + 1))) - 1) <= tol
    lead = 1 / (z * (-cmath.log(z / 2) - np.euler_gamma)) if m == 0 else 2 * m / z
    assert abs(ratio_k(m, z) / lead - 1) <= tol
    assert abs(logderiv_i(m, z) - m) <= tol * max(m, 1)


@pytest.mark.parametrize("m", [0, 1, 5, 20, 60])
@pytest.mark.parametrize("r", [1e6, 1e10, 1e150])
@pytest.mark.parametrize("ph", [0.0, math.pi / 4, -math.pi / 4, 0.49 * math.pi])
def test_large_z_limits(m, r, ph):
    """|z| -> inf: DLMF 10.40.1-10.40.2 give I_{m+1}/I_m = 1 - (2m+1)/(2z) + O(z^-2) and
    K_{m+1}/K_m = 1 + (2m+1)/(2z) + O(z^-2) (|ph z| < pi/2); O(z^-2) coefficients below
    (m+1)^2 set the tolerance."""
    z = _z(r, ph)
    tol = 4 * (m + 1) ** 2 / r**2 + 8 * EPS
    assert abs(ratio_i(m, z) / (1 - (2 * m + 1) / (2 * z)) - 1) <= tol
    assert abs(ratio_k(m, z) / (1 + (2 * m + 1) / (2 * z)) - 1) <= tol
    assert abs(logderiv_k(m, z) / (-z - 0.5) - 1) <= tol


RECUR_Z = [_z(r, ph) for r in (1e-6, 0.3, 4.0, 24.9, 25.1, 55.0, 900.0, 5e3, 2e5)
           for ph in (0.0, 0.6, -1.2, 1.56)]


@pytest.mark.parametrize("m", [1, 2, 4, 5, 30, 60, 61])
def test_recurrence_identities(m):
    """DLMF 10.29.1 ties consecutive orders together across all regimes:
    1/ratio_i(m-1) - ratio_i(m) = 2m/z and ratio_k(m) - 1/ratio_k(m-1) = 2m/z, each relative to
    the sum of the moduli of its terms (they cancel for large |z|)."""
    z = np.array(RECUR_Z)
    ri0, ri1 = ratio_i(m - 1, z), ratio_i(m, z)
    rk0, rk1 = ratio_k(m - 1, z), ratio_k(m, z)
    c = 2 * m / z
    assert np.all(abs(1 / ri0 - ri1 - c) <= 1e-13 * (abs(1 / ri0) + abs(ri1) + abs(c)))
    assert np.all(abs(rk1 - 1 / rk0 - c) <= 1e-13 * (abs(rk1) + abs(1 / rk0) + abs(c)))
    np.testing.assert_allclose(logderiv_i(m, z), m + z * ri1, rtol=1e-15)
    np.testing.assert_allclose(logderiv_k(m, z), m - z * rk1, rtol=1e-15)


@pytest.mark.parametrize("m", [0, 3, 4, 10])
def test_regimes_agree_at_the_switch(m):
    """ratio_i switches from the continued fraction to the Hankel expansion at |z| = max(25,
    (m+1)^2), and K_1/K_0 from scipy's kve to the Hankel expansion at |z| = 25. At the switch both
    methods, evaluated at the same z (white box: the private kernels), agree to 1e-12 (the
    continued fraction's backward error grows like eps |z|, |z| <= 121 here)."""
    r0 = max(25.0, (m + 1.0) ** 2)
    z = np.array([_z(r0, ph) for ph in (0.0, 0.7, 1.5, math.pi / 2, -math.pi / 2)])
    mm = np.full(z.shape, m)
    cf, asym = _ratio_i_cf(mm, z), _ratio_i_asymptotic(mm, z)
    assert np.all(abs(cf - asym) <= 1e-12 * abs(asym))
    z25 = np.array([_z(25.0, ph) for ph in (0.0, 0.7, 1.5, math.pi / 2, -math.pi / 2)])
    p1, _ = _hankel_sums(np.ones(5, dtype=np.int64), z25)
    p0, _ = _hankel_sums(np.zeros(5, dtype=np.int64), z25)
    amos = sc.kve(1, z25) / sc.kve(0, z25)
    assert np.all(abs(p1 / p0 - amos) <= 1e-14 * abs(amos))


@pytest.mark.parametrize("m", [0, 2, 7])
@pytest.mark.parametrize("z", [0.5, 3j, 30 * cmath.exp(0.4j), 7 * cmath.exp(-1.1j)])
def test_mapping_to_thesis_j_and_h(m, z):
    """The docstring's translation to the thesis's J_m(i z), H_m(i z) = H^(1)_m(i z) (DLMF 10.27.6,
    10.27.8). Oracle: mpmath besselj, hankel1 at x = i z (60 digits: H^(1)(x) = J + iY cancels
    where it is exponentially small). Claimed:
    J_{m+1}(x)/J_m(x) = i ratio_i(m, z), H_{m+1}(x)/H_m(x) = -i ratio_k(m, z)."""
    with mpmath.workdps(60):
        x = 1j * mpmath.mpc(z)
        rj = mpmath.besselj(m + 1, x) / mpmath.besselj(m, x)
        rh = mpmath.hankel1(m + 1, x) / mpmath.hankel1(m, x)
    assert _relerr(1j * ratio_i(m, z), rj) <= RTOL
    assert _relerr(-1j * ratio_k(m, z), rh) <= RTOL


EXTREME_Z = [1e-150, 1e-120, 1e-8j, 1e-150j, 3e-9 * cmath.exp(0.7j), 1.0, 1e3j, 6e5, 6e5j,
             6e5 * cmath.exp(-0.78j), 4.0e4j, 1e150, 1e150j, -1e150j, 1e150 * cmath.exp(0.5j)]


@pytest.mark.parametrize("name", list(FUNCS))
def test_finite_for_extreme_inputs(name):
    """No overflow or underflow to inf/NaN anywhere on the domain, m up to M_MAX."""
    m = np.array([0, 1, 60, 61, M_MAX])[:, None]
    z = np.array(EXTREME_Z + ([0j] if name in ("ratio_i", "logderiv_i") else []))[None, :]
    out = FUNCS[name](m, z)
    assert out.shape == (m.size, z.size) and np.all(np.isfinite(out))


def test_zero_argument():
    """ratio_i(m, 0) = 0 and logderiv_i(m, 0) = m are the limits; K_m has a pole at 0."""
    m = np.arange(0, 62)
    assert np.all(ratio_i(m, 0) == 0) and np.all(logderiv_i(m, 0) == m)
    for f in (ratio_k, logderiv_k):
        with pytest.raises(ParameterError, match=r"^z = 0j is invalid"):
            f(3, 0)


INVALID = [("m", -1, 1.0), ("m", 2.5, 1.0), ("m", True, 1.0), ("m", M_MAX + 1, 1.0), ("m", float("nan"), 1.0),
           ("z", 1, float("nan")), ("z", 1, complex(float("inf"), 0.0)), ("z", 1, -1.0 + 2.0j),
           ("z", 1, 1e-200), ("z", 1, 1e200j), ("z", 1, "beta")]


@pytest.mark.parametrize("name", list(FUNCS))
@pytest.mark.parametrize("param, m, z", INVALID)
def test_invalid_input(name, param, m, z):
    """Invalid m or z raise ParameterError (a ValueError) "<param> = <value> is invalid: must be ..."."""
    with pytest.raises(ParameterError, match=rf"^{param} = .* is invalid: must be "):
        FUNCS[name](m, z)


def test_scalar_in_scalar_out():
    for f in FUNCS.values():
        assert isinstance(f(2, 1.5), np.complex128)
        assert f(np.arange(4)[:, None], np.array([0.5, 2j, 30.0])).shape == (4, 3)


@pytest.mark.parametrize("m", [0, 1, 3, 10])
@pytest.mark.parametrize("z", [-0.01 + 0.5j, -1 + 3j, -2 - 5j, -0.3 + 20j, 2 + 1j])
def test_logderiv_k_continued_against_mpmath(m, z):
    """z K_m'/K_m continued across the imaginary axis equals mpmath's principal branch (cut on the
    negative real axis: the continuation from above for Im z > 0, from below for Im z < 0)."""
    from spectralshell.special.cylindrical import logderiv_k_continued

    with mpmath.workdps(30):
        b = mpmath.mpc(z)
        want = complex(b * mpmath.diff(lambda x: mpmath.besselk(m, x), b) / mpmath.besselk(m, b))
    assert abs(logderiv_k_continued(m, z) - want) <= 1e-13 * abs(want)
