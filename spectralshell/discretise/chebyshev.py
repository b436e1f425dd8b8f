"""Chebyshev collocation on one interval: nodes, differentiation, interpolation, quadrature, maps.

Conventions (the one module that owns them)
-------------------------------------------
* Gauss-Lobatto nodes ``x_j = cos(pi j / n)``, j = 0..n, run from +1 down to -1 (so ``x_0 = 1``);
  Gauss nodes ``x_j = cos(pi (2j + 1) / (2n))``, j = 0..n-1, likewise descending. Both are
  computed as sines so that ``x_{n-j} = -x_j`` holds exactly in floating point.
* A function is represented by its values at the nodes (the interpolating polynomial of degree
  n for Lobatto). Derivatives are exact for that polynomial: D^(k) f is the k-th derivative of the
  interpolant, evaluated at the nodes.
* A map carries the computational coordinate x in [-1, 1] to a physical coordinate r. It is given
  by ``1/r`` at the nodes (finite even where r is infinite) and by the first four derivatives of
  x(r), from which the chain rule (Faa di Bruno) builds d^k/dr^k = sum_j c_kj(x) D^(j).

Differentiation matrices use the barycentric recursion of Welfert (1997) / Weideman and Reddy
(2000, ACM TOMS 26, "poldif"),

    D^(k)_ij = (k / (x_i - x_j)) ((w_j / w_i) D^(k-1)_ii - D^(k-1)_ij),   i != j,
    D^(k)_ii = -sum_{j != i} D^(k)_ij                                      (rows kill constants),

with D^(0) = I and barycentric weights w_j = 1 / prod_{k != j} (x_j - x_k). For Chebyshev points
the weights have closed forms (Berrut and Trefethen 2004, SIAM Rev. 46, (5.4) and (5.5)):
Lobatto w_j = (-1)^j delta_j (delta = 1/2 at both ends, 1 elsewhere), Gauss
w_j = (-1)^j sin((2j + 1) pi / (2n)); any common factor cancels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sparse

from .._validate import require_int_in_range
from ..errors import ParameterError

__all__ = ["RadialMap", "lobatto_points", "gauss_points", "lobatto_weights", "gauss_weights",
           "barycentric_weights", "differentiation_matrices", "interpolation_matrix",
           "clenshaw_curtis_weights", "parity_fold", "linear_map", "reciprocal_map",
           "radial_derivatives", "ball_derivatives", "exterior_derivatives",
           "ultraspherical_derivative", "ultraspherical_conversion",
           "ultraspherical_multiplication", "chebyshev_boundary_rows"]


def lobatto_points(n: int) -> np.ndarray:
    """Chebyshev-Gauss-Lobatto points x_j = cos(pi j / n), j = 0..n (descending, x_0 = 1)."""
    n = require_int_in_range("n", n, 1)
    return np.sin(np.pi * (n - 2 * np.arange(n + 1)) / (2 * n))


def gauss_points(n: int) -> np.ndarray:
    """Chebyshev-Gauss points x_j = cos(pi (2j + 1) / (2n)), j = 0..n-1 (descending)."""
    n = require_int_in_range("n", n, 1)
    return np.sin(np.pi * (n - 1 - 2 * np.arange(n)) / (2 * n))


def lobatto_weights(n: int) -> np.ndarray:
    """Barycentric weights of the Lobatto points: (-1)^j, halved at j = 0 and j = n."""
    n = require_int_in_range("n", n, 1)
    w = (-1.0) ** np.arange(n + 1)
    w[[0, -1]] *= 0.5
    return w


def gauss_weights(n: int) -> np.ndarray:
    """Barycentric weights of the Gauss points: (-1)^j sin((2j + 1) pi / (2n))."""
    n = require_int_in_range("n", n, 1)
    j = np.arange(n)
    return (-1.0) ** j * np.sin((2 * j + 1) * np.pi / (2 * n))


def _distinct_nodes(x) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)) or np.min(np.diff(np.sort(x))) <= 0:
        raise ParameterError(f"x = {x!r} is invalid: must be at least two distinct finite nodes")
    return x


def barycentric_weights(x: np.ndarray) -> np.ndarray:
    """Barycentric weights w_j = 1 / prod_{k != j} (x_j - x_k) of arbitrary distinct nodes.

    Each factor is scaled by 4 / (max x - min x) (the logarithmic capacity of the interval) so
    the product neither overflows nor underflows for a few hundred nodes; the result is then
    normalised to max |w| = 1 (a common factor cancels in every barycentric formula).
    """
    x = _distinct_nodes(x)
    diff = x[:, None] - x[None, :]
    np.fill_diagonal(diff, 1.0)
    scale = 4.0 / (x.max() - x.min())
    w = 1.0 / np.prod(diff * scale, axis=1)
    return w / np.max(np.abs(w))


def differentiation_matrices(x: np.ndarray, order: int, weights: np.ndarray | None = None
                             ) -> list[np.ndarray]:
    """Matrices [D^(1), ..., D^(order)] of exact polynomial differentiation on the nodes x.

    Notes
    -----
    Welfert's recursion quoted in the module docstring; the diagonal is the negative row sum,
    which makes every D^(k) annihilate constants to rounding and keeps the error of D^(k)
    near eps N^(2k) (Baltensperger and Trummer 2003, SIAM J. Sci. Comput. 24).
    """
    x = _distinct_nodes(x)
    order = require_int_in_range("order", order, 1)
    w = barycentric_weights(x) if weights is None else np.asarray(weights, dtype=float)
    n = x.size
    dx = x[:, None] - x[None, :]
    off = ~np.eye(n, dtype=bool)
    inv_dx = np.zeros_like(dx)
    inv_dx[off] = 1.0 / dx[off]
    ratio = w[None, :] / w[:, None]
    out = []
    prev = np.eye(n)
    for k in range(1, order + 1):
        d = k * inv_dx * (ratio * np.diag(prev)[:, None] - prev)
        d[~off] = 0.0
        np.fill_diagonal(d, -d.sum(axis=1))
        out.append(d)
        prev = d
    return out


def interpolation_matrix(x: np.ndarray, y: np.ndarray, weights: np.ndarray | None = None
                         ) -> np.ndarray:
    """Matrix E with (E f)(y_i) = p(y_i), p the polynomial interpolating f at the nodes x.

    Barycentric formula of the second kind (Berrut and Trefethen 2004, (4.2)); a point y_i that
    coincides with a node x_j takes f_j exactly.
    """
    x = _distinct_nodes(x)
    y = np.atleast_1d(np.asarray(y, dtype=float))
    w = barycentric_weights(x) if weights is None else np.asarray(weights, dtype=float)
    diff = y[:, None] - x[None, :]
    exact = diff == 0.0
    diff[exact] = 1.0
    terms = w[None, :] / diff
    E = terms / terms.sum(axis=1, keepdims=True)
    hit = exact.any(axis=1)
    E[hit] = exact[hit].astype(float)
    return E


def clenshaw_curtis_weights(n: int) -> np.ndarray:
    """Clenshaw-Curtis quadrature weights on the Lobatto points, int_{-1}^{1} f ~ sum_j v_j f_j.

    Exact for polynomials of degree <= n. Formula of Waldvogel (2006, BIT 46) in the explicit
    cosine-sum form: v_j = (c_j / n) (1 - sum_{k=1}^{floor(n/2)} b_k cos(2 pi k j / n)
    / (4k^2 - 1)), with c_j = 1 at the two ends and 2 elsewhere, b_k = 1 for k = n/2 and 2
    otherwise.
    """
    n = require_int_in_range("n", n, 1)
    j = np.arange(n + 1)
    v = np.ones(n + 1)
    for k in range(1, n // 2 + 1):
        b = 1.0 if 2 * k == n else 2.0
        v -= b * np.cos(2 * np.pi * k * j / n) / (4 * k * k - 1)
    c = np.full(n + 1, 2.0)
    c[[0, -1]] = 1.0
    return c * v / n


def parity_fold(matrix: np.ndarray, parity: int) -> np.ndarray:
    """Restrict a Lobatto-grid operator to functions of one parity, acting on the x > 0 half.

    On the Lobatto grid of odd degree n (no node at 0, x_{n-j} = -x_j) a function with
    f(-x) = parity * f(x) is fixed by its h = (n + 1)/2 values at x_0..x_{h-1} > 0, and

        (A f)(x_i) = sum_{j < h} (A_ij + parity * A_{i, n-j}) f(x_j),     i < h.

    Used for the ball 0 <= r <= 1: a regular field of degree m behaves like r^m times a series
    in r^2, so it extends to [-1, 1] with parity (-1)^m (or (-1)^(m+1) for r times it) and
    regularity at r = 0 needs no boundary row (Trefethen, Spectral Methods in MATLAB, ch. 11).
    """
    matrix = np.asarray(matrix)
    size = matrix.shape[1]
    if size % 2 or matrix.shape[0] != size:
        raise ParameterError(f"matrix shape = {matrix.shape} is invalid: must be square of even "
                             "size (a Lobatto grid of odd degree)")
    if parity not in (1, -1):
        raise ParameterError(f"parity = {parity!r} is invalid: must be 1 or -1")
    h = size // 2
    return matrix[:h, :h] + parity * matrix[:h, ::-1][:, :h]


@dataclass(frozen=True, kw_only=True, eq=False)
class RadialMap:
    """A map x in [-1, 1] -> r, given at the nodes.

    Attributes
    ----------
    x : the computational nodes.
    r_inverse : 1/r at the nodes (0 where r is infinite).
    dx_dr : (x', x'', x''', x''''), the derivatives of x(r) with respect to r at the nodes.
    """

    x: np.ndarray
    r_inverse: np.ndarray
    dx_dr: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def linear_map(x: np.ndarray, a: float, b: float) -> RadialMap:
    """The affine map r = a + (b - a)(x + 1)/2 (x = -1 -> a, x = 1 -> b); x' = 2/(b - a).

    Raises ParameterError if a = b or a node falls on r = 0, where 1/r is undefined (for a ball
    use an odd-degree grid on [-1, 1] and :func:`parity_fold` instead).
    """
    x = np.asarray(x, dtype=float)
    if not (np.isfinite(a) and np.isfinite(b)) or a == b:
        raise ParameterError(f"(a, b) = ({a!r}, {b!r}) is invalid: must be finite and distinct")
    r = a + (b - a) * (x + 1) / 2
    if np.any(r == 0):
        raise ParameterError(f"(a, b) = ({a!r}, {b!r}) is invalid: a node lies on r = 0")
    r_inverse = 1.0 / r
    zero = np.zeros_like(x)
    return RadialMap(x=x, r_inverse=r_inverse,
                     dx_dr=(np.full_like(x, 2.0 / (b - a)), zero, zero, zero))


def reciprocal_map(x: np.ndarray, *, scale: complex = 1.0) -> RadialMap:
    """The map of [-1, 1] onto 1 <= r <= infinity: r = 1 + c (1/xi - 1), xi = (1 + x)/2.

    x = 1 is r = 1 and x = -1 is r = infinity. With c = 1, xi = 1/r, so r^{-k} = xi^k is a
    polynomial: algebraic decay is represented exactly. Inverse and derivatives:

        1/r = xi / (xi + c (1 - xi)),      d^k x / dr^k = 2 (-1)^k k! xi^(k+1) / c^k.

    A complex c = e^{i phi} is exterior complex scaling (the path r = 1 + e^{i phi} rho, rho
    real >= 0): a field exp(-beta r) decays along it when Re(beta e^{i phi}) > 0.
    """
    x = np.asarray(x, dtype=float)
    c = complex(scale)
    c = c.real if c.imag == 0 else c      # keep real operators real
    if c == 0 or not np.isfinite(c):
        raise ParameterError(f"scale = {scale!r} is invalid: must be finite and non-zero")
    xi = (1 + x) / 2
    r_inverse = xi / (xi + c * (1 - xi))
    dx_dr = tuple(2.0 * (-1) ** k * _factorial(k) * xi ** (k + 1) / c ** k for k in range(1, 5))
    return RadialMap(x=x, r_inverse=r_inverse, dx_dr=dx_dr)


def _factorial(k: int) -> int:
    return int(np.prod(np.arange(1, k + 1))) if k > 1 else 1


def radial_derivatives(derivatives: list[np.ndarray], rmap: RadialMap) -> list[np.ndarray]:
    """Matrices of d^k/dr^k, k = 1..len(derivatives) (at most 4), from D^(k) in x and a map.

    Faa di Bruno for f(x(r)), with x1..x4 the entries of ``rmap.dx_dr``::

        d/dr     = x1 D
        d2/dr2   = x1^2 D2 + x2 D
        d3/dr3   = x1^3 D3 + 3 x1 x2 D2 + x3 D
        d4/dr4   = x1^4 D4 + 6 x1^2 x2 D3 + (3 x2^2 + 4 x1 x3) D2 + x4 D

    The coefficients are evaluated at the nodes, so the result is exact for the interpolant.
    """
    if not 1 <= len(derivatives) <= 4:
        raise ValueError(f"len(derivatives) = {len(derivatives)} is invalid: must be 1..4")
    x1, x2, x3, x4 = rmap.dx_dr
    D = list(derivatives) + [None] * (4 - len(derivatives))

    def rows(c, A):
        return c[:, None] * A

    out = [rows(x1, D[0])]
    if D[1] is not None:
        out.append(rows(x1**2, D[1]) + rows(x2, D[0]))
    if D[2] is not None:
        out.append(rows(x1**3, D[2]) + rows(3 * x1 * x2, D[1]) + rows(x3, D[0]))
    if D[3] is not None:
        out.append(rows(x1**4, D[3]) + rows(6 * x1**2 * x2, D[2])
                   + rows(3 * x2**2 + 4 * x1 * x3, D[1]) + rows(x4, D[0]))
    return out


def ball_derivatives(n_inner: int, parity: int) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """Radii and d/dr, d^2/dr^2 on 0 < r <= 1 for fields of one parity in r (a disc or a ball).

    The nodes are the n_inner positive points of the Lobatto grid of odd degree 2 n_inner - 1 on
    [-1, 1], descending from r = 1; the matrices act on functions with f(-r) = parity f(r)
    (:func:`parity_fold`), which makes regularity at r = 0 automatic (no node, no row there).
    """
    n = 2 * n_inner - 1
    x = lobatto_points(n)
    D = differentiation_matrices(x, 2, lobatto_weights(n))
    return x[:n_inner], tuple(parity_fold(Dk, parity) for Dk in D)


def exterior_derivatives(n_outer: int, angle: float, scale: float
                         ) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, ...]]:
    """(xi, 1/r, (d/dr, d^2/dr^2)) on the exterior 1 <= r <= infinity of n_outer Lobatto nodes.

    The map is :func:`reciprocal_map` with c = scale e^{i angle} (real when angle = 0); xi runs
    from 1 (r = 1) down to 0 (r = infinity).
    """
    n = n_outer - 1
    x = lobatto_points(n)
    D = differentiation_matrices(x, 2, lobatto_weights(n))
    rmap = reciprocal_map(x, scale=scale * np.exp(1j * angle) if angle else scale)
    return (1 + x) / 2, rmap.r_inverse, tuple(radial_derivatives(D, rmap))


# ----------------------------------------------------------------------------- coefficient space
# Ultraspherical (Olver and Townsend 2013, SIAM Rev. 55, section 2) operators on coefficient
# vectors of length n: T (Chebyshev T_0..T_{n-1}) and C^(lam) (Gegenbauer C^(lam)_0..), all
# n x n and sparse (scipy.sparse CSR). Every operator is exact on the coefficients it keeps:
# derivatives and conversions never raise the degree, and a multiplication is built on
# n + degree coefficients before its rows are cut to n.

def ultraspherical_derivative(n: int, k: int):
    """D_k: T -> C^(k), d^k T_j / dx^k = 2^(k-1) (k-1)! j C^(k)_{j-k} (k >= 1)."""
    n = require_int_in_range("n", n, 1)
    k = require_int_in_range("k", k, 1)
    j = np.arange(k, n)
    return sparse.csr_matrix((2.0 ** (k - 1) * _factorial(k - 1) * j, (j - k, j)), shape=(n, n))


def ultraspherical_conversion(n: int, lam: int):
    """S_lam: C^(lam) -> C^(lam+1) (S_0: T -> C^(1)), from T_j = (C^(1)_j - C^(1)_{j-2})/2 (j >= 1,
    T_0 = C^(1)_0) and C^(lam)_j = lam/(j + lam) (C^(lam+1)_j - C^(lam+1)_{j-2})."""
    n = require_int_in_range("n", n, 1)
    lam = require_int_in_range("lam", lam, 0)
    j = np.arange(n, dtype=float)
    if lam == 0:
        diag = np.where(j == 0, 1.0, 0.5)
        upper = np.full(max(n - 2, 0), -0.5)
    else:
        diag = lam / (j + lam)
        upper = -lam / (j[2:] + lam)
    return sparse.diags([diag, upper], [0, 2], shape=(n, n), format="csr")


def ultraspherical_multiplication(n: int, lam: int, coefficients, *, shift: float = 0.0,
                                  scale: float = 1.0):
    """Multiplication by a(y) = sum_k a_k y^k, y = shift + scale x, on C^(lam) (lam = 0: T).

    From the three-term recurrences x T_j = (T_{j+1} + T_{|j-1|})/2 and
    x C^(lam)_j = ((j + 1) C^(lam)_{j+1} + (j + 2 lam - 1) C^(lam)_{j-1}) / (2 (j + lam)), a(y) is
    evaluated by Horner's rule on the Jacobi matrix of size n + degree and cut to n x n (exact
    there). ``coefficients`` are the monomial coefficients a_0, a_1, ... in y.
    """
    n = require_int_in_range("n", n, 1)
    lam = require_int_in_range("lam", lam, 0)
    a = np.atleast_1d(np.asarray(coefficients, dtype=float))
    big = n + a.size
    j = np.arange(big, dtype=float)
    if lam == 0:
        sub = np.full(big - 1, 0.5)
        sup = np.full(big - 1, 0.5)
        sub[0] = 1.0                                   # x T_0 = T_1
    else:
        sub = (j[:-1] + 1) / (2 * (j[:-1] + lam))      # C_{j+1} in x C_j
        sup = (j[1:] + 2 * lam - 1) / (2 * (j[1:] + lam))   # C_{j-1} in x C_j
    X = sparse.diags([sub, sup], [-1, 1], shape=(big, big), format="csr")
    eye = sparse.identity(big, format="csr")
    Y = shift * eye + scale * X
    out = a[-1] * eye
    for ak in a[-2::-1]:
        out = out @ Y + ak * eye
    return sparse.csr_matrix(out[:n, :n])


def chebyshev_boundary_rows(n: int) -> dict[str, np.ndarray]:
    """Rows evaluating a T-series of length n at x = +-1 and its derivative there:
    T_j(1) = 1, T_j(-1) = (-1)^j, T_j'(1) = j^2, T_j'(-1) = (-1)^(j+1) j^2."""
    n = require_int_in_range("n", n, 1)
    j = np.arange(n, dtype=float)
    sign = (-1.0) ** np.arange(n)
    return {"value_right": np.ones(n), "value_left": sign, "slope_right": j**2,
            "slope_left": -sign * j**2}
