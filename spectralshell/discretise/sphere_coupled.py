"""Non-uniform stiffness kappa(theta, phi): degrees coupled through products on an SHTns grid.

Model (beyond the thesis, which has uniform kappa). The membrane load is taken pointwise as the
stiffness times the linearised load of the uniform model at unit stiffness,

    F(theta, phi, t) = K(theta, phi, t) F1[X],      K = kappa(theta, phi) (1 + 2 tau sin t),
    F1[X] = -sum_{m,k} (m-1)(m+2) (X^Y_{mk} Yr_{mk} rhat + X^Psi_{mk} Psi_{mk} + X^Phi_{mk} Phi_{mk}),

(Psi = r grad Yr, Phi = rhat x Psi), i.e. the stress-jump rows of each degree receive the
(m, k) component of the product field instead of -K (m-1)(m+2) X. This is a modelling choice:
with a non-uniform tension the sphere is not an exact equilibrium (the tension gradient is a
tangential force the resting fluid cannot balance) and the gradient terms of div(K grad X) are
left out; the product is not symmetric, so there is no energy identity. Degrees 0 and 1 of the
product are not represented (degree 0 is absorbed by the pressure of an incompressible fluid,
degree 1 is a net force that would translate the sphere rigidly).

Discretisation. Every allocated mode (m, k, component) carries the reduced (collocation, at any
n_radial: the load response B below is a column of the reduced ODE) radial system of
:mod:`.sphere_stepping` for degree m at the mean stiffness kappa_mean (the average of kappa over
the sphere), whose implicit part L0 + kappa_mean L1 is block diagonal (the blocks of one degree
are equal: one factorisation per degree and step). The rest is explicit and matrix-free:

    dy/dt = L y + B P[(kappa - kappa_mean) F1[X]] + 2 tau sin(t) B P[kappa F1[X]],

with B = :attr:`DegreeSystem.load_response` and P the projection onto the allocated modes,
computed by synthesising F1 on a Gauss grid of degree l_max (3/2 rule, :mod:`.shtns_adapter`),
multiplying by the (degree <= l_max truncated) kappa and analysing (exact up to degree l_max).
Allocation: the modes of the initial shape and every mode (2 <= m <= l_max) reachable from them
by repeated products with kappa - kappa_mean; nothing else. The toroidal component is allocated
when the coupling reaches it (a non-uniform kappa turns a Psi load partly into a Phi load).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sparse

from .._validate import require_int_in_range, require_nonnegative, require_real
from ..errors import ParameterError
from .shtns_adapter import Grid, grid as dealiased_grid
from .sphere_stepping import DegreeSystem, degree_system

COUPLING_TOL = 1e-12      # relative size below which a product coefficient is zero


@dataclass(frozen=True, kw_only=True, eq=False)
class ModeGroup:
    """The allocated orders ``ks`` of one degree and component, stored contiguously from
    ``offset`` as len(ks) consecutive states of ``system`` (size n each)."""

    m: int
    component: str
    ks: tuple[int, ...]
    offset: int
    system: DegreeSystem

    @property
    def stop(self) -> int:
        return self.offset + len(self.ks) * self.system.size


class KappaLoad:
    """Matrix-free explicit operator v -> B P[w F1[X(v)]] for a weight field w on the grid."""

    def __init__(self, groups: tuple[ModeGroup, ...], weight: np.ndarray, grid: Grid,
                 size: int) -> None:
        self.groups, self.weight, self.grid = groups, weight, grid
        self.shape = (size, size)
        self.positions = [grid.index([(g.m, k) for k in g.ks]) for g in groups]
        self.responses = [g.system.load_response for g in groups]

    def __matmul__(self, v: np.ndarray) -> np.ndarray:
        v = np.asarray(v)
        if v.ndim == 2:
            return np.column_stack([self @ v[:, j] for j in range(v.shape[1])])
        grid = self.grid
        radial, sph, tor = (np.zeros(len(grid.modes)) for _ in range(3))
        for g, pos in zip(self.groups, self.positions):
            X = v[g.offset:g.stop].reshape(len(g.ks), g.system.size)[:, g.system.membrane]
            q1 = (g.m - 1) * (g.m + 2)
            if g.component == "poloidal":
                radial[pos], sph[pos] = -q1 * X[:, 0], -q1 * X[:, 1]
            else:
                tor[pos] = -q1 * X[:, 0]
        load_r, load_s, load_t = weighted_load(grid, self.weight, radial, sph, tor)
        out = np.zeros(v.shape)
        for g, pos, B in zip(self.groups, self.positions, self.responses):
            F = (np.vstack([load_r[pos], load_s[pos]]) if g.component == "poloidal"
                 else load_t[pos][None, :])
            out[g.offset:g.stop] = (B @ F).T.reshape(-1)
        return out


@dataclass(frozen=True, kw_only=True, eq=False)
class CoupledSystem:
    """dy/dt = L y + sum_j f_j(t) N_j y for all allocated modes (see the module docstring).

    Attributes: M (sparse identity), L (sparse block diagonal), explicit_terms ((f, N), ...) for
    the stepper, groups (the allocated modes), kappa_mean, kappa_coefficients (real harmonic
    coefficients of the kappa used, degrees <= l_max), grid, warnings.
    """

    M: sparse.csc_matrix
    L: sparse.csc_matrix
    explicit_terms: tuple
    groups: tuple[ModeGroup, ...]
    kappa_mean: float
    kappa_coefficients: dict
    grid: Grid
    tau: float
    warnings: tuple[str, ...]

    @property
    def size(self) -> int:
        return self.L.shape[0]

    @property
    def modes(self) -> tuple[tuple[int, int], ...]:
        """Poloidal modes (m, k), in state order."""
        return tuple((g.m, k) for g in self.groups if g.component == "poloidal" for k in g.ks)

    @property
    def toroidal_modes(self) -> tuple[tuple[int, int], ...]:
        return tuple((g.m, k) for g in self.groups if g.component == "toroidal" for k in g.ks)

    def initial_state(self, shape: Mapping[tuple[int, int], float]) -> np.ndarray:
        """The state at rest with radial displacement ``shape`` {(m, k): X^Y}."""
        v = np.zeros(self.size)
        for g in self.groups:
            if g.component != "poloidal":
                continue
            X = np.zeros((2, len(g.ks)))
            X[0] = [shape.get((g.m, k), 0.0) for k in g.ks]
            v[g.offset:g.stop] = g.system.initial_state(X).T.reshape(-1)
        return v

    def displacement(self, v: np.ndarray) -> np.ndarray:
        """(X^Y of every poloidal mode, X^Psi of every poloidal mode, X^Phi of every toroidal
        mode), concatenated in the order of :attr:`modes` and :attr:`toroidal_modes`."""
        parts = {"Y": [], "Psi": [], "Phi": []}
        for g in self.groups:
            Y = np.asarray(v)[g.offset:g.stop].reshape(len(g.ks), g.system.size)
            X = Y[:, g.system.membrane]
            if g.component == "poloidal":
                parts["Y"].append(X[:, 0])
                parts["Psi"].append(X[:, 1])
            else:
                parts["Phi"].append(X[:, 0])
        return np.concatenate([np.concatenate(p) if p else np.zeros(0) for p in parts.values()])


def weighted_load(grid: Grid, weight: np.ndarray, radial: np.ndarray, sph: np.ndarray,
                  tor: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coefficient vectors (radial, spheroidal, toroidal) of P[w F]: the membrane field F with
    coefficient vectors (radial, sph, tor) multiplied on the grid by the weight field w and
    analysed (exact up to degree l_max; the product of the module docstring)."""
    load_r = grid.analyse_array(weight * grid.synthesise_array(radial))
    vt, vp = grid.synthesise_tangential_array(sph, tor)
    load_s, load_t = grid.analyse_tangential_array(weight * vt, weight * vp)
    return load_r, load_s, load_t


