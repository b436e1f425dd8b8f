"""Vertical Chebyshev operators of the cochlea's cosine modes: s M v = (L_fluid + K L_stiffness) v.

A second, independent discretisation of the linearised cochlea of
``derivations/cochlea_linear_result.md`` (thesis chapter 5): per cosine mode cos(k x) the unsteady
Stokes flow above the membrane is collocated in y on a mapped semi-infinite Chebyshev grid
instead of being solved in closed form (the transfer function Z_k(s) of
:func:`spectralshell.models.cochlea.transfer`); the modes couple only through the stiffness
profile e^{-alpha x} in the membrane rows (the matrix C of
:func:`spectralshell.models.cochlea.coupling_matrix`, the one piece of the model used). At
K = kappa the finite eigenvalues of the pencil are the natural modes, the zeros of
det(diag(Z_k(s)) + kappa C); the same matrices serve a time stepper in the form

    M dv/dt = (L_fluid + kappa L_stiffness + f(t) kappa L_stiffness) v,   f(t) = 2 tau sin t,

i.e. K(t) = kappa e^{-alpha x} (1 + 2 tau sin t). Every row is derived and checked in
``derivations/cochlea_vertical.py``.

Symmetry. The flow is antisymmetric about the membrane (u and p odd in y, v even: the reflection
(u, v, p)(x, y) -> (-u, v, -p)(x, -y) maps solutions with the membrane conditions u = 0,
v = h_t on both sides onto themselves), so only y >= 0 is discretised and [[p]] = 2 p(0+).

Streamfunction. Per mode k >= 1, psi = f(y) sin(k x), u = psi_y = f' sin(k x),
v = -psi_x = -k f cos(k x) (div u = 0 identically; u = 0 and v_x = 0 at the walls x = 0, pi).
With omega = L_k f, L_k = d^2/dy^2 - k^2 (minus the vorticity's amplitude), the x momentum row
gives the pressure p = P cos(k x), P = (s f' - nu omega')/k, and the y row reduces to

    s omega = nu L_k omega,        L_k f = omega.

Solutions: f = e^{-k y} (potential flow) and e^{-beta y}, beta = sqrt(s/nu + k^2) (omega =
(s/nu) f).

Rows at the membrane y = 0 (h = sum_k h_k cos(k x); K h = kappa (C h)_k in mode k):

* f'(0) = 0: no slip, u = 0;
* -2 nu omega'(0)/k + K (C h)_k = 0: the normal stress [[p]] = -K h (the viscous normal stress
  2 nu v_y = -2 nu k f' cos(k x) vanishes with u = 0), since P(0) = -nu omega'(0)/k when
  f'(0) = 0 at all times;
* s h_k = -k f(0): kinematics dh/dt = v(0);
* f = 0 and omega = 0 at xi = 0 (y = infinity): the decaying fields e^{-k y}, e^{-beta y}.

The equations L_k f = omega and s omega = nu L_k omega are collocated at the other nodes.

Vertical map. x in [-1, 1] maps to y = L (1/xi - 1), xi = (1 + x)/2, L = ``vertical_scale``
(:func:`.chebyshev.exterior_derivatives` with r = 1 + y): both e^{-k y} and the Stokes layer
e^{-beta y} are flat at xi = 0 and converge faster than any power of 1/n_vertical; L = 1 to 2
suits the potential parts of the first modes (measured: natural modes to 2e-11 at n_vertical =
64, M = 4..6, kappa = 0.5, nu = 1e-3, alpha = 1). The real map discretises the continuous
spectrum s <= -nu k^2 into a cloud of nearly real eigenvalues near -nu k^2.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from .._validate import require_int_in_range, require_nonnegative, require_positive, require_real
from ..errors import ParameterError
from ..models.cochlea import coupling_matrix
from ..params.cochlea import MODE_RANGE
from .chebyshev import exterior_derivatives
from .membrane_pencil import MembranePencil
from .sphere_radial import N_RADIAL_MAX, require_exterior_scale

N_VERTICAL_MIN = 6


@dataclass(frozen=True, kw_only=True, eq=False)
class CochleaVerticalOperators(MembranePencil):
    """Vertical operators of the cochlea's cosine modes 1..M: s M v = (L_fluid + K L_stiffness) v.

    The state v is the concatenation, for k = 1..M, of the blocks ``f<k>`` and ``omega<k>`` (f
    and omega = L_k f at the nodes ``xi``), then ``membrane`` (h_1..h_M). The rows follow the
    unknowns (f rows: L_k f = omega; omega rows: s omega = nu L_k omega), except that node 0
    (y = 0) of f<k> holds f'(0) = 0 and of omega<k> the normal stress row, and the last node
    (xi = 0) of each block the condition at infinity; the membrane rows are the kinematics.

    Attributes
    ----------
    n_spatial, nu, alpha, n_vertical, vertical_scale : what was assembled.
    xi : (n_vertical,) nodes as xi, from 1 (y = 0) to 0 (y = infinity).
    M, L_fluid : (size, size) real matrices (M is zero on the algebraic rows).
    L_stiffness : the membrane term C h at unit stiffness in the stress rows.
    blocks : read-only mapping name -> slice of v.

    ``size``, ``pencil(kappa)`` (stiffness kappa e^{-alpha x}) and ``displacement(v)``
    (h_1, ..., h_M) come from :class:`.membrane_pencil.MembranePencil`.
    """

    n_spatial: int
    nu: float
    alpha: float
    n_vertical: int
    vertical_scale: float
    xi: np.ndarray
    M: np.ndarray
    L_fluid: np.ndarray
    L_stiffness: np.ndarray
    blocks: Mapping[str, slice]


def cochlea_vertical_operators(*, n_spatial: int, nu: float, alpha: float, n_vertical: int,
                               vertical_scale: float = 1.0) -> CochleaVerticalOperators:
    """Assemble the vertical Chebyshev operators of cosine modes 1..n_spatial (module docstring).

    Parameters
    ----------
    n_spatial : number M of cosine modes (1..2000). nu : viscosity > 0. alpha : stiffness
        grading >= 0 (K = kappa e^{-alpha x}).
    n_vertical : unknowns per field and mode (Lobatto grid of degree n_vertical - 1 in xi), >= 6.
    vertical_scale : L of the map y = L (1/xi - 1), in [1e-3, 1e3].

    Raises
    ------
    ParameterError : any argument outside its range.
    """
    M_modes = require_int_in_range("n_spatial", n_spatial, *MODE_RANGE)
    nu = require_positive("nu", nu)
    alpha = require_nonnegative("alpha", alpha)
    n = require_int_in_range("n_vertical", n_vertical, N_VERTICAL_MIN, N_RADIAL_MAX)
    try:
        scale = require_exterior_scale(vertical_scale)
    except ParameterError as exc:
        raise ParameterError(str(exc).replace("exterior_scale", "vertical_scale")) from None
    xi, _, (d1, d2) = exterior_derivatives(n, 0.0, scale)
    C = coupling_matrix(np.arange(1, M_modes + 1), alpha)
    membrane = slice(2 * n * M_modes, 2 * n * M_modes + M_modes)
    size = membrane.stop
    M, L, S = np.zeros((size, size)), np.zeros((size, size)), np.zeros((size, size))
    ode = np.arange(1, n - 1)
    blocks = {}
    for j in range(M_modes):
        k = j + 1
        F, W = slice(2 * n * j, 2 * n * j + n), slice(2 * n * j + n, 2 * n * (j + 1))
        blocks[f"f{k}"], blocks[f"omega{k}"] = F, W
        lap = (d2 - k * k * np.eye(n))[ode]
        L[F.start + ode, F] = lap                       # L_k f = omega (algebraic)
        L[F.start + ode, W.start + ode] = -1.0
        M[W.start + ode, W.start + ode] = 1.0           # s omega = nu L_k omega
        L[W.start + ode, W] = nu * lap
        L[F.start, F] = d1[0]                           # f'(0) = 0 (no slip)
        L[W.start, W] = -2.0 * nu / k * d1[0]           # -2 nu omega'(0)/k
        S[W.start, membrane] = C[j]                     #   + K (C h)_k = 0
        L[F.stop - 1, F.stop - 1] = 1.0                 # f = 0 at xi = 0
        L[W.stop - 1, W.stop - 1] = 1.0                 # omega = 0 at xi = 0
        M[membrane.start + j, membrane.start + j] = 1.0     # s h_k = -k f(0)
        L[membrane.start + j, F.start] = -k
    blocks["membrane"] = membrane
    return CochleaVerticalOperators(
        n_spatial=M_modes, nu=nu, alpha=alpha, n_vertical=n, vertical_scale=scale, xi=xi, M=M,
        L_fluid=L, L_stiffness=S, blocks=MappingProxyType(blocks))


@dataclass(frozen=True, kw_only=True, eq=False)
class CochleaStepping:
    """The cochlea's semi-discrete system M dv/dt = L v + f(t) N v (a DAE).

    L = L_fluid + kappa L_stiffness (the mean stiffness, implicit), N = kappa L_stiffness and
    f(t) = 2 tau sin t (explicit), so that the stress rows carry
    K(t) = kappa e^{-alpha x} (1 + 2 tau sin t). M is singular (index 1: the algebraic rows fix
    f and the boundary values of omega given the interior omega and h); the steppers of
    :mod:`spectralshell.solvers.stepper` take it as it is. At tau = 0, N and the forcing are None.
    """

    operators: CochleaVerticalOperators
    kappa: float
    tau: float
    M: np.ndarray
    L: np.ndarray
    N: np.ndarray | None
    forcing: Callable[[float], float] | None

    def displacement(self, v: np.ndarray) -> np.ndarray:
        """(h_1, ..., h_M) of a state."""
        return self.operators.displacement(v)


def stepping_system(operators: CochleaVerticalOperators, *, kappa: float,
                    tau: float) -> CochleaStepping:
    """The time-stepping form of ``operators`` at K(t) = kappa e^{-alpha x} (1 + 2 tau sin t).

    Raises
    ------
    ParameterError : kappa not positive, tau not real.
    """
    kappa = require_positive("kappa", kappa)
    tau = require_real("tau", tau)
    L, M = operators.pencil(kappa)
    forced = tau != 0.0
    return CochleaStepping(operators=operators, kappa=kappa, tau=tau, M=M, L=L,
                           N=kappa * operators.L_stiffness if forced else None,
                           forcing=(lambda t: 2.0 * tau * np.sin(t)) if forced else None)
