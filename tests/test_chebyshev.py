"""Chebyshev nodes, differentiation, interpolation, quadrature and maps (discretise/chebyshev.py).

Oracles: exactness on polynomials (the defining property of collocation matrices), closed forms
(Trefethen, Spectral Methods in MATLAB, program cheb: D_00 = (2N^2 + 1)/6; Clenshaw-Curtis weights
of degree 2: 1/3, 4/3, 1/3), and derivatives of elementary functions.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spectralshell.discretise.chebyshev import (barycentric_weights, clenshaw_curtis_weights,
                                                differentiation_matrices, gauss_points,
                                                gauss_weights, interpolation_matrix, linear_map,
                                                lobatto_points, lobatto_weights, parity_fold,
                                                radial_derivatives, reciprocal_map)
from spectralshell.errors import ParameterError


def poly_derivatives(coef, x, order):
    """Values of the polynomial sum coef_k x^k and its first ``order`` derivatives."""
    p = np.polynomial.Polynomial(coef)
    return [p.deriv(k)(x) if k else p(x) for k in range(order + 1)]


def test_points_are_symmetric_and_match_cosines():
    for n in (1, 2, 7, 32):
        x = lobatto_points(n)
        np.testing.assert_allclose(x, np.cos(np.pi * np.arange(n + 1) / n), atol=1e-15)
        assert x[0] == 1.0 and x[-1] == -1.0 and np.array_equal(x, -x[::-1])
        g = gauss_points(n)
        np.testing.assert_allclose(g, np.cos(np.pi * (2 * np.arange(n) + 1) / (2 * n)), atol=1e-15)
        assert np.array_equal(g, -g[::-1])


@pytest.mark.parametrize("nodes,weights", [(lobatto_points, lobatto_weights),
                                           (gauss_points, gauss_weights)])
def test_closed_form_weights_equal_generic_ones(nodes, weights):
    """Berrut-Trefethen (5.4)/(5.5) against the defining product, up to a common factor."""
    for n in (3, 8, 40):
        a, b = weights(n), barycentric_weights(nodes(n))
        np.testing.assert_allclose(a / a[0], b / b[0], rtol=1e-12)


def test_lobatto_first_derivative_corner_entries():
    """cheb (Trefethen 2000): D_00 = -D_NN = (2N^2 + 1)/6."""
    for n in (4, 16, 64):
        D = differentiation_matrices(lobatto_points(n), 1, lobatto_weights(n))[0]
        assert D[0, 0] == pytest.approx((2 * n * n + 1) / 6, rel=1e-13)
        assert D[-1, -1] == pytest.approx(-(2 * n * n + 1) / 6, rel=1e-13)


@settings(max_examples=25, deadline=None)
@given(st.integers(min_value=4, max_value=40),
       st.lists(st.floats(-1, 1), min_size=1, max_size=41),
       st.sampled_from(["lobatto", "gauss"]))
def test_differentiation_exact_on_polynomials(n, coef, kind):
    """D^(k) p = p^(k) at the Chebyshev nodes for every polynomial of degree < number of nodes,
    k <= 4; tolerance eps N^(2k) times the size of p (the known growth of the recursion's
    rounding on Chebyshev nodes; on arbitrary nodes it is set by the spacing instead)."""
    coef = coef[:n]
    x = lobatto_points(n - 1) if kind == "lobatto" else gauss_points(n)
    Ds = differentiation_matrices(x, 4)
    vals = poly_derivatives(coef, x, 4)
    scale = np.sum(np.abs(coef)) + 1e-300
    for k, D in enumerate(Ds, start=1):
        tol = 1e-14 * (x.size ** (2 * k)) * scale + 1e-12
        assert np.max(np.abs(D @ vals[0] - vals[k])) <= tol


def test_differentiation_exact_on_arbitrary_nodes():
    """Barycentric differentiation is exact for polynomials on any distinct nodes: 9 fixed
    random nodes (spacing >= 0.05), degree 8, first and second derivatives."""
    x = np.array([-0.93, -0.71, -0.52, -0.2, -0.05, 0.18, 0.41, 0.66, 0.97])
    coef = list(np.random.default_rng(1).uniform(-1, 1, x.size))
    D1, D2 = differentiation_matrices(x, 2)
    vals = poly_derivatives(coef, x, 2)
    np.testing.assert_allclose(D1 @ vals[0], vals[1], atol=1e-11)
    np.testing.assert_allclose(D2 @ vals[0], vals[2], atol=1e-9)


def test_interpolation_exact_and_hits_nodes():
    n = 12
    x = lobatto_points(n)
    y = np.linspace(-1, 1, 37)
    coef = np.random.default_rng(1).normal(size=n + 1)
    E = interpolation_matrix(x, y, lobatto_weights(n))
    np.testing.assert_allclose(E @ np.polynomial.Polynomial(coef)(x),
                               np.polynomial.Polynomial(coef)(y), atol=1e-12)
    E = interpolation_matrix(x, x[[0, 3]])
    np.testing.assert_array_equal(E, np.eye(n + 1)[[0, 3]])


def test_clenshaw_curtis_weights():
    np.testing.assert_allclose(clenshaw_curtis_weights(2), [1 / 3, 4 / 3, 1 / 3], rtol=1e-14)
    for n in (1, 5, 16, 33):
        w, x = clenshaw_curtis_weights(n), lobatto_points(n)
        for k in range(n + 1):
            exact = 0.0 if k % 2 else 2.0 / (k + 1)
            assert abs(w @ x**k - exact) < 1e-13


@pytest.mark.parametrize("parity", [1, -1])
def test_parity_fold_differentiates_even_and_odd_functions(parity):
    """Folded matrices act on the x > 0 half of a function of known parity exactly as the full
    matrix acts on the whole function (degree-N polynomials of that parity)."""
    n = 21
    x = lobatto_points(n)
    D1, D2 = differentiation_matrices(x, 2, lobatto_weights(n))
    h = (n + 1) // 2
    powers = np.arange(0 if parity == 1 else 1, n + 1, 2)
    coef = np.zeros(n + 1)
    coef[powers] = np.random.default_rng(0).normal(size=powers.size)
    f, f1, f2 = poly_derivatives(coef, x, 2)
    np.testing.assert_allclose(parity_fold(D1, parity) @ f[:h], f1[:h], atol=1e-10)
    np.testing.assert_allclose(parity_fold(D2, parity) @ f[:h], f2[:h], atol=1e-8)
    with pytest.raises(ParameterError, match="shape"):
        parity_fold(np.eye(5), 1)
    with pytest.raises(ParameterError, match="parity"):
        parity_fold(D1, 0)


def test_reciprocal_map_represents_powers_of_one_over_r_exactly():
    """r = 1/xi (scale 1): r^-3 = xi^3 is a cubic, so d^k/dr^k r^-3 = (-3)(-4)...(-2-k) r^(-3-k)
    is exact to rounding at every node, including r = infinity (xi = 0)."""
    n = 12
    x = lobatto_points(n)
    rmap = reciprocal_map(x)
    xi = (1 + x) / 2
    np.testing.assert_allclose(rmap.r_inverse, xi, atol=1e-16)
    d = radial_derivatives(differentiation_matrices(x, 4, lobatto_weights(n)), rmap)
    f = xi**3
    for k in range(1, 5):
        exact = np.prod(-np.arange(3, 3 + k)) * xi ** (3 + k)
        assert np.max(np.abs(d[k - 1] @ f - exact)) < 1e-14 * 10 ** (2 * k)


def test_complex_scaled_map_converges_spectrally():
    """r = 1 + c (1/xi - 1), c = 2 e^{-i pi/3}: r^-2 is rational in xi with its pole off [0, 1],
    so its r-derivatives converge geometrically; n = 48 reaches ~1e-9 (relative)."""
    c = 2 * np.exp(-1j * np.pi / 3)
    n = 48
    x = lobatto_points(n)
    rmap = reciprocal_map(x, scale=c)
    q = rmap.r_inverse
    d1, d2 = radial_derivatives(differentiation_matrices(x, 2, lobatto_weights(n)), rmap)
    f = q**2
    assert np.max(np.abs(d1 @ f + 2 * q**3)) < 1e-9
    assert np.max(np.abs(d2 @ f - 6 * q**4)) < 1e-8


def test_linear_map_chain_rule_on_sine():
    a, b, n = 0.5, 3.0, 30
    x = lobatto_points(n)
    rmap = linear_map(x, a, b)
    r = 1 / rmap.r_inverse
    d = radial_derivatives(differentiation_matrices(x, 4, lobatto_weights(n)), rmap)
    exact = [np.cos(r), -np.sin(r), -np.cos(r), np.sin(r)]
    for k in range(4):
        assert np.max(np.abs(d[k] @ np.sin(r) - exact[k])) < 1e-13 * 10 ** (2 * k + 1)


def test_bad_arguments_raise_parameter_error():
    with pytest.raises(ParameterError, match="n = 0"):
        lobatto_points(0)
    with pytest.raises(ParameterError, match="order"):
        differentiation_matrices(lobatto_points(4), 0)
    with pytest.raises(ParameterError, match="scale"):
        reciprocal_map(lobatto_points(4), scale=0.0)
    with pytest.raises(ParameterError, match="distinct"):
        differentiation_matrices(np.array([0.0, 0.5, 0.5]), 1)
    with pytest.raises(ParameterError, match="r = 0"):
        linear_map(lobatto_points(4), -1.0, 1.0)