def _products(grid: Grid, weight: np.ndarray, mode: tuple[int, int], component: str) -> tuple:
    """Coefficients (radial, spheroidal, toroidal) of weight times the unit field of a mode."""
    unit, zero = grid.vector({mode: 1.0}), np.zeros(len(grid.modes))
    fields = (unit, unit, zero) if component == "poloidal" else (zero, zero, unit)
    return tuple(dict(zip(grid.modes, c.tolist())) for c in weighted_load(grid, weight, *fields))


def _allocate(grid: Grid, coupling: np.ndarray, start: set,
              max_degree: int) -> tuple[dict[str, set], bool]:
    """Closure of ``start`` (poloidal modes) under products with the coupling field, degrees
    2..max_degree; and whether the products reach beyond max_degree (truncated)."""
    scale = max(float(np.max(np.abs(coupling))), 1e-300)
    found = {"poloidal": set(start), "toroidal": set()}
    truncated = False
    frontier = [(mk, "poloidal") for mk in start]
    while frontier:
        mode, component = frontier.pop()
        radial, sph, tor = _products(grid, coupling, mode, component)
        for comp, coeffs in (("poloidal", radial), ("poloidal", sph), ("toroidal", tor)):
            for mk, c in coeffs.items():
                if mk[0] < 2 or abs(c) <= COUPLING_TOL * scale or mk in found[comp]:
                    continue
                if mk[0] > max_degree:
                    truncated = True
                    continue
                found[comp].add(mk)
                frontier.append((mk, comp))
    return found, truncated


@dataclass(frozen=True, kw_only=True, eq=False)
class StiffnessField:
    """kappa(theta, phi) on a grid, truncated to degrees <= l_max: ``weight`` (grid values),
    ``coefficients`` {(m, k): c}, ``mean`` (its average over the sphere), ``degree`` (its
    highest degree above COUPLING_TOL relative to the mean) and ``warnings``."""

    weight: np.ndarray
    coefficients: dict
    mean: float
    degree: int
    warnings: tuple[str, ...]


