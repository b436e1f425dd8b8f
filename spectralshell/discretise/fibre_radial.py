"""Radial Chebyshev operators of one wavenumber m of the fibre: s M v = (L_fluid + K L_stiffness) v.

A second, independent discretisation of the linearised fibre of
``derivations/fibre_linear_result.md`` (thesis chapter 4): unsteady Stokes flow is collocated in r
inside and outside the unit circle instead of being solved with Bessel functions, as
:mod:`.sphere_radial` does for the sphere (same grids and exterior map,
:func:`.chebyshev.ball_derivatives`, :func:`.chebyshev.exterior_derivatives`). At K = kappa the
finite eigenvalues of the pencil are the natural modes, the zeros of det D(s); the same matrices
serve a time stepper in the form

    M dv/dt = (L_fluid + kappa L_stiffness + f(t) kappa L_pumped) v,   f(t) = 2 tau sin t,

where L_pumped holds the stress rows that carry K(t) (both, or only the pressure or the
tangential one: the ``forcing`` split of Fig 4.2). Every row is derived and checked in
``derivations/fibre_radial.py``.

Streamfunction. psi = f(r) sin(m theta), u^r = U cos(m theta), u^theta = V sin(m theta) with

    U = m f / r,     V = -f'        (the convention of the result file, V = -(r U)'/m),

so div u = 0 holds identically (no pressure unknown). With omega = L_m f,
L_m = d^2/dr^2 + (1/r) d/dr - m^2/r^2 (minus the vorticity's amplitude), the theta momentum row
gives the pressure P = r (nu omega' - s f')/m exactly, and the r row reduces to

    s omega = nu L_m omega,        L_m f = omega.

Solutions: f = r^m, r^-m (potential flow, harmonic pressure, omega = 0) and I_m(beta r),
K_m(beta r) (omega = beta^2 f), beta = sqrt(s/nu).

Rows ([[q]] = q(1+) - q(1-); ' = d/dr; membrane load -K E X, E = [[m^2, m], [m, m^2]] on
X = (X^r, X^theta)):

* [[f]] = 0 and [[f']] = 0: continuity of U and V at r = 1;
* nu [[omega']]/m + K (m^2 X^r + m X^theta) = 0: normal stress [[P]] - nu [[U']] = -K (E X)_r,
  since with the continuity rows [[P]] = nu [[omega']]/m and [[U']] = 0;
* nu [[omega]] + K (m X^r + m^2 X^theta) = 0: tangential stress -nu [[V']] = nu [[omega]];
* s X^r = m f(1-), s X^theta = -f'(1-): kinematics dX/dt = u(1);
* f = 0 and omega = 0 at xi = 0 (r = infinity): f = b r^-m + exponentially small;
* none at r = 0: f and omega are r^m times a series in r^2 (parity (-1)^m on [-1, 1]).

The equations L_m f = omega and s omega = nu L_m omega are collocated at the other nodes.

Exterior. x in [-1, 1] maps to r = 1 + L (1/xi - 1), xi = (1 + x)/2, L = ``exterior_scale``
(real: these operators are for time stepping). With L = 1 the potential part b r^-m = b xi^m is
a polynomial; the vortical tail K_m(beta r) ~ exp(-beta r) is flat at xi = 0 and converges faster
than any power of 1/n_outer. As for the sphere, modes close to the branch cut of beta (large
zeta = nu/sqrt(kappa)) are not resolved and the real map discretises the continuous spectrum into
a cloud of nearly real eigenvalues (:func:`spectralshell.solvers.eigen.least_damped` keeps the
eigenvalues that agree between two resolutions).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from .._validate import require_choice, require_int_in_range, require_positive, require_real
from ..errors import ParameterError
from ..params.fibre import FORCINGS, M_RANGE
from .chebyshev import ball_derivatives, exterior_derivatives
from .membrane_pencil import MembranePencil
from .sphere_radial import N_RADIAL_MAX, require_exterior_scale

MEMBRANE = ("r", "theta")


@dataclass(frozen=True, kw_only=True, eq=False)
class FibreRadialOperators(MembranePencil):
    """Radial operators of wavenumber m of the fibre, s M v = (L_fluid + K L_stiffness) v.

    The state v is the concatenation of the blocks ``f_inner``, ``f_outer`` (f at ``r_inner``
    and ``xi_outer``), ``omega_inner``, ``omega_outer`` (omega = L_m f at the same nodes) and
    ``membrane`` (X^r, X^theta). The rows follow the unknowns (f rows: L_m f = omega; omega
    rows: s omega = nu L_m omega), except that node 0 (r = 1) of the four blocks holds [[f]],
    [[f']], the normal and the tangential stress row, in that order, and the last outer node
    (xi = 0) of each outer block the condition at infinity; the membrane rows are the kinematics.

    Attributes
    ----------
    m, nu, n_inner, n_outer, exterior_scale : what was assembled.
    r_inner : (n_inner,) radii of the inner nodes, descending from 1 to > 0.
    xi_outer : (n_outer,) outer nodes as xi, from 1 (r = 1) to 0 (r = infinity).
    M, L_fluid : (size, size) real matrices (M is zero on the algebraic rows).
    L_pressure, L_tangential : the membrane term E X at unit stiffness in the normal and in the
        tangential stress row (L_stiffness = their sum).
    blocks : read-only mapping name -> slice of v.

    ``size``, ``pencil(kappa)`` (K = kappa) and ``displacement(v)`` (X^r, X^theta) come from
    :class:`.membrane_pencil.MembranePencil`.
    """

    m: int
    nu: float
    n_inner: int
    n_outer: int
    exterior_scale: float
    r_inner: np.ndarray
    xi_outer: np.ndarray
    M: np.ndarray
    L_fluid: np.ndarray
    L_pressure: np.ndarray
    L_tangential: np.ndarray
    blocks: Mapping[str, slice]

    @property
    def L_stiffness(self) -> np.ndarray:
        """The membrane term E X at unit stiffness, in both stress rows."""
        return self.L_pressure + self.L_tangential

    def pumped(self, forcing: str) -> np.ndarray:
        """The unit-stiffness membrane term in the rows that carry K(t): 'both', 'pressure' (normal stress
        row only) or 'tangential' (tangential stress row only)."""
        forcing = require_choice("forcing", forcing, FORCINGS)
        return {"both": self.L_stiffness, "pressure": self.L_pressure,
                "tangential": self.L_tangential}[forcing]


def fibre_radial_operators(*, m: int, nu: float, n_inner: int, n_outer: int,
                           exterior_scale: float = 1.0) -> FibreRadialOperators:
    """Assemble the radial Chebyshev operators of wavenumber m (rows: see the module docstring).

    Parameters
    ----------
    m : wavenumber, 2..200. nu : viscosity > 0.
    n_inner : inner unknowns per field (positive nodes of a Lobatto grid of degree
        2 n_inner - 1), >= 4.
    n_outer : outer unknowns per field (Lobatto grid of degree n_outer - 1 in xi), >= 6.
    exterior_scale : L of the exterior map r = 1 + L (1/xi - 1), in [1e-3, 1e3]
        (:func:`.sphere_radial.exterior_scale_hint` suggests one).

    Raises
    ------
    ParameterError : any argument outside its range.
    """
    m = require_int_in_range("m", m, *M_RANGE)
    nu = require_positive("nu", nu)
    ni = require_int_in_range("n_inner", n_inner, 4, N_RADIAL_MAX)
    no = require_int_in_range("n_outer", n_outer, 6, N_RADIAL_MAX)
    scale = require_exterior_scale(exterior_scale)
    r_in, d_in = ball_derivatives(ni, (-1) ** m)
    xi, rinv_out, d_out = exterior_derivatives(no, 0.0, scale)
    rinv_in = 1.0 / r_in

    def lm(d, rinv):
        return d[1] + rinv[:, None] * d[0] - m * m * np.diag(rinv**2)

    FI, FO = slice(0, ni), slice(ni, ni + no)
    WI, WO = slice(ni + no, 2 * ni + no), slice(2 * ni + no, 2 * (ni + no))
    ir, it = 2 * (ni + no), 2 * (ni + no) + 1
    size = it + 1
    M, L = np.zeros((size, size)), np.zeros((size, size))
    Sp, St = np.zeros((size, size)), np.zeros((size, size))
    ode_i, ode_o = np.arange(1, ni), np.arange(1, no - 1)
    for F, W, d, rinv, ode in ((FI, WI, d_in, rinv_in, ode_i), (FO, WO, d_out, rinv_out, ode_o)):
        lap = lm(d, rinv)[ode]
        L[F.start + ode, F] = lap                       # L_m f = omega (algebraic)
        L[F.start + ode, W.start + ode] = -1.0
        M[W.start + ode, W.start + ode] = 1.0           # s omega = nu L_m omega
        L[W.start + ode, W] = nu * lap
    r0, r1, r2, r3 = FI.start, FO.start, WI.start, WO.start
    L[r0, FI.start], L[r0, FO.start] = -1.0, 1.0                        # [[f]] = 0
    L[r1, FI], L[r1, FO] = -d_in[0][0], d_out[0][0]                     # [[f']] = 0
    L[r2, WI], L[r2, WO] = -nu / m * d_in[0][0], nu / m * d_out[0][0]   # nu [[omega']]/m
    Sp[r2, ir], Sp[r2, it] = m * m, m                                   #   + K (E X)_r = 0
    L[r3, WI.start], L[r3, WO.start] = -nu, nu                          # nu [[omega]]
    St[r3, ir], St[r3, it] = m, m * m                                   #   + K (E X)_theta = 0
    L[FO.stop - 1, FO.stop - 1] = 1.0                                   # f = 0 at xi = 0
    L[WO.stop - 1, WO.stop - 1] = 1.0                                   # omega = 0 at xi = 0
    M[ir, ir], L[ir, FI.start] = 1.0, m                                 # s X^r = m f(1)
    M[it, it], L[it, FI] = 1.0, -d_in[0][0]                             # s X^theta = -f'(1)
    return FibreRadialOperators(
        m=m, nu=nu, n_inner=ni, n_outer=no, exterior_scale=scale, r_inner=r_in, xi_outer=xi,
        M=M, L_fluid=L, L_pressure=Sp, L_tangential=St,
        blocks=MappingProxyType({"f_inner": FI, "f_outer": FO, "omega_inner": WI,
                                 "omega_outer": WO, "membrane": slice(ir, size)}))


@dataclass(frozen=True, kw_only=True, eq=False)
class FibreStepping:
    """The fibre's semi-discrete system M dv/dt = L v + f(t) N v of one wavenumber (a DAE).

    L = L_fluid + kappa L_stiffness (the mean stiffness, implicit), N = kappa L_pumped and
    f(t) = 2 tau sin t (explicit), so that the stress rows carry K(t) = kappa (1 + 2 tau sin t)
    where ``pumping`` says (both rows, or the pressure or the tangential one). M is singular
    (index 1: the algebraic rows fix f and the boundary values of omega given the interior
    omega and X); the steppers of :mod:`spectralshell.solvers.stepper` take it as it is. At
    tau = 0, N and the forcing are None.
    """

    operators: FibreRadialOperators
    kappa: float
    tau: float
    pumping: str
    M: np.ndarray
    L: np.ndarray
    N: np.ndarray | None
    forcing: Callable[[float], float] | None

    def initial_state(self, displacement) -> np.ndarray:
        """v with the membrane at ``displacement`` (X^r, X^theta) and the fluid at rest (the
        first step projects it onto the algebraic rows: the impulsive start)."""
        X = np.asarray(displacement, dtype=float)
        if X.shape != (2,):
            raise ParameterError(f"displacement shape {X.shape} is invalid: must be (2,) "
                                 "(X^r, X^theta)")
        v = np.zeros(self.operators.size)
        v[self.operators.blocks["membrane"]] = X
        return v

    def displacement(self, v: np.ndarray) -> np.ndarray:
        """(X^r, X^theta) of a state."""
        return self.operators.displacement(v)


def stepping_system(operators: FibreRadialOperators, *, kappa: float, tau: float,
                    pumping: str = "both") -> FibreStepping:
    """The time-stepping form of ``operators`` at stiffness K(t) = kappa (1 + 2 tau sin t).

    Raises
    ------
    ParameterError : kappa not positive, tau not real, pumping not 'both', 'pressure' or
        'tangential'.
    """
    kappa = require_positive("kappa", kappa)
    tau = require_real("tau", tau)
    pumped = operators.pumped(pumping)
    L, M = operators.pencil(kappa)
    forced = tau != 0.0
    return FibreStepping(operators=operators, kappa=kappa, tau=tau, pumping=pumping, M=M, L=L,
                         N=kappa * pumped if forced else None,
                         forcing=(lambda t: 2.0 * tau * np.sin(t)) if forced else None)
