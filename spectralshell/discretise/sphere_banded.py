"""Sparse radial operators of one degree m of the sphere in Chebyshev coefficient space.

The equations, interface and membrane rows are those of :mod:`.sphere_radial` (module docstring
there; derived in ``derivations/sphere_radial.py``), discretised by the ultraspherical spectral
method (Olver and Townsend 2013, SIAM Rev. 55) instead of collocation, so that every matrix has
O(n) non-zero entries:

    M dv/dt = (L_fluid + K(t) L_stiffness) v,      K(t) = kappa (1 + 2 tau sin t)   (6.3f).

Unknowns are Chebyshev (T) coefficients; an equation is multiplied by the power of r (inside) or
of rho = r xi (outside) that makes all its coefficients polynomial, and its residual is expanded
in C^(2) (differentiation T -> C^(k), conversion C^(k) -> C^(k+1) and multiplication by a
polynomial are banded: :func:`.chebyshev.ultraspherical_derivative` etc.). The highest residual
coefficients are dropped (tau method) to make room for the boundary and interface rows, which
are the only dense rows. Each step of the check is in ``derivations/sphere_banded.py``.

Interior 0 <= r <= 1 (regular at r = 0). A regular field of degree m is r^(m+1) (poloidal psi,
omega) or r^m (toroidal g) times an even function of r, so the unknowns are the even functions

    psi = r^(m+1) p,  omega = r^(m+1) w,  g = r^m q,

and with L_m(r^(m+1) p) = r^(m+1) B p, Lap_m(r^m q) = r^m B q, B = d^2/dr^2 + (2(m+1)/r) d/dr,
the equations of sphere_radial become, multiplied by r,

    r B p = r w   (psi relation, algebraic),   s r w = nu r B w,   s r q = nu r B q,

r B = r d^2/dr^2 + 2(m+1) d/dr. Their polynomial solutions need no condition at r = 0 (B has the
second solution r^-(2m+1)): one condition per unknown, at r = 1. The interior is [-1, 1] in r
with parity-restricted coefficients: p, w, q are sums of T_0, T_2, .., T_{2 n_inner - 2}
(n_inner unknowns), their equations odd functions whose odd C^(2) coefficients 1, 3, ..,
2 n_inner - 3 are kept (n_inner - 1 rows; the even ones vanish identically).

Exterior r >= 1, mapped as in sphere_radial (real angle only): r = 1 + L (1/xi - 1) = rho/xi,
rho = L + (1 - L) xi, xi = (1 + x)/2, so d/dr = -(xi^2/L) d/dxi and 1/r = xi/rho. Multiplied by
L^2 rho^2, L_m f = rho^2 (xi^4 f'' + 2 xi^3 f') - c L^2 xi^2 f (' = d/dxi, c = m(m+1)) carries
a factor xi^2, which makes the psi relation (no s term) degenerate at xi = 0 and its
coefficient matrix ill-conditioned (cond(M - h L) measured 2e12 at n = 64, 1e18 at n = 256). The exterior vorticity unknown is
therefore Omega = omega / xi^2 (omega is flat at xi = 0: the tail exp(-beta r)), and the rows,
divided by xi^2, are

    rho^2 (xi^2 psi'' + 2 xi psi') - c L^2 psi = L^2 rho^2 Omega                   (psi relation)
    s L^2 rho^2 Omega = nu xi^2 [rho^2 (xi^2 Omega'' + 6 xi Omega' + 6 Omega) - c L^2 Omega]
    s L^2 rho^2 g = nu [rho^2 (xi^4 g'' + 2 xi^3 g') - 2 L rho xi^3 g' - c L^2 xi^2 g]

on T-series in x (n_outer coefficients each), with C^(2) coefficients 0 .. n_outer - 3 kept and
two conditions each: the interface row and the value 0 at xi = 0 (r = infinity), as in
sphere_radial (psi = 0, omega = 0 there; Omega = 0 is the same condition on the flat tail).
At r = 1+, omega = Omega and omega' = -(1/L)(2 Omega + Omega_xi). Then cond(11/6 M - 0.005 L)
is 3e7 at n = 64 and 6e10 at n = 256 (m = 2, nu = 0.01).

Interface and membrane rows (sphere_radial, q1 = (m-1)(m+2), ' = d/dr): at r = 1-,
psi = p, psi' = (m+1) p + p', omega' = (m+1) w + w', g' = m q + q'; at r = 1+, ' = -(1/L) d/dxi.
[[psi]] = 0, [[psi']] = 0, -nu [[omega']] - K q1 X^Y = 0, nu [[omega]] - K q1 X^Psi = 0,
s X^Y = c psi(1-), s X^Psi = psi'(1-); toroidal [[g]] = 0, nu [[g']] - K q1 X^Phi = 0,
s X^Phi = g(1-).

M is not diagonal (it is the banded operator of the s terms); its zero rows are the psi relation
and the boundary/interface rows. The system is an index-1 DAE: the s rows together with the
boundary rows of omega (g) determine dv/dt of the differential unknowns. The unknowns and rows
are stored interleaved across blocks with the boundary rows last (:func:`_ordering`), so that a
sparse LU of M - h L without row interchanges has O(n) fill (solvers/stepper.py); ``blocks``
maps each block to the positions of its coefficients.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from types import MappingProxyType

import numpy as np
import scipy.sparse as sparse
from numpy.polynomial import chebyshev as cheb
from numpy.polynomial import polynomial as poly

from .._validate import require_choice, require_int_in_range, require_positive
from .chebyshev import (chebyshev_boundary_rows, ultraspherical_conversion,
                        ultraspherical_derivative, ultraspherical_multiplication)
from .sphere_radial import COMPONENTS, MEMBRANE, N_RADIAL_MAX, require_exterior_scale

N_MIN = 6


@dataclass(frozen=True, kw_only=True, eq=False)
class BandedOperators:
    """Per-degree sparse operators, s M v = (L_fluid + K L_stiffness) v (see the module docstring).

    The state v holds Chebyshev coefficient blocks (``blocks``: name -> index array of the
    coefficients 0, 1, .. in storage order; the membrane a slice, stored last):

    * poloidal: ``p_inner`` (coefficients of T_0, T_2, .. in r of p = psi / r^(m+1)),
      ``psi_outer`` (T_0, T_1, .. in x of psi), ``w_inner`` (omega / r^(m+1)),
      ``Omega_outer`` (omega / xi^2), ``membrane`` (X^Y, X^Psi);
    * toroidal: ``q_inner`` (g / r^m), ``g_outer``, ``membrane`` (X^Phi).

    The rows are the blocks' equations (kept C^(2) coefficients) and boundary rows, stored as
    described in :func:`_ordering`.

    Attributes
    ----------
    m, nu, component, n_inner, n_outer, exterior_scale : what was assembled.
    M, L_fluid, L_stiffness : (size, size) scipy.sparse CSR matrices (real).
    blocks : read-only mapping name -> positions in v. membrane_names : ('Y', 'Psi') or ('Phi',).
    constraint_rows : indices of the zero rows of M.
    """

    m: int
    nu: float
    component: str
    n_inner: int
    n_outer: int
    exterior_scale: float
    M: sparse.csr_matrix
    L_fluid: sparse.csr_matrix
    L_stiffness: sparse.csr_matrix
    blocks: Mapping[str, np.ndarray | slice]
    membrane_names: tuple[str, ...]
    constraint_rows: np.ndarray

    @property
    def size(self) -> int:
        """Length of the state vector v."""
        return self.M.shape[0]

    def pencil(self, kappa: float):
        """(L, M) of the natural-mode problem s M v = L v at constant stiffness K = kappa."""
        kappa = require_positive("kappa", kappa)
        return (self.L_fluid + kappa * self.L_stiffness).tocsr(), self.M

    def displacement(self, v: np.ndarray) -> np.ndarray:
        """Membrane displacement components (X^Y, X^Psi) or (X^Phi,) of a state vector."""
        return np.asarray(v)[self.blocks["membrane"]]

    def inner_series(self, v: np.ndarray, name: str) -> np.ndarray:
        """Full T-series in r on [-1, 1] (zeros at odd degrees) of an inner block."""
        coeffs = np.asarray(v)[self.blocks[name]]
        out = np.zeros((2 * coeffs.shape[0] - 1,) + coeffs.shape[1:], dtype=coeffs.dtype)
        out[::2] = coeffs
        return out

    def kinetic_dissipation(self, v: np.ndarray) -> tuple[float, float]:
        """(E_kin, D) of a real state (integrals of sphere_stepping.DegreeSystem.energy):

        E_kin = 1/2 int (c^2 psi^2 / r^2 + c psi'^2) dr   or 1/2 int c g^2 r^2 dr,
        D     = nu int c omega^2 dr                        or nu int (c^2 g^2 + c ((r g)')^2) dr,

        by Gauss-Legendre rules: inside (polynomial integrands) exact, outside in xi with
        dr = (L / xi^2) dxi (the integrands are smooth there and vanish at xi = 0)."""
        v = np.asarray(v, dtype=float)
        m, c, L = self.m, self.m * (self.m + 1), self.exterior_scale
        r, wr = _unit_gauss(2 * self.n_inner + m + 4)
        xi, wx = _unit_gauss(2 * self.n_outer + 8)
        x_out = 2 * xi - 1
        rho = L + (1 - L) * xi
        jac = L / xi**2
        if self.component == "poloidal":
            p = self.inner_series(v, "p_inner")
            pv, dp = cheb.chebval(r, p), cheb.chebval(r, cheb.chebder(p))
            psi_r2 = r ** (2 * m) * pv**2                       # psi^2 / r^2
            dpsi = r**m * ((m + 1) * pv + r * dp)               # psi'
            w = cheb.chebval(r, self.inner_series(v, "w_inner")) * r ** (m + 1)
            kin_in = wr @ (c**2 * psi_r2 + c * dpsi**2)
            dis_in = wr @ (c * w**2)
            a = v[self.blocks["psi_outer"]]
            psi = cheb.chebval(x_out, a)
            dpsi_dr = -(xi**2 / L) * 2 * cheb.chebval(x_out, cheb.chebder(a))
            om = cheb.chebval(x_out, v[self.blocks["Omega_outer"]]) * xi**2   # omega
            kin_out = wx @ ((c**2 * psi**2 * (xi / rho) ** 2 + c * dpsi_dr**2) * jac)
            dis_out = wx @ (c * om**2 * jac)
        else:
            q = self.inner_series(v, "q_inner")
            qv, dq = cheb.chebval(r, q), cheb.chebval(r, cheb.chebder(q))
            g = r**m * qv
            drg = r**m * ((m + 1) * qv + r * dq)                # (r g)' = (r^(m+1) q)'
            kin_in = wr @ (c * g**2 * r**2)
            dis_in = wr @ (c**2 * g**2 + c * drg**2)
            a = v[self.blocks["g_outer"]]
            g = cheb.chebval(x_out, a)
            dg_dr = -(xi**2 / L) * 2 * cheb.chebval(x_out, cheb.chebder(a))
            rr = rho / xi
            kin_out = wx @ (c * g**2 * rr**2 * jac)
            dis_out = wx @ ((c**2 * g**2 + c * (g + rr * dg_dr) ** 2) * jac)
        kinetic = 0.5 * (kin_in + kin_out)
        dissipation = self.nu * (dis_in + dis_out)
        return float(kinetic), float(dissipation)


@lru_cache(maxsize=32)
def _unit_gauss(count: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [0, 1]."""
    nodes, weights = np.polynomial.legendre.leggauss(count)
    return (nodes + 1) / 2, weights / 2


def _check(m, nu, component, n_inner, n_outer, exterior_scale):
    m = require_int_in_range("m", m, 2, 200)
    nu = require_positive("nu", nu)
    component = require_choice("component", component, COMPONENTS)
    n_inner = require_int_in_range("n_inner", n_inner, N_MIN, N_RADIAL_MAX)
    n_outer = require_int_in_range("n_outer", n_outer, N_MIN, N_RADIAL_MAX)
    return m, nu, component, n_inner, n_outer, require_exterior_scale(exterior_scale)


def banded_operators(*, m: int, nu: float, component: str = "poloidal", n_inner: int,
                     n_outer: int, exterior_scale: float = 1.0) -> BandedOperators:
    """Assemble the sparse ultraspherical operators of degree m (rows: module docstring).

    Parameters
    ----------
    m : degree, 2..200. nu : viscosity > 0. component : 'poloidal' or 'toroidal'.
    n_inner : even T coefficients of each inner unknown (degree 2 n_inner - 2 in r), >= 6.
    n_outer : T coefficients of each outer unknown (degree n_outer - 1 in x), >= 6.
    exterior_scale : L of the map r = 1 + L (1/xi - 1), in [1e-3, 1e3].

    Raises
    ------
    ParameterError : any argument outside its range.
    """
    m, nu, component, n_inner, n_outer, scale = _check(m, nu, component, n_inner, n_outer,
                                                       exterior_scale)
    inner = _inner_operator(n_inner, m)
    if component == "poloidal":
        return _poloidal(m, nu, n_inner, n_outer, scale, inner)
    return _toroidal(m, nu, n_inner, n_outer, scale, inner)


def _inner_operator(n_inner: int, m: int):
    """(r B, r) on the even T coefficients -> odd C^(2) coefficients 1, 3, .., 2 n_inner - 3."""
    n = 2 * n_inner - 1
    S01 = ultraspherical_conversion(n, 1) @ ultraspherical_conversion(n, 0)
    X = ultraspherical_multiplication(n, 2, [0.0, 1.0])
    rB = X @ ultraspherical_derivative(n, 2) + 2 * (m + 1) * (
        ultraspherical_conversion(n, 1) @ ultraspherical_derivative(n, 1))
    rows, cols = np.arange(1, n - 1, 2), np.arange(0, n, 2)
    return rB[rows][:, cols], (X @ S01)[rows][:, cols]


def _outer_operators(n_outer: int, m: int, scale: float, component: str):
    """Exterior operators in x -> C^(2) coefficients 0 .. n_outer - 3 (xi = (1 + x)/2, so
    d/dxi = 2 d/dx): poloidal (psi relation on psi, vorticity operator on Omega, mass), toroidal
    (Laplacian operator on g, mass); the rows of the module docstring."""
    n, L, c = n_outer, scale, m * (m + 1)
    rho = np.array([L, 1.0 - L])                                   # in xi
    rho2 = poly.polymul(rho, rho)
    xi = lambda k: np.eye(k + 1)[k]                                # noqa: E731  xi^k

    def times(*factors):
        coeffs = np.array([1.0])
        for f in factors:
            coeffs = poly.polymul(coeffs, f)
        return ultraspherical_multiplication(n, 2, coeffs, shift=0.5, scale=0.5)

    D2 = 4 * ultraspherical_derivative(n, 2)                       # d^2/dxi^2
    D1 = 2 * ultraspherical_conversion(n, 1) @ ultraspherical_derivative(n, 1)
    D0 = ultraspherical_conversion(n, 1) @ ultraspherical_conversion(n, 0)
    mass = L**2 * times(rho2) @ D0
    if component == "poloidal":
        psi = times(rho2, xi(2)) @ D2 + 2 * times(rho2, xi(1)) @ D1 - c * L**2 * D0
        omega = (times(rho2, xi(4)) @ D2 + 6 * times(rho2, xi(3)) @ D1
                 + times(xi(2), poly.polysub(6 * rho2, [c * L**2])) @ D0)
        ops = (psi, omega, mass)
    else:
        lap = (times(rho2, xi(4)) @ D2 + 2 * times(rho2, xi(3)) @ D1
               - 2 * L * times(rho, xi(3)) @ D1 - c * L**2 * times(xi(2)) @ D0)
        ops = (lap, mass)
    rows = np.arange(n - 2)
    return tuple(sparse.csr_matrix(op[rows]) for op in ops)


class _Assembly:
    """COO triplets of a square matrix built from blocks."""

    def __init__(self, size: int) -> None:
        self.size, self.rows, self.cols, self.vals = size, [], [], []

    def add(self, row0: int, col0: int, block) -> None:
        block = sparse.coo_matrix(np.atleast_2d(block) if not sparse.issparse(block) else block)
        self.rows.append(block.row + row0)
        self.cols.append(block.col + col0)
        self.vals.append(block.data)

    def matrix(self) -> sparse.csr_matrix:
        if not self.rows:
            return sparse.csr_matrix((self.size, self.size))
        return sparse.csr_matrix((np.concatenate(self.vals), (np.concatenate(self.rows),
                                  np.concatenate(self.cols))), shape=(self.size, self.size))


def _edges(n_inner: int, n_outer: int, shift: int, scale: float):
    """Boundary rows: inner value and d/dr at r = 1 of r^shift times an even series; outer value
    and d/dr at r = 1 (x = 1), value at r = infinity (x = -1), and d/dr of omega = xi^2 Omega at
    r = 1 from Omega."""
    j = np.arange(0, 2 * n_inner - 1, 2, dtype=float)
    out = chebyshev_boundary_rows(n_outer)
    return {"in_value": np.ones(n_inner), "in_slope": shift + j**2,
            "out_value": out["value_right"], "out_slope": -(2.0 / scale) * out["slope_right"],
            "out_infinity": out["value_left"],
            "out_omega_slope": -(2.0 / scale) * (out["value_right"] + out["slope_right"])}


def _poloidal(m, nu, ni, no, scale, inner) -> BandedOperators:
    c, q1 = m * (m + 1), (m - 1) * (m + 2)
    rB, r_mass = inner
    psi_out, omega_out, mass_out = _outer_operators(no, m, scale, "poloidal")
    e = _edges(ni, no, m + 1, scale)
    P, PO, W, WO = 0, ni, ni + no, 2 * ni + no
    iy, ip = 2 * (ni + no), 2 * (ni + no) + 1
    size = ip + 1
    M, L, S = _Assembly(size), _Assembly(size), _Assembly(size)
    # psi relation (algebraic) and vorticity diffusion, inside and outside
    L.add(P, P, rB)
    L.add(P, W, -r_mass)
    L.add(PO, PO, psi_out)
    L.add(PO, WO, -mass_out)
    M.add(W, W, r_mass)
    L.add(W, W, nu * rB)
    M.add(WO, WO, mass_out)
    L.add(WO, WO, nu * omega_out)
    # boundary rows, last rows of each block
    L.add(P + ni - 1, P, -e["in_value"])                        # [[psi]] = 0
    L.add(P + ni - 1, PO, e["out_value"])
    L.add(PO + no - 2, P, -e["in_slope"])                       # [[psi']] = 0
    L.add(PO + no - 2, PO, e["out_slope"])
    L.add(PO + no - 1, PO, e["out_infinity"])                   # psi(infinity) = 0
    L.add(W + ni - 1, W, nu * e["in_slope"])                    # -nu [[omega']]
    L.add(W + ni - 1, WO, -nu * e["out_omega_slope"])
    S.add(W + ni - 1, iy, [[-q1]])                              #   - K q1 X^Y = 0
    L.add(WO + no - 2, W, -nu * e["in_value"])                  # nu [[omega]]
    L.add(WO + no - 2, WO, nu * e["out_value"])
    S.add(WO + no - 2, ip, [[-q1]])                             #   - K q1 X^Psi = 0
    L.add(WO + no - 1, WO, e["out_infinity"])                   # omega(infinity) = 0
    # kinematics s X^Y = c psi(1-), s X^Psi = psi'(1-)
    M.add(iy, iy, np.eye(2))
    L.add(iy, P, c * e["in_value"])
    L.add(ip, P, e["in_slope"])
    blocks = {"p_inner": slice(P, P + ni), "psi_outer": slice(PO, PO + no),
              "w_inner": slice(W, W + ni), "Omega_outer": slice(WO, WO + no),
              "membrane": slice(iy, size)}
    return _operators(m, nu, "poloidal", ni, no, scale, M, L, S, blocks)


def _toroidal(m, nu, ni, no, scale, inner) -> BandedOperators:
    q1 = (m - 1) * (m + 2)
    rB, r_mass = inner
    op_out, mass_out = _outer_operators(no, m, scale, "toroidal")
    e = _edges(ni, no, m, scale)
    G, GO, ix = 0, ni, ni + no
    size = ix + 1
    M, L, S = _Assembly(size), _Assembly(size), _Assembly(size)
    M.add(G, G, r_mass)                                         # s g = nu Lap_m g
    L.add(G, G, nu * rB)
    M.add(GO, GO, mass_out)
    L.add(GO, GO, nu * op_out)
    L.add(G + ni - 1, G, e["in_value"])                         # [[g]] = 0
    L.add(G + ni - 1, GO, -e["out_value"])
    L.add(GO + no - 2, G, -nu * e["in_slope"])                  # nu [[g']]
    L.add(GO + no - 2, GO, nu * e["out_slope"])
    S.add(GO + no - 2, ix, [[-q1]])                             #   - K q1 X^Phi = 0
    L.add(GO + no - 1, GO, e["out_infinity"])                   # g(infinity) = 0
    M.add(ix, ix, [[1.0]])                                      # s X^Phi = g(1-)
    L.add(ix, G, e["in_value"])
    blocks = {"q_inner": slice(G, G + ni), "g_outer": slice(GO, GO + no),
              "membrane": slice(ix, size)}
    return _operators(m, nu, "toroidal", ni, no, scale, M, L, S, blocks)


def _ordering(blocks: dict[str, slice]) -> tuple[np.ndarray, np.ndarray]:
    """(rows, columns): the order of equations and unknowns in which the matrices are stored.

    Assembled block by block, an equation row i of a block expands its residual in C^(2) and is
    dominated by coefficient k = i + shift of its own unknown (shift 1 inside, 2 outside: the
    second derivative lowers the degree; the k < shift left over belong to the boundary rows).
    The unknowns are stored with those dominant coefficients interleaved across blocks in
    descending order of k / (block length), then the left-over coefficients, then the membrane;
    each equation row sits at the position of its dominant coefficient and the boundary rows at
    the left-over ones. The matrices are then banded apart from the boundary rows and the last
    columns, so a sparse LU in this order with diagonal pivots has O(n) fill (see
    solvers/stepper.py)."""
    matched, left = [], []
    for b, (name, sl) in enumerate(blocks.items()):
        count = sl.stop - sl.start
        if name == "membrane":
            left += [(b, sl.start + k, sl.start + k) for k in range(count)]
            continue
        shift = 1 if name.endswith("inner") else 2
        for k in range(count - 1, -1, -1):
            if k >= shift:
                matched.append((-k / count, b, sl.start + k, sl.start + k - shift))
            else:   # boundary rows, in order, at the left-over coefficients
                left.append((b, sl.start + k, sl.start + count - shift + (shift - 1 - k)))
    matched.sort()
    left.sort(key=lambda item: item[0])                    # stable: block order kept
    columns = np.array([c for *_, c, _ in matched] + [c for _, c, _ in left])
    rows = np.array([r for *_, r in matched] + [r for *_, r in left])
    return rows, columns


def _operators(m, nu, component, ni, no, scale, M, L, S, blocks) -> BandedOperators:
    rows, columns = _ordering(blocks)
    position = np.empty_like(columns)
    position[columns] = np.arange(columns.size)
    M, L, S = (sparse.csr_matrix(A.matrix()[rows][:, columns]) for A in (M, L, S))
    stored = {name: position[sl.start:sl.stop] for name, sl in blocks.items()}
    count = blocks["membrane"].stop - blocks["membrane"].start
    stored["membrane"] = slice(columns.size - count, columns.size)     # stored last, in order
    constraint = np.flatnonzero(np.diff(M.indptr) == 0)
    return BandedOperators(m=m, nu=nu, component=component, n_inner=ni, n_outer=no,
                           exterior_scale=scale, M=M, L_fluid=L, L_stiffness=S,
                           blocks=MappingProxyType(stored), membrane_names=MEMBRANE[component],
                           constraint_rows=constraint)
