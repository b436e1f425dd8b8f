"""Radial Chebyshev operators of one degree m of the sphere: s M v = (L_fluid + K L_stiffness) v.

A second, independent discretisation of the linearised model of
``derivations/sphere_linear_result.md`` (thesis 6.1-6.3, 7.1-7.2): the unsteady Stokes equations
are collocated in r inside and outside the unit sphere instead of being solved with Bessel
functions. At K = kappa the finite eigenvalues of the pencil are the natural modes, the roots of
det D(s) = 0 ((7.14); poloidal) and of D_Phi(s) = 0 (toroidal). The same matrices serve a time
stepper in the form

    M dv/dt = (L_fluid + K(t) L_stiffness) v,      K(t) = kappa (1 + 2 tau sin t),

where the rows with a zero row of M are algebraic (the streamfunction relation and the boundary
and interface conditions). L_stiffness is the membrane load at unit stiffness; its only entries
are in the stress rows. Every row is derived and checked in ``derivations/sphere_radial.py``.

Poloidal part (X^Y, X^Psi)
--------------------------
The velocity u = u^Y Yv + u^Psi Psi (VSH of the result file) is written with a poloidal
streamfunction psi(r) (u = curl curl (g Y r rhat), psi = r g),

    u^Y = c psi / r^2,     u^Psi = psi' / r,     c = m(m+1),

so div u = (r^2 u^Y)'/r^2 - c u^Psi/r = 0 holds identically: there is no pressure unknown and
hence no spurious pressure mode. With the vorticity-like omega = L_m psi,
L_m = d^2/dr^2 - c/r^2, the Psi row of s u = -grad p + nu Lap u ((6.20b)) gives the pressure
p = nu omega' - s psi' exactly, and the Y row then reduces to

    s omega = nu L_m omega,        L_m psi = omega,

a second-order diffusion equation for omega and an algebraic (elliptic) relation for psi. The
single fourth-order equation s L_m psi = nu L_m^2 psi is equivalent, but collocating it on the
exterior map gave an ill-conditioned pencil with spurious eigenvalues (eigenvalues moving by O(1)
between resolutions); the split form is as well behaved as the toroidal one. Solutions: psi =
r^{m+1}, r^{-m} (potential flow, p = a r^m, b r^{-(m+1)}, omega = 0) and r i_m(beta r),
r k_m(beta r) (omega = beta^2 psi), beta = sqrt(s/nu): the fields of the result file with
psi = r^2 u^Y / c.

Rows ([[q]] = q(1+) - q(1-); ' = d/dr; load -K q1 X with q1 = (m-1)(m+2), result file section 1):

* [[psi]] = 0 and [[psi']] = 0: continuity of u^Y and u^Psi at r = 1;
* -nu [[omega']] - K q1 X^Y = 0: normal stress -[[p]] + nu [[u^Y']] = K q1 X^Y, because with
  the two continuity rows [[p]] = nu [[omega']] and [[u^Y']] = 0;
* nu [[omega]] - K q1 X^Psi = 0: tangential stress nu [[u^Psi']] = nu [[psi'']] = K q1 X^Psi;
* s X^Y = c psi(1-), s X^Psi = psi'(1-): kinematics dX/dt = u(1);
* psi = 0 and omega = 0 at xi = 0 (r = infinity): psi = b r^{-m} + exponentially small;
* none at r = 0: psi and omega are r^{m+1} times a series in r^2, so they extend to [-1, 1]
  with parity (-1)^{m+1}; the inner unknowns are their values at the positive nodes of a
  Lobatto grid of odd degree 2 n_inner - 1 on [-1, 1] (:func:`.chebyshev.parity_fold`). Only
  regular solutions are representable and r = 0 is not a node.

The two equations are collocated at the other nodes: inner nodes 1.., outer nodes 1..N-1.

Toroidal part (X^Phi)
---------------------
u = g(r) Phi with s g = nu (g'' + 2 g'/r - c g/r^2) (Phi row of (6.20)); rows [[g]] = 0,
nu [[g']] - K q1 X^Phi = 0, s X^Phi = g(1-), g = 0 at xi = 0; inner parity (-1)^m; no pressure.

Exterior and its error
----------------------
Outside, x in [-1, 1] maps to r = 1 + L e^{i phi} (1/xi - 1), xi = (1 + x)/2
(:func:`.chebyshev.reciprocal_map`), L = ``exterior_scale``, phi = ``exterior_angle``. The domain
is not truncated. With L = 1, phi = 0, xi = 1/r and the potential part b xi^m is a polynomial
(represented exactly); for other L it is rational in xi with its pole off [0, 1] (geometric
convergence). The error outside is that of the vortical tail r k_m(beta r) ~ exp(-beta (r - 1)),
which has an essential singularity at xi = 0 (flat there): it converges faster than any power of
1/n_outer but not geometrically, and slowly when |L beta| is small or Re beta is small. A scale L
of about 8/|beta| (``exterior_scale_hint``) balances the boundary layer at r = 1 against the tail.

Near the negative real s axis, the branch cut of beta (large zeta = nu/sqrt(kappa)), Re beta -> 0
and for phi = 0 the tail stops decaying: the discrete spectrum then holds a cloud of eigenvalues
on and near the negative real axis (the discretised continuous spectrum of the unbounded fluid,
which starts at s = 0) and modes near the cut are not resolved. Those eigenvalues move when
n_outer changes, genuine modes do not: :func:`spectralshell.solvers.eigen.least_damped` keeps only
eigenvalues that agree between two resolutions. For modes near the cut use phi in (-pi/2, 0)
(exterior complex scaling): every tail with arg beta in [0, pi/2), i.e. every mode with
Im s >= 0, then decays along the path (Re(beta e^{i phi}) > 0), and those modes are unchanged,
since k_m(beta r) is entire in r and the interface rows see the same Q(beta). The continuous
spectrum rotates onto the ray arg s = pi - 2 phi (Im s < 0). Modes with Im s < 0 are not
reproduced and the matrices are complex, so phi != 0 is for eigenvalues only, never for time
stepping. Resolution measured for 1e-8 relative error:
``validation/bench_modes_chebyshev_resolution.py``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from .._validate import require_choice, require_int_in_range, require_positive, require_real
from ..errors import ParameterError
from .chebyshev import ball_derivatives, exterior_derivatives

COMPONENTS = ("poloidal", "toroidal")
MEMBRANE = {"poloidal": ("Y", "Psi"), "toroidal": ("Phi",)}
N_RADIAL_MAX = 2000
SCALE_RANGE = (1e-3, 1e3)


@dataclass(frozen=True, kw_only=True, eq=False)
class RadialOperators:
    """Per-degree radial operators of the sphere, s M v = (L_fluid + K L_stiffness) v.

    The state vector v is a concatenation of blocks (``blocks`` maps each name to its slice):

    * poloidal: ``psi_inner`` (psi at ``r_inner``), ``psi_outer`` (psi at ``xi_outer``),
      ``omega_inner``, ``omega_outer`` (omega = L_m psi at the same nodes), ``membrane``
      (X^Y, X^Psi);
    * toroidal: ``g_inner``, ``g_outer`` (u^Phi = g), ``membrane`` (X^Phi).

    The rows are ordered like the unknowns: the equation collocated at the nodes of a block sits
    in that block's rows (psi rows: L_m psi = omega; omega rows: s omega = nu L_m omega; g rows:
    s g = nu Lap_m g), except that each block's node-0 row (r = 1) and the last outer row
    (xi = 0) hold the boundary and interface conditions, in the order listed in the module
    docstring; the membrane rows are the kinematic equations.

    Attributes
    ----------
    m, nu, component, n_inner, n_outer, exterior_angle, exterior_scale : what was assembled.
    r_inner : (n_inner,) radii of the inner nodes, descending from r_inner[0] = 1 to > 0.
    xi_outer : (n_outer,) outer nodes as xi, descending from 1 (r = 1) to 0 (r = infinity); the
        radius is r = 1 + L e^{i phi} (1/xi - 1), so xi = 1/r for the default L = 1, phi = 0.
    M, L_fluid, L_stiffness : (size, size) matrices; L_stiffness is the load at unit stiffness
        (real, non-zero only in the two (one) stress rows).
    blocks : read-only mapping name -> slice of v.
    membrane_names : ('Y', 'Psi') or ('Phi',), the components in ``blocks['membrane']``.
    constraint_rows : indices of the algebraic rows (zero rows of M): the psi relation and all
        boundary and interface rows.
    """

    m: int
    nu: float
    component: str
    n_inner: int
    n_outer: int
    exterior_angle: float
    exterior_scale: float
    r_inner: np.ndarray
    xi_outer: np.ndarray
    M: np.ndarray
    L_fluid: np.ndarray
    L_stiffness: np.ndarray
    blocks: Mapping[str, slice]
    membrane_names: tuple[str, ...]
    constraint_rows: np.ndarray
    _d_inner: tuple[np.ndarray, ...]
    _d_outer: tuple[np.ndarray, ...]
    _rinv_inner: np.ndarray
    _rinv_outer: np.ndarray

    @property
    def size(self) -> int:
        """Length of the state vector v."""
        return self.M.shape[0]

    def pencil(self, kappa: float) -> tuple[np.ndarray, np.ndarray]:
        """(L, M) of the natural-mode problem s M v = L v at constant stiffness K = kappa."""
        kappa = require_positive("kappa", kappa)
        return self.L_fluid + kappa * self.L_stiffness, self.M

    def displacement(self, v: np.ndarray) -> np.ndarray:
        """Membrane displacement components (X^Y, X^Psi) or (X^Phi,) of a state vector."""
        return np.asarray(v)[self.blocks["membrane"]]

    def velocity(self, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Velocity components on the inner and outer nodes, shapes (k, n_inner), (k, n_outer).

        Poloidal: rows (u^Y, u^Psi) = (m(m+1) psi / r^2, psi' / r); toroidal: (u^Phi,) = g.
        Both vanish at xi = 0. With exterior_angle != 0 the outer values belong to the complex
        path, not to physical radii.
        """
        v = np.asarray(v)
        if self.component == "toroidal":
            return v[self.blocks["g_inner"]][None, :], v[self.blocks["g_outer"]][None, :]
        c = self.m * (self.m + 1)
        out = []
        for side, d, rinv in (("inner", self._d_inner, self._rinv_inner),
                              ("outer", self._d_outer, self._rinv_outer)):
            psi = v[self.blocks["psi_" + side]]
            out.append(np.stack([c * psi * rinv**2, (d[0] @ psi) * rinv]))
        return out[0], out[1]

    def pressure(self, v: np.ndarray, dvdt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pressure on the inner and outer nodes from a state v and its time derivative.

        Poloidal: p = nu omega' - (d psi/dt)', the Psi row of the momentum equation (6.20b) with
        (L_m psi)' = omega'; for an eigenvector pass ``dvdt = s v``. Toroidal: p = 0. The outer
        value at xi = 0 (r = infinity) is 0.
        """
        v, dvdt = np.asarray(v), np.asarray(dvdt)
        if self.component == "toroidal":
            dtype = np.result_type(v, dvdt)
            return np.zeros(self.n_inner, dtype), np.zeros(self.n_outer, dtype)
        out = []
        for side, d in (("inner", self._d_inner), ("outer", self._d_outer)):
            omega = v[self.blocks["omega_" + side]]
            out.append(self.nu * (d[0] @ omega) - d[0] @ dvdt[self.blocks["psi_" + side]])
        return out[0], out[1]


def _check(m, nu, component, n_inner, n_outer, exterior_angle, exterior_scale):
    m = require_int_in_range("m", m, 2, 200)
    nu = require_positive("nu", nu)
    component = require_choice("component", component, COMPONENTS)
    n_inner = require_int_in_range("n_inner", n_inner, 4, N_RADIAL_MAX)
    n_outer = require_int_in_range("n_outer", n_outer, 6, N_RADIAL_MAX)
    angle = require_real("exterior_angle", exterior_angle)
    if not -np.pi / 2 < angle <= 0.0:
        raise ParameterError(f"exterior_angle = {exterior_angle!r} is invalid: must be in "
                             "(-pi/2, 0] (0: real operators; negative: complex scaling that "
                             "keeps the modes with Im s >= 0)")
    return m, nu, component, n_inner, n_outer, angle, require_exterior_scale(exterior_scale)


def require_exterior_scale(value: object) -> float:
    """The exterior map's scale L (r = 1 + L (1/xi - 1)), checked to lie in SCALE_RANGE."""
    scale = require_real("exterior_scale", value)
    if not SCALE_RANGE[0] <= scale <= SCALE_RANGE[1]:
        raise ParameterError(f"exterior_scale = {value!r} is invalid: must be in "
                             f"[{SCALE_RANGE[0]:g}, {SCALE_RANGE[1]:g}]")
    return scale


def radial_operators(*, m: int, nu: float, component: str = "poloidal", n_inner: int,
                     n_outer: int, exterior_angle: float = 0.0,
                     exterior_scale: float = 1.0) -> RadialOperators:
    """Assemble the radial Chebyshev operators of degree m (see the module docstring for the rows).

    Parameters
    ----------
    m : degree, 2..200.
    nu : viscosity > 0 (the inviscid model has no radial structure).
    component : 'poloidal' or 'toroidal'.
    n_inner : inner unknowns (positive nodes of a Lobatto grid of degree 2 n_inner - 1), >= 4.
    n_outer : outer unknowns (Lobatto grid of degree n_outer - 1 in xi), >= 6.
    exterior_angle : phi of the exterior path r = 1 + L e^{i phi}(1/xi - 1), in (-pi/2, 0];
        0 gives real matrices (time stepping); e.g. -pi/3 for eigenvalues near the branch cut.
    exterior_scale : L of that path, in [1e-3, 1e3]; see :func:`exterior_scale_hint`.

    Raises
    ------
    ParameterError : any argument outside its range.
    """
    m, nu, component, n_inner, n_outer, angle, scale = _check(
        m, nu, component, n_inner, n_outer, exterior_angle, exterior_scale)
    build = _poloidal if component == "poloidal" else _toroidal
    return build(m, nu, n_inner, n_outer, angle, scale)


def exterior_scale_hint(*, nu: float, s_scale: float) -> float:
    """Suggested ``exterior_scale`` L = 8 sqrt(nu / s_scale) = 8/|beta|, clipped to [0.5, 8].

    ``s_scale`` is the expected |s| of the modes of interest (e.g. the inviscid frequency
    lambda0 of :func:`spectralshell.models.sphere.lambda0_squared`, or a previous estimate). The
    constant 8 and the clip are empirical (``validation/bench_modes_chebyshev_resolution.py``):
    the boundary layer 1/|beta| then spans about 1/8 of the map's unit length, which keeps both
    it and the tail resolved with a few dozen outer nodes for zeta = 1e-3 .. 1.

    Raises
    ------
    ParameterError : nu or s_scale not positive.
    """
    nu = require_positive("nu", nu)
    s_scale = require_positive("s_scale", s_scale)
    return float(np.clip(8.0 * np.sqrt(nu / s_scale), 0.5, 8.0))


def _poloidal(m: int, nu: float, n_inner: int, n_outer: int, angle: float,
              scale: float) -> RadialOperators:
    c, q1 = m * (m + 1), (m - 1) * (m + 2)
    r_in, d_in = ball_derivatives(n_inner, (-1) ** (m + 1))
    xi, rinv_out, d_out = exterior_derivatives(n_outer, angle, scale)
    rinv_in = 1.0 / r_in

    def lm(d, rinv):
        return d[1] - c * np.diag(rinv**2)

    ni, no = n_inner, n_outer
    PI, PO = slice(0, ni), slice(ni, ni + no)
    WI, WO = slice(ni + no, 2 * ni + no), slice(2 * ni + no, 2 * (ni + no))
    iy, ip = 2 * (ni + no), 2 * (ni + no) + 1
    size = ip + 1
    dtype = complex if angle else float
    M = np.zeros((size, size), dtype)
    L = np.zeros((size, size), dtype)
    S = np.zeros((size, size))
    ode_i, ode_o = np.arange(1, ni), np.arange(1, no - 1)
    # L_m psi = omega (algebraic) and s omega = nu L_m omega, at inner nodes 1.. and outer 1..N-1
    L[PI.start + ode_i, PI] = lm(d_in, rinv_in)[ode_i]
    L[PI.start + ode_i, WI.start + ode_i] = -1.0
    L[PO.start + ode_o, PO] = lm(d_out, rinv_out)[ode_o]
    L[PO.start + ode_o, WO.start + ode_o] = -1.0
    M[WI.start + ode_i, WI.start + ode_i] = 1.0
    L[WI.start + ode_i, WI] = nu * lm(d_in, rinv_in)[ode_i]
    M[WO.start + ode_o, WO.start + ode_o] = 1.0
    L[WO.start + ode_o, WO] = nu * lm(d_out, rinv_out)[ode_o]
    # interface r = 1 (node 0 of each block)
    r0, r1, r2, r3 = PI.start, PO.start, WI.start, WO.start
    L[r0, PI.start], L[r0, PO.start] = 1.0, -1.0                      # [[psi]] = 0
    L[r1, PI], L[r1, PO] = d_in[0][0], -d_out[0][0]                   # [[psi']] = 0
    L[r2, WI], L[r2, WO] = nu * d_in[0][0], -nu * d_out[0][0]         # -nu [[omega']]
    S[r2, iy] = -q1                                                   #   - K q1 X^Y = 0
    L[r3, WI.start], L[r3, WO.start] = -nu, nu                        # nu [[omega]]
    S[r3, ip] = -q1                                                   #   - K q1 X^Psi = 0
    # infinity, xi = 0 (last outer node): psi = 0, omega = 0
    L[PO.stop - 1, PO.stop - 1] = 1.0
    L[WO.stop - 1, WO.stop - 1] = 1.0
    # kinematics s X^Y = m(m+1) psi(1), s X^Psi = psi'(1)
    M[iy, iy], L[iy, PI.start] = 1.0, c
    M[ip, ip], L[ip, PI] = 1.0, d_in[0][0]
    constraint = np.flatnonzero(~M.any(axis=1))
    return RadialOperators(
        m=m, nu=nu, component="poloidal", n_inner=ni, n_outer=no, exterior_angle=angle,
        exterior_scale=scale,
        r_inner=r_in, xi_outer=xi, M=M, L_fluid=L, L_stiffness=S,
        blocks=MappingProxyType({"psi_inner": PI, "psi_outer": PO, "omega_inner": WI,
                                 "omega_outer": WO, "membrane": slice(iy, size)}),
        membrane_names=MEMBRANE["poloidal"], constraint_rows=constraint, _d_inner=d_in,
        _d_outer=d_out, _rinv_inner=rinv_in, _rinv_outer=rinv_out)


def _toroidal(m: int, nu: float, n_inner: int, n_outer: int, angle: float,
              scale: float) -> RadialOperators:
    c, q1 = m * (m + 1), (m - 1) * (m + 2)
    r_in, d_in = ball_derivatives(n_inner, (-1) ** m)
    xi, rinv_out, d_out = exterior_derivatives(n_outer, angle, scale)
    rinv_in = 1.0 / r_in

    def lap(d, rinv):
        return d[1] + 2 * rinv[:, None] * d[0] - c * np.diag(rinv**2)

    ni, no = n_inner, n_outer
    GI, GO = slice(0, ni), slice(ni, ni + no)
    ix = ni + no
    size = ix + 1
    dtype = complex if angle else float
    M = np.zeros((size, size), dtype)
    L = np.zeros((size, size), dtype)
    S = np.zeros((size, size))
    ode_i, ode_o = np.arange(1, ni), np.arange(1, no - 1)
    M[GI.start + ode_i, GI.start + ode_i] = 1.0                     # s g = nu Lap_m g
    L[GI.start + ode_i, GI] = nu * lap(d_in, rinv_in)[ode_i]
    M[GO.start + ode_o, GO.start + ode_o] = 1.0
    L[GO.start + ode_o, GO] = nu * lap(d_out, rinv_out)[ode_o]
    L[GI.start, GI.start], L[GI.start, GO.start] = 1.0, -1.0       # [[g]] = 0
    L[GO.start, GI], L[GO.start, GO] = -nu * d_in[0][0], nu * d_out[0][0]  # nu [[g']]
    S[GO.start, ix] = -q1                                           #   - K q1 X^Phi = 0
    L[GO.stop - 1, GO.stop - 1] = 1.0                               # g = 0 at xi = 0
    M[ix, ix], L[ix, GI.start] = 1.0, 1.0                           # s X^Phi = g(1)
    constraint = np.flatnonzero(~M.any(axis=1))
    return RadialOperators(
        m=m, nu=nu, component="toroidal", n_inner=ni, n_outer=no, exterior_angle=angle,
        exterior_scale=scale,
        r_inner=r_in, xi_outer=xi, M=M, L_fluid=L, L_stiffness=S,
        blocks=MappingProxyType({"g_inner": GI, "g_outer": GO, "membrane": slice(ix, size)}),
        membrane_names=MEMBRANE["toroidal"], constraint_rows=constraint, _d_inner=d_in,
        _d_outer=d_out, _rinv_inner=rinv_in, _rinv_outer=rinv_out)