def stiffness_field(grid: Grid, kappa: Callable[[np.ndarray, np.ndarray], np.ndarray]
                    ) -> StiffnessField:
    """The stiffness field of a numpy function kappa(theta, phi) on ``grid`` (degrees <= its
    l_max; a warning when kappa is not resolved by them).

    Raises
    ------
    ParameterError : kappa not positive everywhere on the grid.
    """
    values = grid.evaluate(kappa)
    coeffs = grid.analyse(values)
    weight = grid.synthesise(coeffs)                 # kappa truncated to degrees <= l_max
    warnings = []
    residual = np.max(np.abs(weight - values)) / np.max(np.abs(values))
    if residual > 1e-8:
        warnings.append(f"kappa is not resolved by degrees <= l_max = {grid.l_max} (relative "
                        f"residual {residual:.1e}); its higher degrees are left out")
    if np.min(weight) <= 0:
        raise ParameterError(f"kappa = expression is invalid: must be > 0 everywhere (minimum "
                             f"{np.min(weight):.3g} on the grid)")
    degree = max((m for (m, _), c in coeffs.items()
                  if m > 0 and abs(c) > COUPLING_TOL * abs(coeffs[0, 0])), default=0)
    return StiffnessField(weight=weight, coefficients=coeffs,
                          mean=float(coeffs[0, 0] / np.sqrt(4 * np.pi)), degree=degree,
                          warnings=tuple(warnings))


def coupled_system(*, kappa: Callable[[np.ndarray, np.ndarray], np.ndarray],
                   shape: Mapping[tuple[int, int], float], nu: float, tau: float, l_max: int,
                   max_degree: int | None = None, n_radial: int | None = None,
                   tol: float = 1e-9) -> CoupledSystem:
    """The coupled system of a scene with stiffness kappa(theta, phi) (a numpy function).

    l_max : degree of the grid (products exact up to it) and of the truncated kappa.
    max_degree : highest allocated degree (<= l_max); default: the shape's highest degree plus
        twice the degree of kappa - kappa_mean (two successive products), at most l_max. Each
        product moves energy by up to that degree, with an amplitude factor of the relative
        non-uniformity, so the default keeps the first two orders of the coupling; a warning
        says when the coupling reaches further (raise max_degree to check convergence).

    Raises
    ------
    ParameterError : nu = 0 (the tangential load needs viscosity), kappa not positive
        everywhere, a shape degree above l_max.
    """
    nu = require_nonnegative("nu", nu)
    tau = require_real("tau", tau)
    l_max = require_int_in_range("l_max", l_max, 2, 200)
    if nu == 0.0:
        raise ParameterError("nu = 0 is invalid with a non-uniform kappa: the coupled model "
                             "needs the viscous fluid (tangential loads)")
    bad = [mk for mk in shape if mk[0] > l_max]
    if bad:
        raise ParameterError(f"shape mode {bad[0]} is invalid: its degree exceeds l_max = {l_max}")
    grid = dealiased_grid(l_max)
    field = stiffness_field(grid, kappa)
    weight, coeffs, mean, kappa_degree = field.weight, field.coefficients, field.mean, field.degree
    warnings = list(field.warnings)
    if max_degree is None:
        max_degree = min(l_max, max(m for m, _ in shape) + 2 * kappa_degree)
    max_degree = require_int_in_range("max_degree", max_degree, 2, l_max)
    found, truncated = _allocate(grid, weight - mean, set(shape), max_degree)
    if truncated:
        warnings.append(f"the kappa coupling reaches degrees above {max_degree}, which are not "
                        "allocated (set simulate.l_max to allocate up to it)")
    groups, offset = [], 0
    for component in ("poloidal", "toroidal"):
        for m in sorted({mk[0] for mk in found[component]}):
            ks = tuple(sorted(k for mm, k in found[component] if mm == m))
            system = degree_system(m=m, kappa=mean, nu=nu, tau=0.0, component=component,
                                   n_radial=n_radial, tol=tol, radial="collocation")
            groups.append(ModeGroup(m=m, component=component, ks=ks, offset=offset,
                                    system=system))
            offset += len(ks) * system.size
    groups = tuple(groups)
    L = sparse.block_diag([g.system.L for g in groups for _ in g.ks], format="csc")
    terms = [(lambda t: 1.0, KappaLoad(groups, weight - mean, grid, offset))]
    if tau != 0.0:
        terms.append((lambda t, tau=tau: 2.0 * tau * np.sin(t),
                      KappaLoad(groups, weight, grid, offset)))
    return CoupledSystem(M=sparse.identity(offset, format="csc"), L=L, explicit_terms=tuple(terms),
                         groups=groups, kappa_mean=float(mean), kappa_coefficients=coeffs,
                         grid=grid, tau=tau, warnings=tuple(warnings))
