"""Semi-discrete systems of the sphere for time stepping: M dy/dt = (L + f(t) N) y per degree.

Two radial discretisations of the same equations (``radial``):

* ``'auto'`` (default): collocation below n = BANDED_FROM radial nodes, banded from there,
  where the banded step becomes the cheaper one (validation/bench_stepper.py). The automatic
  resolutions (n <= N_AUTO_MAX < BANDED_FROM) are collocation; a larger ``n_radial`` asked for
  is banded. So the cost per step is at most linear in n over the whole range;
* ``'collocation'``: the reduced dense ODE below (M = I), from the collocation
  operators of :mod:`.sphere_radial`; a step costs O(n^2) (one dense solve);
* ``'banded'``: the unreduced index-1 DAE of :mod:`.sphere_banded` (ultraspherical, Chebyshev
  coefficients; sparse M, L = L_fluid + kappa L_stiffness, N = kappa L_stiffness), whose step
  costs O(n) (a sparse LU solve with O(n) fill and sparse products, solvers/stepper.py). Its
  state is the whole coefficient vector (size about 4n against 2n) and it needs about 1.4 times
  the n of collocation for the same error, so per step it is slower than the dense path up to
  n of about 128 .. 192 (validation/bench_stepper.py); banded is for high radial resolution. Its ``leading`` is the eigenvalue nearest the collocation
  leader at n = 24 (its discretised continuum has oscillatory members that can be less damped
  than the mode), by inverse iteration; the initial state (fluid at rest, displacement X) does
  not satisfy the interface rows (the impulsive start is a vortex sheet): the first step
  projects it, as the reduced form does by construction. sphere_coupled.py needs the reduced
  ODE (``load_response``, M = I) and uses collocation.

Collocation. Built from the radial Chebyshev operators of :mod:`.sphere_radial` (reused, not
re-derived): for
degree m and one component they give the index-1 differential-algebraic system

    M dv/dt = (L_fluid + K(t) L_stiffness) v,      K(t) = kappa (1 + 2 tau sin t)   (6.3f)

whose differential unknowns y are the vorticity omega (toroidal: u^Phi = g) at the interior
collocation nodes and the membrane displacement X, and whose algebraic unknowns z are the
streamfunction psi at every node and the boundary/interface values of omega (g). M is the
identity on y and zero on z, and L_stiffness has non-zero columns only at X (a part of y), so the
algebraic rows 0 = A_zy y + A_zz z + K S_zy y are solved once for all:

    z = Z0 y + K Z1 y,       Z0 = -A_zz^{-1} A_zy,   Z1 = -A_zz^{-1} S_zy,
    dy/dt = (L0 + K(t) L1) y,   L0 = A_yy + A_yz Z0,   L1 = A_yz Z1,

with A = L_fluid, S = L_stiffness. The time stepper then sees an ordinary differential system
with M = I, the implicit part L = L0 + kappa L1 (the mean stiffness) and the explicit part
f(t) N y, f(t) = 2 tau sin t, N = kappa L1. Its eigenvalues are the finite eigenvalues of the
pencil of sphere_radial (the natural modes at tau = 0).

Inviscid fluid (nu = 0): no fluid grid. The Y row is the Mathieu equation
X'' + lambda0^2 (1 + 2 tau sin t) X = 0 ((6.23), lambda0^2 = kappa m(m+1)(m-1)(m+2)/(2m+1)),
stepped as y = (X^Y, dX^Y/dt); X^Psi = X^Phi = 0 (a massless membrane without viscous drag
cannot hold a tangential load).

Exterior domain and its error. The exterior r > 1 is mapped, not truncated:
r = 1 + L (1/xi - 1) with xi in (0, 1] (sphere_radial, exterior_angle = 0; complex scaling is for
eigenvalues only, its matrices are complex and keep only Im s >= 0), with
L = max(1, exterior_scale_hint(nu, lambda0)). Potential flow is represented with geometric
convergence, the vortical tail exp(-beta (r - 1)) faster than any power of 1/n but not
geometrically. The real map also discretises the continuous spectrum of the unbounded fluid
(which starts at s = 0) into a cloud of slowly decaying, nearly real eigenvalues: it stands for
the algebraic long-time tail of the exact solution, and modes near the negative real axis
(zeta = nu / sqrt(kappa) above about 0.2, where the least damped modes approach the branch cut)
are not resolved (tests/test_sphere_radial.py). The stated spatial error of a system is the
relative change of its least damped oscillatory eigenvalue (Im s > ``OSCILLATORY`` |s| and
|s| > ``CONTINUUM_FLOOR`` lambda0, which leaves out the continuum cloud) between
n and n - ``N_STEP`` radial nodes; with ``n_radial=None`` n grows until it is below ``tol``.
Tested against the dispersion relation (tests/test_stepper_sphere.py): with tol = 1e-9 the
leading mode is within the stated error (<= 1e-9) for m = 2, 3 and zeta = 0.01, 0.1; on coarse
grids (n = 24, 32; actual errors 1e-5 .. 1e-7) the stated error is within a factor 30 of the
actual one.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sparse
import scipy.sparse.linalg as spla

from .._threads import one_blas_thread
from .._validate import (require_choice, require_int_in_range, require_nonnegative,
                         require_positive, require_real)
from ..errors import ConvergenceError, ParameterError
from ..models.sphere import lambda0_squared
from .chebyshev import clenshaw_curtis_weights
from .sphere_banded import BandedOperators, banded_operators
from .sphere_radial import (COMPONENTS, N_RADIAL_MAX, RadialOperators, exterior_scale_hint,
                            radial_operators)

N_START = 24            # first radial resolution tried (inner = outer nodes)
N_STEP = 8              # resolution increment, and the offset of the comparison grid
N_AUTO_MAX = 160        # largest resolution chosen automatically
OSCILLATORY = 0.05      # |Im s| / |s| above which an eigenvalue counts as oscillatory ...
CONTINUUM_FLOOR = 0.1   # ... and |s| / lambda0 above which it is not in the continuum cloud
ZETA_CUT = 0.2          # zeta above which modes near the branch cut are expected
RADIAL = ("auto", "collocation", "banded")   # radial discretisations (module docstring)
DEFAULT_RADIAL = "auto"
BANDED_FROM = 192       # 'auto': banded from this n_radial on (measured crossover: 128 .. 192)
assert BANDED_FROM > N_AUTO_MAX  # automatic resolutions stay on collocation
INVERSE_ITERATIONS = 40  # banded: inverse iterations for the mode (shift within ~1e-4)


@dataclass(frozen=True, kw_only=True, eq=False)
class DegreeSystem:
    """The semi-discrete system of one degree m and component: M dy/dt = L y + f(t) N y.

    ``radial = 'collocation'``: the reduced ODE of the collocation operators (M = I, dense L, N);
    ``radial = 'banded'``: the unreduced index-1 DAE of :mod:`.sphere_banded` (sparse M, L, N;
    y is its whole coefficient state v and ``operators`` the :class:`BandedOperators`).

    Attributes
    ----------
    m, component, kappa, nu, tau : physics (component 'poloidal' or 'toroidal').
    M, L, N : (n, n) matrices; L = L0 + kappa L1 (implicit), N = kappa L1 (explicit, scaled by
        ``forcing``); banded: M, L = L_fluid + kappa L_stiffness, N = kappa L_stiffness (CSR);
        ``forcing`` is f(t) = 2 tau sin t, or None when tau = 0 (then N is None).
    membrane : slice of y holding the membrane components ``membrane_names`` ('Y', 'Psi'),
        ('Phi',) or, inviscid, ('Y',) followed by dX^Y/dt.
    lambda0 : inviscid natural frequency sqrt(lambda0^2) of the degree.
    leading : least damped oscillatory eigenvalue of L (the dominant natural mode; i lambda0
        when inviscid; banded: the eigenvalue of the pencil (L, M) nearest the collocation
        leader at n = 24): its modulus is the time scale that sets the default step.
    n_inner, n_outer, exterior_scale : radial resolution and exterior map (0 when inviscid).
    spatial_error : estimated relative error of the least damped oscillatory eigenvalue (0 when
        inviscid: the Mathieu equation is exact).
    operators : the :class:`RadialOperators` it was reduced from, or the
        :class:`BandedOperators` (None when inviscid).
    radial : 'collocation' or 'banded' (see above).
    """

    m: int
    component: str
    kappa: float
    nu: float
    tau: float
    M: np.ndarray
    L: np.ndarray
    N: np.ndarray | None
    forcing: Callable[[float], float] | None
    membrane: slice
    membrane_names: tuple[str, ...]
    lambda0: float
    leading: complex
    n_inner: int
    n_outer: int
    exterior_scale: float
    spatial_error: float
    operators: RadialOperators | BandedOperators | None
    _reduction: "_Reduction | None"
    radial: str = "collocation"

    @property
    def size(self) -> int:
        """Length of the state y."""
        return self.L.shape[0]

    @property
    def load_response(self) -> np.ndarray:
        """B, shape (size, components): dy/dt = ... + B F for a membrane load F per unit area
        (components ``membrane_names``, the load -K (m-1)(m+2) X of the uniform model being one
        such F), so that L1 = -(m-1)(m+2) B on the membrane columns. Viscous collocation
        systems only (it is a column of the reduced ODE)."""
        if self._reduction is None:
            raise ParameterError("the load response needs a viscous system with "
                                 "radial='collocation' (the reduced ODE; the inviscid system "
                                 "has no fluid grid)")
        q1 = (self.m - 1) * (self.m + 2)
        cols = np.arange(self.membrane.start, self.membrane.stop)
        return self._reduction.L1[:, cols] / -q1

    def stiffness(self, t: float) -> float:
        """K(t) = kappa (1 + 2 tau sin t) (6.3f)."""
        return self.kappa * (1.0 + 2.0 * self.tau * np.sin(t))

    def initial_state(self, displacement) -> np.ndarray:
        """y at rest (zero vorticity, zero membrane velocity) with the given membrane displacement.

        ``displacement`` has one row per name in ``membrane_names`` (inviscid: the X^Y row only)
        and optional columns (independent solutions, e.g. the orders k of the degree).
        """
        X = np.asarray(displacement, dtype=float)
        names = self.membrane_names[:1] if self.nu == 0.0 else self.membrane_names
        if X.shape[0] != len(names):
            raise ParameterError(f"displacement shape {X.shape} is invalid: must have "
                                 f"{len(names)} row(s) ({', '.join(names)})")
        y = np.zeros((self.size,) + X.shape[1:])
        y[self.membrane.start:self.membrane.start + len(names)] = X
        return y

    def displacement(self, y: np.ndarray) -> np.ndarray:
        """The membrane displacement rows of y (X^Y, X^Psi), (X^Phi,) or, inviscid, (X^Y,)."""
        n = 1 if self.nu == 0.0 else len(self.membrane_names)
        return np.asarray(y)[self.membrane.start:self.membrane.start + n]

    def full_state(self, y: np.ndarray, t: float) -> np.ndarray:
        """The state v of :attr:`operators` (all radial unknowns) from y at time t (banded: y)."""
        if self.operators is None:
            raise ParameterError("the inviscid system has no radial state")
        if self._reduction is None:
            return np.array(y)
        return self._reduction.expand(np.asarray(y), self.stiffness(t))

    def energy(self, y: np.ndarray, t: float) -> tuple[float, float, float]:
        """(kinetic, elastic, dissipation rate) of a real state y at time t, per unit amplitude of
        an orthonormal harmonic (``derivations/sphere_energy.py``):

        E_kin = 1/2 int (c^2 psi^2/r^4 + c psi'^2/r^2) r^2 dr      (poloidal, c = m(m+1))
              = 1/2 int c g^2 r^2 dr                              (toroidal)
        E_el  = K q1 / 2 (X^Y^2 + c X^Psi^2)  or  K q1 c X^Phi^2 / 2
        D     = nu int c omega^2 dr  or  nu int (c^2 g^2 + c ((r g)')^2) dr,

        with q1 = (m-1)(m+2), integrals over 0 < r < infinity (Clenshaw-Curtis on both radial
        grids; banded: :meth:`BandedOperators.kinetic_dissipation`). At tau = 0,
        d(E_kin + E_el)/dt = -D. Inviscid: the potential flow r^m inside,
        r^-(m+1) outside has E_kin = (2m+1)/(2 m (m+1)) (dX^Y/dt)^2 and D = 0.
        """
        y = np.asarray(y, dtype=float)
        c, q1 = self.m * (self.m + 1), (self.m - 1) * (self.m + 2)
        K = self.stiffness(t)
        X = self.displacement(y)
        weights = (1.0,) if self.membrane_names[0] == "Y" else (c,)
        weights = weights + (c,) * (len(X) - 1)
        elastic = 0.5 * K * q1 * float(sum(w * x**2 for w, x in zip(weights, X)))
        if self.operators is None:
            velocity = float(np.asarray(y)[self.membrane.start + 1])
            return 0.5 * (2 * self.m + 1) / c * velocity**2, elastic, 0.0
        if self._reduction is None:
            kinetic, dissipation = self.operators.kinetic_dissipation(y)
            return kinetic, elastic, dissipation
        kinetic, dissipation = self._reduction.kinetic_dissipation(self.full_state(y, t))
        return kinetic, elastic, dissipation


class _Reduction:
    """Elimination of the algebraic unknowns of a RadialOperators system, and its quadrature."""

    def __init__(self, ops: RadialOperators) -> None:
        self.ops = ops
        diff = np.diag(ops.M) != 0
        self.d, self.a = np.flatnonzero(diff), np.flatnonzero(~diff)
        A, S = ops.L_fluid, ops.L_stiffness
        ix = np.ix_
        lu = sla.lu_factor(A[ix(self.a, self.a)])
        self.Z0 = -sla.lu_solve(lu, A[ix(self.a, self.d)])
        self.Z1 = -sla.lu_solve(lu, S[ix(self.a, self.d)])
        self.L0 = A[ix(self.d, self.d)] + A[ix(self.d, self.a)] @ self.Z0
        self.L1 = A[ix(self.d, self.a)] @ self.Z1
        if not (np.all(np.isfinite(self.L0)) and np.all(np.isfinite(self.L1))):
            raise ConvergenceError("eliminating the algebraic rows failed (singular constraint "
                                   "block): the radial resolution is too small or inconsistent")
        self._weights()

    def expand(self, y: np.ndarray, K: float) -> np.ndarray:
        v = np.zeros((self.ops.size,) + y.shape[1:])
        v[self.d] = y
        v[self.a] = self.Z0 @ y + K * (self.Z1 @ y)
        return v

    def _weights(self) -> None:
        """Quadrature weights of int_0^1 dr (inner) and int_1^inf dr (outer) on the nodes."""
        ops = self.ops
        n = 2 * ops.n_inner - 1
        # the inner integrands are even in r: half the Clenshaw-Curtis rule on [-1, 1] x 2
        self.w_inner = clenshaw_curtis_weights(n)[:ops.n_inner]
        xi = ops.xi_outer
        L = ops.exterior_scale
        w = clenshaw_curtis_weights(ops.n_outer - 1)
        live = xi > 0
        jac = np.zeros_like(xi)
        jac[live] = L / (2.0 * xi[live] ** 2)          # dr = L/(2 xi^2) dx, x = 2 xi - 1
        self.w_outer = w * jac
        self.r_outer = np.full_like(xi, np.inf)
        self.r_outer[live] = 1.0 + L * (1.0 / xi[live] - 1.0)

    def kinetic_dissipation(self, v: np.ndarray) -> tuple[float, float]:
        ops = self.ops
        c = ops.m * (ops.m + 1)
        u_in, u_out = ops.velocity(v)
        r_in, r_out = ops.r_inner, self.r_outer
        live = np.isfinite(r_out)
        if ops.component == "poloidal":
            # |u|^2 r^2 = (u^Y^2 + c u^Psi^2) r^2
            f_in = (u_in[0] ** 2 + c * u_in[1] ** 2) * r_in**2
            f_out = np.zeros_like(r_out)
            f_out[live] = (u_out[0][live] ** 2 + c * u_out[1][live] ** 2) * r_out[live] ** 2
            w_in = v[ops.blocks["omega_inner"]]
            w_out = v[ops.blocks["omega_outer"]]
            d_in, d_out = c * w_in**2, c * w_out**2
        else:
            g_in, g_out = u_in[0], u_out[0]
            f_in = c * g_in**2 * r_in**2
            f_out = np.zeros_like(r_out)
            f_out[live] = c * g_out[live] ** 2 * r_out[live] ** 2
            # (r g)' = g + r g'
            dg_in = ops._d_inner[0] @ g_in
            dg_out = ops._d_outer[0] @ g_out
            d_in = c**2 * g_in**2 + c * (g_in + r_in * dg_in) ** 2
            d_out = np.zeros_like(r_out)
            rl = r_out[live]
            d_out[live] = c**2 * g_out[live] ** 2 + c * (g_out[live] + rl * dg_out[live]) ** 2
        kinetic = 0.5 * (self.w_inner @ f_in + self.w_outer @ f_out)
        dissipation = ops.nu * (self.w_inner @ d_in + self.w_outer @ d_out)
        return float(kinetic), float(dissipation)


def oscillatory_leader(values: np.ndarray, floor: float) -> complex | None:
    """Least damped eigenvalue with Im s > OSCILLATORY |s| and |s| > floor (the nearly real
    discretised continuum near s = 0 is left out)."""
    osc = values[(values.imag > OSCILLATORY * np.abs(values)) & (np.abs(values) > floor)]
    return None if osc.size == 0 else complex(osc[np.argmax(osc.real)])


@lru_cache(maxsize=64)
def _reduced(m: int, nu: float, component: str, n: int, scale: float) -> _Reduction:
    ops = radial_operators(m=m, nu=nu, component=component, n_inner=n, n_outer=n,
                           exterior_scale=scale)
    return _Reduction(ops)


@lru_cache(maxsize=64)
def _banded(m: int, nu: float, component: str, n: int, scale: float) -> BandedOperators:
    return banded_operators(m=m, nu=nu, component=component, n_inner=n, n_outer=n,
                            exterior_scale=scale)


def _nearest_eigenvalue(A, B, shift: complex) -> complex:
    """The finite eigenvalue of s B v = A v nearest ``shift`` by inverse iteration with
    (A - shift B)^{-1} B (ratio |s - shift| / |s' - shift| per iteration, s' the next nearest;
    the infinite eigenvalues are removed by the first product with B)."""
    C = sparse.csc_matrix(A - shift * B, dtype=complex)
    lu = spla.splu(C, permc_spec="NATURAL", diag_pivot_thresh=0.0)
    x = np.random.default_rng(0).standard_normal(C.shape[0]) + 0j
    value = np.inf
    for _ in range(INVERSE_ITERATIONS):
        y = lu.solve(np.asarray(B @ x, dtype=complex))
        new = shift + np.vdot(x, x) / np.vdot(x, y)
        x = y / np.linalg.norm(y)
        if abs(new - value) <= 1e-15 * abs(new):
            break
        value = new
    return complex(new)


@lru_cache(maxsize=256)
def _leader(m, nu, component, n, scale, kappa, radial="collocation") -> complex | None:
    floor = CONTINUUM_FLOOR * np.sqrt(lambda0_squared(m, kappa))
    if radial == "banded":
        # the banded exterior's discretised continuum also has oscillatory members with
        # |s| ~ 0.1 .. 0.3 lambda0 (moving with n), so the least damped oscillatory eigenvalue
        # is not always the mode: the mode taken is the eigenvalue nearest the collocation
        # system's leader at n = N_START (a shift within ~1e-4 of it)
        guess = _leader(m, nu, component, N_START, scale, kappa)
        if guess is None:
            return None
        A, B = _banded(m, nu, component, n, scale).pencil(kappa)
        return _nearest_eigenvalue(A, B, guess)
    red = _reduced(m, nu, component, n, scale)
    return oscillatory_leader(np.linalg.eigvals(red.L0 + kappa * red.L1), floor)


def _resolve(m, kappa, nu, component, n_radial, scale, tol,
             radial="collocation") -> tuple[int, float, complex]:
    """(n, spatial error, leading oscillatory eigenvalue): n given, or the smallest
    n = N_START + j N_STEP meeting ``tol``."""
    candidates = [n_radial] if n_radial is not None else range(N_START, N_AUTO_MAX + 1, N_STEP)
    error = np.inf
    for n in candidates:
        fine = _leader(m, nu, component, n, scale, kappa, radial)
        coarse = _leader(m, nu, component, n - N_STEP, scale, kappa, radial)
        if fine is None or coarse is None:
            raise ConvergenceError(
                f"degree m = {m} ({component}) has no resolved oscillatory mode at zeta = "
                f"{nu / np.sqrt(kappa):.3g}: the real exterior map of the time stepper does not "
                "resolve modes near the branch cut (zeta above about 0.2)")
        error = abs(fine - coarse) / abs(fine)
        if n_radial is not None or error <= tol:
            return n, float(error), fine
    zeta = nu / np.sqrt(kappa)
    cause = (f"; at zeta = nu/sqrt(kappa) = {zeta:.3g} the least damped modes approach the branch "
             "cut, which the real exterior map of the time stepper does not resolve"
             if zeta > ZETA_CUT else "; pass a larger tol or n_radial")
    raise ConvergenceError(f"degree m = {m} ({component}): the radial discretisation did not reach "
                           f"tol = {tol:g} with n_radial <= {N_AUTO_MAX} (error {error:.1e})"
                           + cause)


def degree_system(*, m: int, kappa: float, nu: float, tau: float = 0.0,
                  component: str = "poloidal", n_radial: int | None = None,
                  tol: float = 1e-9, radial: str = DEFAULT_RADIAL) -> DegreeSystem:
    """The semi-discrete system of degree m (see the module docstring).

    Parameters
    ----------
    m : degree, 2..200. kappa : stiffness > 0. nu : viscosity >= 0 (0: the Mathieu ODE).
    tau : forcing amplitude (K(t) = kappa (1 + 2 tau sin t)); tau = 0 leaves out N.
    component : 'poloidal' or 'toroidal' (toroidal needs nu > 0).
    n_radial : inner and outer nodes each (>= 14); None chooses the smallest n = 24, 32, ...
        (<= 160) whose least damped oscillatory eigenvalue changes by <= ``tol`` (relative)
        against n - 8.
    tol : target relative spatial error of that eigenvalue.
    radial : 'auto' (collocation for n < BANDED_FROM, else banded), 'collocation' (reduced
        dense ODE, M = I) or 'banded' (sparse DAE of :mod:`.sphere_banded`, cost per step O(n);
        n_radial then counts the Chebyshev coefficients of each inner and outer unknown).
        Ignored when nu = 0.

    Raises
    ------
    ParameterError : an argument out of range.
    ConvergenceError : ``tol`` not reached, or no resolved oscillatory mode (zeta too large for
        the real exterior map).
    """
    m = require_int_in_range("m", m, 2, 200)
    kappa = require_positive("kappa", kappa)
    nu = require_nonnegative("nu", nu)
    tau = require_real("tau", tau)
    component = require_choice("component", component, COMPONENTS)
    tol = require_positive("tol", tol)
    radial = require_choice("radial", radial, RADIAL)
    if n_radial is not None:
        n_radial = require_int_in_range("n_radial", n_radial, 6 + N_STEP, N_RADIAL_MAX)
    if radial == "auto":
        radial = "banded" if n_radial is not None and n_radial >= BANDED_FROM else "collocation"
    lam = float(np.sqrt(lambda0_squared(m, kappa)))
    forcing = None if tau == 0.0 else (lambda t, tau=tau: 2.0 * tau * np.sin(t))
    if nu == 0.0:
        if component == "toroidal":
            raise ParameterError("nu = 0 is invalid for the toroidal component: without viscosity "
                                 "nothing holds a tangential displacement (X^Phi = 0)")
        L = np.array([[0.0, 1.0], [-lam**2, 0.0]])
        N = None if forcing is None else np.array([[0.0, 0.0], [-lam**2, 0.0]])
        return DegreeSystem(m=m, component=component, kappa=kappa, nu=nu, tau=tau, M=np.eye(2),
                            L=L, N=N, forcing=forcing, membrane=slice(0, 2),
                            membrane_names=("Y", "dY/dt"), lambda0=lam, leading=1j * lam,
                            n_inner=0, n_outer=0,
                            exterior_scale=0.0, spatial_error=0.0, operators=None,
                            _reduction=None)
    scale = max(1.0, exterior_scale_hint(nu=nu, s_scale=lam))
    with one_blas_thread():   # small dense matrices: threads only cost
        n, error, leading = _resolve(m, kappa, nu, component, n_radial, scale, tol, radial)
        if radial == "banded":
            return _banded_system(m, kappa, nu, tau, component, n, scale, error, leading, lam,
                                  forcing)
        red = _reduced(m, nu, component, n, scale)
    ops = red.ops
    mem = ops.blocks["membrane"]
    first = int(np.searchsorted(red.d, mem.start))
    names = ops.membrane_names
    return DegreeSystem(m=m, component=component, kappa=kappa, nu=nu, tau=tau,
                        M=np.eye(red.d.size), L=red.L0 + kappa * red.L1,
                        N=None if forcing is None else kappa * red.L1, forcing=forcing,
                        membrane=slice(first, first + len(names)), membrane_names=names,
                        lambda0=lam, leading=leading, n_inner=n, n_outer=n,
                        exterior_scale=scale, spatial_error=error, operators=ops,
                        _reduction=red)


def _banded_system(m, kappa, nu, tau, component, n, scale, error, leading, lam,
                   forcing) -> DegreeSystem:
    """The sparse DAE M dv/dt = (L_fluid + kappa L_stiffness) v + f(t) kappa L_stiffness v."""
    ops = _banded(m, nu, component, n, scale)
    stiff = (kappa * ops.L_stiffness).tocsr()
    return DegreeSystem(m=m, component=component, kappa=kappa, nu=nu, tau=tau, M=ops.M,
                        L=(ops.L_fluid + stiff).tocsr(), N=None if forcing is None else stiff,
                        forcing=forcing, membrane=ops.blocks["membrane"],
                        membrane_names=ops.membrane_names, lambda0=lam, leading=leading,
                        n_inner=n, n_outer=n, exterior_scale=scale, spatial_error=error,
                        operators=ops, _reduction=None, radial="banded")


@dataclass(frozen=True, kw_only=True, eq=False)
class DegreeBlock:
    """One system of a scene and the modes it carries: the columns of its state are the orders k
    of ``modes`` (all of degree ``system.m``), started from ``initial`` (size x len(modes))."""

    system: DegreeSystem
    modes: tuple[tuple[int, int], ...]
    initial: np.ndarray


def shape_coefficients(function, l_max: int) -> tuple[dict[tuple[int, int], float], list[str]]:
    """Real harmonic coefficients (degrees 2..l_max) of a displacement given as function(theta,
    phi), and warnings: degrees 0 and 1 are dropped (degree 0 changes the enclosed volume,
    which incompressibility forbids; degree 1 is a rigid translation with no restoring force),
    and a function not resolved by degree l_max is flagged.
    """
    from .shtns_adapter import grid

    g = grid(require_int_in_range("l_max", l_max, 2, 200))
    values = g.evaluate(function)
    coeffs = g.analyse(values)
    scale = max(np.max(np.abs(values)), 1e-300)
    warnings = []
    residual = np.max(np.abs(g.synthesise(coeffs) - values)) / scale
    if residual > 1e-8:
        warnings.append(f"the shape is not resolved by degrees <= l_max = {g.l_max} (relative "
                        f"residual {residual:.1e}): raise l_max")
    low = {mk: c for mk, c in coeffs.items() if mk[0] < 2 and abs(c) > 1e-12 * scale}
    if low:
        warnings.append("degrees 0 and 1 of the shape are left out (volume change and rigid "
                        f"translation): {', '.join(f'{mk}: {c:.3g}' for mk, c in low.items())}")
    kept = {mk: c for mk, c in coeffs.items() if mk[0] >= 2 and abs(c) > 1e-12 * scale}
    if not kept:
        raise ParameterError("the shape has no degree m >= 2 component: nothing would move")
    return kept, warnings


def scene_blocks(*, shape: dict[tuple[int, int], float], twist: dict[tuple[int, int], float],
                 kappa: float, nu: float, tau: float, n_radial: int | None = None,
                 tol: float = 1e-9, radial: str = DEFAULT_RADIAL) -> tuple[DegreeBlock, ...]:
    """The per-degree systems a uniform-kappa scene needs: one poloidal system per degree of the
    radial ``shape`` (its orders k as columns) and one toroidal system per degree of ``twist``
    (only if given; uniform kappa never excites X^Phi otherwise). Nothing else is allocated.
    """
    if nu == 0.0 and twist:
        raise ParameterError("initial.twist is invalid with nu = 0: without viscosity the "
                             "membrane cannot hold a tangential displacement")
    blocks = []
    for component, modes in (("poloidal", shape), ("toroidal", twist)):
        for m in sorted({mk[0] for mk in modes}):
            cols = tuple(sorted(mk for mk in modes if mk[0] == m))
            system = degree_system(m=m, kappa=kappa, nu=nu, tau=tau, component=component,
                                   n_radial=n_radial, tol=tol, radial=radial)
            X = np.zeros((1 if nu == 0.0 else len(system.membrane_names), len(cols)))
            X[0] = [modes[mk] for mk in cols]
            blocks.append(DegreeBlock(system=system, modes=cols,
                                      initial=system.initial_state(X)))
    if not blocks:
        raise ParameterError("the scene excites no mode: give initial.shape")
    return tuple(blocks)
