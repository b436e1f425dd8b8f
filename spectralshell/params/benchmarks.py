"""Benchmark problems for immersed-boundary and FSI codes: their definitions and parameters.

A :class:`BenchmarkProblem` names a problem, lists its physical inputs (cgs, with defaults), the
quantities a code reports (with units) and holds its one-page specification text; the reference
data are computed by :mod:`spectralshell.runner.benchmark`. Problems are registered in
:data:`BENCHMARKS` only once their reference computation exists (issue 29:
fibre-parametric offers the Floquet quantities only; fibre-release is computed by exact Laplace
inversion; the fibre's time stepper, runner/fibre_stepping, fits growth rates and writes no
series).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from .._validate import require_int_in_range, require_nonnegative, require_positive
from ..errors import ParameterError
from .physical import COCHLEA_UNITS, PHYSICAL_UNITS, TABLE_5_1, PhysicalSphere, fibre_forced

#: sigma* = IB_SPRING_FACTOR sigma: thesis 6.4.1 (six springs per node, small spring length).
IB_SPRING_FACTOR = math.log(3.0) / 2.0
#: zeta of sphere-release: the range whose corners (l = 2..12) the tests check against the
#: dispersion relation to 1e-8.
ZETA_RANGE = (1e-3, 0.06)
#: nu at an end of a range, as the user's cgs values give it, may be off by rounding.
RANGE_RTOL = 1e-12
#: sphere-parametric's relative distance of tau from tau_min: tau = (1 -+ margin) tau_min.
MARGIN_RANGE = (0.02, 0.5)


@dataclass(frozen=True)
class Quantity:
    """A reported time series: CSV column ``name``, its ``units`` and what it is."""

    name: str
    units: str
    description: str


@dataclass(frozen=True, kw_only=True)
class BenchmarkProblem:
    """A named benchmark problem.

    name : registry key (the CLI's NAME). title : one line. inputs : {name: units} of the
    parameters a user may change. defaults : their default values. quantities : the time
    series of the reference (after the time column ``t`` in s). specification : the one-page
    text (format fields: the parameters and derived values of :func:`specification`).
    reference : how the reference data are computed (one paragraph).
    """

    name: str
    title: str
    inputs: Mapping[str, str]
    defaults: Mapping[str, float]
    quantities: tuple[Quantity, ...]
    specification: str
    reference: str
    l_max: int = 12
    nu_range: tuple[float, float] | None = None
    rate_only: tuple[Quantity, ...] = ()
    zeta_range: tuple[float, float] = ZETA_RANGE
    omega_range: tuple[float, float] | None = None


#: The last part of every sphere specification: the IB spring constant and the reference.
IB_SPRING_SPEC = """\
Immersed-boundary spring constant (thesis 6.4.1). A triangulated membrane whose nodes are joined
by Hookean springs (force sigma* (X_i - X_j) per link) represents F = sigma Delta_S X with
    sigma* = (ln 3 / 2) sigma = {sigma_star:.10g} dyn/cm,
assuming: the spring length Delta s is small against R; the membrane is near its spherical
equilibrium; the stiffness is uniform; every node has six neighbours (nodes with five or
seven links, unavoidable on a sphere, make the force slightly non-uniform). The relation comes
from a midpoint-rule quadrature of the force on one node's hexagonal patch near the pole; it
is approximate, not exact in Delta s (the factor is half the patch integral of sec xi over
|xi| < pi/6, ln(sqrt 3); re-derived, and checked by quadrature in the tests). It does not
involve the fluid, and with a stiffness K(t) varying in time alone it holds at every instant:
sigma*(t) = (ln 3 / 2) K(t).

Reference data: {reference}
"""

SPHERE_RELEASE_SPEC = """\
sphere-release: a viscous sphere released from rest with a small (l, k) shape

Physical problem (cgs units). A closed elastic membrane of equilibrium radius R = {radius:g} cm
is immersed in an unbounded incompressible Newtonian fluid of density rho = {rho:g} g/cm^3 and
viscosity mu = {mu:g} g/(cm s), the same fluid inside and outside, fluid at rest at infinity. The
membrane force per unit (unit-sphere) parameter area is F = sigma Delta_S X (thesis (6.2)), with
stiffness sigma = {sigma:g} dyn/cm (= g/s^2); the membrane is massless and moves with the fluid
(dX/dt = u(X)); the force enters the fluid as f = int F delta(x - X) dOmega (thesis (6.1)). At
t = 0 the fluid is at rest and the membrane has the shape
    r(theta, phi, 0) = R + A0 Yr_{{l,k}}(theta, phi),   A0 = epsilon R = {amplitude:g} cm,
with l = {l}, k = {k}, theta the polar angle, phi the azimuth, and Yr_{{l,k}} the real orthonormal
spherical harmonic (int Yr^2 dOmega = 1 over the unit sphere): Yr_{{l,0}} = Y_l^0,
Yr_{{l,k}} = sqrt(2) Re Y_l^k and Yr_{{l,-k}} = sqrt(2) Im Y_l^k for k > 0 (Y_l^k with the
Condon-Shortley phase). The membrane then oscillates and decays back to the sphere.

Dimensionless form (thesis 7.2). Lengths in R, time in T = sqrt(rho R^3 / sigma) = {T:.10g} s,
so that kappa = 1 and the only parameter is zeta = mu / sqrt(rho R sigma) = {zeta:.10g}
(the viscosity nu of (6.3) with kappa = 1; references are offered for zeta in [0.001, 0.06],
2 <= l <= 12). The problem is linear in epsilon: the reference is
the linearised solution (epsilon -> 0) scaled to epsilon = {epsilon:g}; a nonlinear code should
use a small epsilon (the thesis's IB runs: 0.05 of max |Yr|) and compare after scaling.

Reported quantities (CSV columns after t in s):
  amplitude    cm    A(t) = int (r(theta, phi, t) - R) Yr_{{l,k}} dOmega, the membrane's modal
                     amplitude (the projection X^r of thesis 6.4.2 times R, linearised)
  u_r_pole     cm/s  radial velocity of the membrane at the pole theta = 0 (left out when
                     Yr_{{l,k}} vanishes there, k != 0)
  u_r_equator  cm/s  radial velocity at theta = pi/2, phi = 0 (left out when Yr vanishes there)
  pressure_jump          dyn/cm^2  P(t) = int (p_in - p_out - 2 sigma / R) Yr_{{l,k}} dOmega,
                                   the modal amplitude of the pressure jump across the membrane
                                   (inside minus outside, the equilibrium jump 2 sigma / R left out)
  pressure_jump_pole     dyn/cm^2  p_in - p_out - 2 sigma / R at theta = 0 (left out as u_r_pole)
  pressure_jump_equator  dyn/cm^2  the same at theta = pi/2, phi = 0 (left out as u_r_equator)
The pressure jump of the linearised problem is fixed by the normal stress balance at the
membrane (thesis (6.17), Laplace's law for the perturbed sphere): the viscous normal stress
2 mu du_r/dr does not jump (the velocity is continuous and divergence free on both sides), so
    p_in - p_out - 2 sigma / R = sigma (l - 1)(l + 2) A(t) Yr_{{l,k}} / R^2,
in phase with the amplitude ((l - 1)(l + 2) sigma / R^2 = {jump_factor:.10g} dyn/cm^3). An IB code
spreads the jump over its kernel's width: compare the difference of pressures sampled just
inside and just outside the membrane, or the jump of a fit on either side.

Exact late-time behaviour. After the continuous-spectrum transient of the unbounded fluid, A(t)
decays as exp(gamma t) cos(omega_d t + phase) with gamma + i omega_d the least damped natural
mode of degree l (the dispersion relation, thesis 7.2):
  growth rate gamma = {growth_rate:.12g} 1/s, angular frequency omega_d = {frequency:.12g} rad/s
  (dimensionless: {growth_rate_nd:.12g} and {frequency_nd:.12g} per T).
The inviscid (Lamb) frequency for comparison: {lamb:.10g} rad/s. At very late times the
algebraic tail of the continuous spectrum dominates the decayed mode; the reference covers
the mode's decay by about exp(-{efolds:g}) after the transient.

""" + IB_SPRING_SPEC

SPHERE_RELEASE = BenchmarkProblem(
    name="sphere-release",
    title="viscous sphere released from rest with a small (l, k) shape: decaying oscillation",
    inputs={**{k: PHYSICAL_UNITS[k] for k in ("rho", "mu", "radius", "sigma")},
            "l": "degree", "k": "order", "epsilon": "A0 / R"},
    # Table 6.1, case 1 (the thesis's IB simulations of 6.4.2): zeta = 0.0424
    defaults={"rho": 1.0, "mu": 0.006, "radius": 1.0, "sigma": 0.02, "l": 2, "k": 0,
              "epsilon": 0.05},
    quantities=(Quantity("amplitude", "cm", "modal amplitude A(t) of Yr_{l,k}"),
                Quantity("u_r_pole", "cm/s", "radial membrane velocity at theta = 0"),
                Quantity("u_r_equator", "cm/s",
                         "radial membrane velocity at theta = pi/2, phi = 0"),
                Quantity("pressure_jump", "dyn/cm^2",
                         "modal amplitude of p_in - p_out - 2 sigma / R over Yr_{l,k}"),
                Quantity("pressure_jump_pole", "dyn/cm^2",
                         "p_in - p_out - 2 sigma / R at theta = 0"),
                Quantity("pressure_jump_equator", "dyn/cm^2",
                         "p_in - p_out - 2 sigma / R at theta = pi/2, phi = 0")),
    specification=SPHERE_RELEASE_SPEC,
    reference=("the linearised equations are time-stepped per degree (radial Chebyshev "
               "collocation inside and outside the sphere, reduced to an ODE, SBDF4; "
               "runner/benchmark.py). The error bound of each sample is |fine - half the "
               "steps| + |fine - 8 fewer radial nodes|; the late-time decay rate and frequency "
               "fitted from the reference agree with the dispersion relation to 1e-8 (tests)."),
)

#: How the Floquet quantities of the parametric problems are computed.
HILL_REFERENCE = ("Floquet exponents by Hill's method (truncation raised until they change by "
                  "less than 1e-10; the list proved complete by the argument principle); the "
                  "eigen-shape is the null vector of the truncated Hill matrix")


def _below_above(name: str, units: str, description: str) -> tuple[Quantity, ...]:
    """The quantity ``name`` of a parametric problem's two runs: name_below, name_above."""
    return tuple(Quantity(f"{name}_{case}", units, f"{description} at tau_{case}")
                 for case in ("below", "above"))


SPHERE_PARAMETRIC_SPEC = """\
sphere-parametric: the viscous sphere with a periodic stiffness, just below and just above the
onset of parametric resonance

Physical problem (cgs units). The membrane and fluid of sphere-release (radius R = {radius:g} cm,
density rho = {rho:g} g/cm^3, viscosity mu = {mu:g} g/(cm s), F = K Delta_S X, the membrane
massless and moving with the fluid), with a stiffness that varies in time, uniformly over the
membrane (thesis (6.3f)):
    K(t) = sigma (1 + 2 tau sin(omega t)),  sigma = {sigma:g} dyn/cm, omega = {omega:g} rad/s
(forcing period 2 pi / omega = {forcing_period:.10g} s; tau < 1/2 keeps K > 0). At t = 0 the
fluid is at rest and the membrane has the shape r = R + A0 Yr_{{l,k}}(theta, phi),
A0 = epsilon R = {amplitude:g} cm, l = {l}, k = {k} (Yr_{{l,k}} as in sphere-release). Two runs:
    tau_below = (1 - {margin:g}) tau_min = {tau_below:.12g}
    tau_above = (1 + {margin:g}) tau_min = {tau_above:.12g}
where tau_min = {tau_min:.12g} is the smallest forcing amplitude at which degree l resonates
(the tip of its lowest, {kind}, tongue; the Floquet stability of thesis chapter 6). The order
k does not matter (the linear problem depends on l only). tau_below must lie in the band just
below tau_min where the least stable exponent is locked to the forcing (a periodic
eigen-shape); the band narrows with nu, so a small nu needs a small margin.

Dimensionless form (thesis (6.4)-(6.5)). Lengths in R, time in 1 / omega:
kappa = sigma / (rho R^3 omega^2) = {kappa:.10g}, nu = mu / (rho R^2 omega) = {nu:.10g},
K(t) = kappa (1 + 2 tau sin t) (references are offered for nu in [0.001, 0.006] and l = 2..6).
The problem is linear in epsilon: the reference is the linearised solution scaled to
epsilon = {epsilon:g}; a nonlinear code sees the linear growth until the amplitude is large
(thesis 6.4.2: nonlinear effects then bend the growth), so compare early and scale.

Reported quantities (CSV columns after t in s):
  amplitude_below  cm  A(t) = int (r(theta, phi, t) - R) Yr_{{l,k}} dOmega at tau_below
  amplitude_above  cm  the same at tau_above
over {periods} forcing periods.

Exact Floquet quantities. After the transient (the other Floquet solutions and the fluid's
continuous spectrum decay), A(t) = c exp(g t) p(t): p is periodic with the period
{shape_period:.10g} s (twice the forcing period for a subharmonic response, which oscillates
at omega / 2; the forcing period for a harmonic one) and
g = omega Re gamma, gamma the least stable Floquet exponent of degree l (Hill's method on the
exact fluid equations, thesis (6.28)-(6.30); spectralshell exponents sphere):
  tau_below: g = {rate_below:.12g} 1/s ({rate_below_nd:.12g} omega), growth per forcing
             period exp(2 pi g / omega) = {growth_below:.12g} (decay)
  tau_above: g = {rate_above:.12g} 1/s ({rate_above_nd:.12g} omega), growth per forcing
             period {growth_above:.12g} (growth)
A code must see decay below and growth above, at these rates. The periodic eigen-shape p(t)
(the radial component, max |p| = 1, t from a forcing phase of 0) is in the reference's
attribute 'floquet' (JSON: per run tau, gamma, growth rate, growth per period, eigen-shape
samples shape_t in s and shape), with each exponent's error estimate.

""" + IB_SPRING_SPEC

SPHERE_PARAMETRIC = BenchmarkProblem(
    name="sphere-parametric",
    title="viscous sphere with K(t) = sigma (1 + 2 tau sin omega t) just below and above "
          "tau_min: Floquet growth",
    inputs={**{k: PHYSICAL_UNITS[k] for k in ("rho", "mu", "radius", "sigma", "omega")},
            "l": "degree", "k": "order", "epsilon": "A0 / R",
            "margin": "tau = (1 -+ margin) tau_min"},
    # Table 6.1, case 2 (kappa = 0.06, nu = 0.002; l = 2 resonates, Fig 6.6b)
    defaults={"rho": 1.0, "mu": 0.01, "radius": 0.5, "sigma": 3.0, "omega": 20.0, "l": 2,
              "k": 0, "epsilon": 0.05, "margin": 0.1},
    quantities=_below_above("amplitude", "cm", "modal amplitude A(t) of Yr_{l,k}"),
    specification=SPHERE_PARAMETRIC_SPEC,
    reference=(HILL_REFERENCE + ". The series are time-stepped as "
               "in sphere-release (SBDF4, 512 steps per forcing period, radial resolution for "
               "1e-11), error bound per sample |fine - twice the step| + |fine - 8 fewer radial "
               "nodes|; the growth rates fitted from them (whole periods from period 40) agree "
               "with the Floquet exponents to 1e-8 in units of omega (tests)."),
    l_max=6,
    nu_range=(1e-3, 6e-3),
)

FIBRE_SPRING_SPEC = """\
Immersed-boundary spring constant (2D; thesis 6.4.1 treats the 3D triangulated sphere). A fibre
of N nodes, equally spaced in s (Delta s = 2 pi / N), joined by Hookean springs (force
sigma* (X_(j+1) - X_j) per link) represents F = sigma d^2X/ds^2 with
    sigma* = sigma / Delta s = sigma N / (2 pi),
since the force on the arc of node j, sigma (dX/ds(s_j + Delta s/2) - dX/ds(s_j - Delta s/2)),
is sigma (X_(j+1) - 2 X_j + X_(j-1)) / Delta s up to O(Delta s^2) (tests). Assumptions: nodes
equally spaced in s, uniform stiffness, N large against m; with K(t) uniform in space the
relation holds at every instant. A code that spreads the force density
F_j = sigma (X_(j+1) - 2 X_j + X_(j-1)) / Delta s^2 with weight Delta s uses sigma itself.

Reference data: {reference}
"""

FIBRE_PARAMETRIC_SPEC = """\
fibre-parametric: the 2D immersed fibre with a periodic stiffness, just below and just above
the onset of parametric resonance (Floquet quantities only)

Physical problem (thesis chapter 4, the 2D problem of Cortez et al.). A closed elastic fibre,
a circle of radius R = {radius:g} cm at rest, in an unbounded 2D incompressible Newtonian fluid
of density rho = {rho:g} and viscosity mu = {mu:g} (units of thesis Table 4.1: g/cm^3,
g/(cm s)), the same fluid inside and outside. The fibre X(s, t), s in [0, 2 pi), is massless,
moves with the fluid, resists stretching only (E = K/2 int |dX/ds|^2 ds) and exerts
F = K(t) d^2X/ds^2 (thesis (4.3)) with
    K(t) = sigma (1 + 2 tau sin(omega t)),  sigma = {sigma:g} (g cm/s^2, Table 4.1),
    omega = {omega:g} rad/s (forcing period {forcing_period:.10g} s).
A small perturbation r = R (1 + eps cos(m s)) of wavenumber m = {m} evolves linearly; two
amplitudes:
    tau_below = (1 - {margin:g}) tau_min = {tau_below:.12g}
    tau_above = (1 + {margin:g}) tau_min = {tau_above:.12g}
with tau_min = {tau_min:.12g} the tip of the lowest ({kind}) tongue of wavenumber m; tau_below
must lie in the band just below tau_min where the least stable exponent is locked to the
forcing, which narrows with nu (at nu = 5e-05, margin 0.02).

Dimensionless form (thesis (4.5)-(4.6)). Lengths in R, time in 1 / omega:
nu = mu / (rho R^2 omega) = {nu:.10g}, kappa = sigma / (rho R^2 omega^2) = {kappa:.10g},
K(t) = kappa (1 + 2 tau sin t) (offered: nu in [5e-05, 0.005], m = 2..12).

No reference time series: the package's fibre stepper only fits growth rates (it writes no
series), so the reference
holds the Floquet quantities only, from Hill's method on the exact fluid equations (thesis
(4.24)-(4.25) with the sign of ERRATA.md corrected; spectralshell exponents fibre):
  tau_below: g = {rate_below:.12g} 1/s ({rate_below_nd:.12g} omega), growth per forcing
             period exp(2 pi g / omega) = {growth_below:.12g} (decay)
  tau_above: g = {rate_above:.12g} 1/s ({rate_above_nd:.12g} omega), growth per forcing
             period {growth_above:.12g} (growth)
and the periodic eigen-shape: after the transient, the radial amplitude of the cos(m s) mode is
c exp(g t) p(t) with p periodic of period {shape_period:.10g} s. Reported (CSV columns after t,
which here runs over one period of p, in s):
  shape_below   1  p(t) at tau_below (radial component, max |p| = 1, forcing phase 0 at t = 0)
  shape_above   1  the same at tau_above
each with an error bound from two truncations of the Hill matrix.

Scoring your run. Give the radial amplitude of the cos(m s) mode of your run as CSV columns
amplitude_below and amplitude_above (any units, t in s from the start of the forcing);
score fits exp(g t) p(t) (harmonics of omega, from {score_start:.6g} s, when the next Floquet
solution has decayed by e^-{transient_efolds:g} against the leading one, to {score_end:.6g} s:
run at least that long) and reports the growth rate and frequency against the exact ones.

""" + FIBRE_SPRING_SPEC

FIBRE_PARAMETRIC = BenchmarkProblem(
    name="fibre-parametric",
    title="2D fibre with K(t) = sigma (1 + 2 tau sin omega t) just below and above tau_min: "
          "Floquet exponents and eigen-shapes (no time series)",
    inputs={"rho": "g/cm^3", "mu": "g/(cm s)", "radius": "cm", "sigma": "g cm/s^2",
            "omega": "rad/s", "m": "wavenumber", "margin": "tau = (1 -+ margin) tau_min"},
    # Table 4.1, case 1 (kappa = 0.02, nu = 2e-4); m = 3 has the lowest tongue there
    defaults={"rho": 1.0, "mu": 0.02, "radius": 0.2, "sigma": 5e3, "omega": 2500.0, "m": 3,
              "margin": 0.1},
    quantities=_below_above("shape", "1", "periodic eigen-shape p(t)"),
    rate_only=_below_above("amplitude", "any", "your run's radial cos(m s) amplitude"),
    specification=FIBRE_PARAMETRIC_SPEC,
    reference=(HILL_REFERENCE + ", its error bound the change at the coarser truncation. No "
               "time stepping (the package has no fibre stepper)."),
    l_max=12,
    nu_range=(5e-5, 5e-3),
)

FIBRE_RELEASE_SPEC = """\
fibre-release: the 2D immersed fibre released from rest with a small mode-m shape

Physical problem (thesis chapter 4, the 2D problem of Cortez et al.). A closed elastic fibre,
a circle of radius R = {radius:g} cm at rest, in an unbounded 2D incompressible Newtonian fluid
of density rho = {rho:g} and viscosity mu = {mu:g} (units of thesis Table 4.1: g/cm^3,
g/(cm s)), the same fluid inside and outside, fluid at rest at infinity. The fibre X(s, t),
s in [0, 2 pi), is massless, moves with the fluid, resists stretching only
(E = sigma/2 int |dX/ds|^2 ds) and exerts F = sigma d^2X/ds^2 (thesis (4.3)),
sigma = {sigma:g} (g cm/s^2, Table 4.1). At t = 0 the fluid is at rest and the fibre has the
shape, with every point displaced radially (no tangential displacement),
    X(s, 0) = (R + A0 cos(m s)) (cos s, sin s),   A0 = epsilon R = {amplitude:g} cm,
m = {m}. It then oscillates and decays back to the circle.

Dimensionless form (thesis (4.5)-(4.6) with omega = 1 / T). Lengths in R, time in
T = R sqrt(rho / sigma) = {T:.10g} s, so that kappa = 1 and the only parameter is
zeta = nu = mu / (R sqrt(rho sigma)) = {zeta:.10g} (references are offered for zeta in
[{zeta_lo:g}, {zeta_hi:g}], 2 <= m <= 12). The problem is linear in epsilon: the reference is the
linearised solution (epsilon -> 0) scaled to epsilon = {epsilon:g}.

Reported quantities (CSV columns after t in s):
  amplitude  cm    A(t): the fibre's radial displacement is A(t) cos(m s) (R X^r of thesis
                   (4.18d), linearised); A(0) = A0
  u_r        cm/s  radial velocity of the fibre at s = 0, dA/dt

Exact late-time behaviour. After the continuous-spectrum transient of the unbounded fluid, A(t)
decays as exp(gamma t) cos(omega_d t + phase) with gamma + i omega_d the least damped natural
mode of wavenumber m (the dispersion relation det D(gamma) = 0 of the fibre):
  growth rate gamma = {growth_rate:.12g} 1/s, angular frequency omega_d = {frequency:.12g} rad/s
  (dimensionless: {growth_rate_nd:.12g} and {frequency_nd:.12g} per T).
The inviscid (Rayleigh) frequency for comparison: sqrt(m (m^2 - 1) / 2) / T = {rayleigh:.10g}
rad/s. The reference covers the mode's decay by about exp(-{efolds:g}) after the transient; at
very late times the algebraic tail of the continuous spectrum dominates.

""" + FIBRE_SPRING_SPEC

#: fibre-release: zeta = mu / (R sqrt(rho sigma)) offered (the late rate checked at its ends).
FIBRE_ZETA_RANGE = (1e-3, 0.05)

FIBRE_RELEASE = BenchmarkProblem(
    name="fibre-release",
    title="2D fibre released from rest with a small mode-m shape: decaying oscillation",
    inputs={"rho": "g/cm^3", "mu": "g/(cm s)", "radius": "cm", "sigma": "g cm/s^2",
            "m": "wavenumber", "epsilon": "A0 / R"},
    # Table 4.1, case 1 (rho, mu, R, sigma), released with wavenumber 2
    defaults={"rho": 1.0, "mu": 0.02, "radius": 0.2, "sigma": 5e3, "m": 2, "epsilon": 0.05},
    quantities=(Quantity("amplitude", "cm", "radial amplitude A(t) of cos(m s)"),
                Quantity("u_r", "cm/s", "radial fibre velocity at s = 0")),
    specification=FIBRE_RELEASE_SPEC,
    reference=("exact Laplace inversion of the linearised release (solvers/laplace.py): the "
               "transform X^(s) = (X0 - D(s)^-1 D(0) X0) / s of the fibre's D(s) is inverted "
               "as the residues at the natural modes (trapezoidal rule on circles) plus the "
               "continuous spectrum on a Talbot contour around the branch cut. Error bound "
               "per sample: the change with 8 fewer contour nodes and half the circle nodes. "
               "The method reproduces sphere-release's time stepper within its error bounds, "
               "and the late-time decay rate fitted from the reference agrees with the "
               "dispersion relation to 1e-8 (tests). No time stepping."),
    l_max=12,
    zeta_range=FIBRE_ZETA_RANGE,
)

COCHLEA_TONE_SPEC = """\
cochlea-tone: the 2D box cochlea's basilar-membrane response to a pure tone (peak position)

Physical problem (cgs units; thesis chapter 5, Table 5.1, the box model of LeVeque, Peskin &
Lax). A basilar membrane (BM) of length L = {length:g} cm lies on y = 0, x in [0, L] (base x = 0,
apex x = L), between two fluid chambers of density rho = {rho:g} g/cm^3 and viscosity
mu = {mu:g} g/(cm s), infinitely deep, with walls at x = 0 and x = L that the fluid neither
penetrates nor slips along. The BM is massless, moves with the fluid, and its transverse
displacement h(x, t) feels the pressure jump against a local spring of stiffness per unit area
    K(x) = sigma exp(-lambda_c x),  sigma = {sigma:g} g/(cm^2 s^2), lambda_c = {lambda_c:g} 1/cm
(no bending, no coupling along x: the BM force per unit area is -K(x) h). A pressure load
concentrated at the base, proportional to exp(-(x / w)^2) with w = {width:g} L / pi =
{width_cm:.6g} cm, oscillates as cos(omega t), omega = {omega:g} rad/s
({hertz:.6g} Hz). After the start-up transient h(x, t) = Re(H(x) e^(i omega t)) (a passive,
linear response: no pumping, tau = 0).

Dimensionless form (thesis (5.2)-(5.10)). Lengths in L / pi (x in [0, pi]), time in 1 / omega:
kappa = sigma pi / (rho L omega^2) = {kappa:.10g}, nu = mu pi^2 / (rho L^2 omega) = {nu:.10g},
alpha = lambda_c L / pi = {alpha:.10g}; the load is exp(-(x / {width:g})^2). References are
offered for omega in [{omega_lo:g}, {omega_hi:g}] rad/s (Table 5.1's range), where the peak lies
well inside the membrane.

Reported quantities (CSV columns after x in cm, {points} points from base to apex):
  envelope  1  |H(x)| / max |H|: the BM displacement envelope, normalised to maximum 1 (the
               load's amplitude is arbitrary: the problem is linear)
and the scalar peak position x_peak (cm, the maximum of the envelope beyond 4 w from the base,
past the load) with its error bound, in the attributes peak_x_cm and peak_error_cm:
  x_peak = {peak_cm:.8g} cm +- {peak_error_cm:.2g} cm ({peak_share:.4g} % of L from the base)
(the leading-order WKB estimate, for comparison: {wkb}).

Comparing. Give your run's envelope as a CSV with columns x (cm) and envelope (max over a
period of |h| after the transient, any normalisation: score divides it by its largest sample,
as the reference is). score
interpolates it (cubic spline) onto the reference x inside your range and reports the relative
L2 and max errors of the envelope, and your peak position (the maximum of the spline, beyond
4 w) against the exact one. An IB code needs no spring-constant relation here: the BM force
is local, -K(x) h per unit area at each membrane point.

Reference data: {reference}
"""

COCHLEA_TONE = BenchmarkProblem(
    name="cochlea-tone",
    title="2D box cochlea driven by a pure tone: basilar-membrane envelope and peak position",
    inputs={k: COCHLEA_UNITS[k] for k in ("rho", "mu", "sigma", "length", "lambda_c", "omega")},
    defaults={**{k: TABLE_5_1[k] for k in ("rho", "mu", "sigma", "length", "lambda_c")},
              "omega": 1000.0},
    quantities=(Quantity("envelope", "1", "BM displacement envelope |H(x)| / max |H|"),),
    specification=COCHLEA_TONE_SPEC,
    reference=("the cosine-Galerkin system of the box cochlea (M modes cos(k x), exact unsteady "
               "Stokes transfer functions; models/cochlea.py) solved at s = i omega for the "
               "base load, evaluated on the x grid (the response command, runner/response.py). "
               "Error bound per sample: the largest |envelope(M) - envelope(M / 2)| within 10 "
               "samples of it (M = 512; the change crosses zero where the two agree by "
               "chance); of the peak: "
               "|x_peak(M) - x_peak(M / 2)| + the grid spacing / 10 (a parabola through the "
               "three samples around the maximum). No time stepping."),
    omega_range=(TABLE_5_1["omega_range"][0], TABLE_5_1["omega_range"][1]),
)

#: The registered problems, by name.
BENCHMARKS: dict[str, BenchmarkProblem] = {p.name: p for p in (SPHERE_RELEASE, SPHERE_PARAMETRIC,
                                                                 FIBRE_PARAMETRIC, FIBRE_RELEASE,
                                                                 COCHLEA_TONE)}


def benchmark_problem(name: str) -> BenchmarkProblem:
    """The registered problem ``name``; ParameterError naming the known ones otherwise."""
    if not isinstance(name, str) or name not in BENCHMARKS:
        raise ParameterError(f"benchmark = {name!r} is unknown: expected one of "
                             f"{', '.join(sorted(BENCHMARKS))}")
    return BENCHMARKS[name]


def benchmark_params(problem: BenchmarkProblem, values: Mapping[str, object]) -> dict[str, float]:
    """The problem's defaults updated by ``values`` (None values ignored), each checked:
    rho, radius, sigma, epsilon, omega > 0, mu >= 0, 2 <= l (or the fibre's m) <=
    problem.l_max, -l <= k <= l, margin in :data:`MARGIN_RANGE`; a forced problem:
    nu = mu / (rho R^2 omega) in problem.nu_range; a release problem: zeta
    (:func:`release_scales`) in problem.zeta_range (sphere-release, :data:`ZETA_RANGE`: above
    it the least damped mode nears the fluid's continuous spectrum and the radial resolution
    for 1e-11 exceeds the stepper's automatic limit; fibre-release, :data:`FIBRE_ZETA_RANGE`:
    above it the algebraic tail spoils the fitted rate; below it runs grow as 1 / zeta); the
    cochlea (problem.omega_range set): length > 0, lambda_c >= 0, omega in omega_range."""
    given = {k: v for k, v in values.items() if v is not None}
    unknown = sorted(set(given) - set(problem.inputs))
    if unknown:
        raise ParameterError(f"{problem.name} parameter {unknown[0]} is unknown: expected "
                             f"{', '.join(problem.inputs)}")
    p = {**problem.defaults, **given}
    out = {k: require_positive(k, p[k])
           for k in ("rho", "radius", "sigma", "epsilon", "omega") if k in p}
    out["mu"] = require_nonnegative("mu", p["mu"])
    if problem.omega_range is not None:
        return {**out, "length": require_positive("length", p["length"]),
                "lambda_c": require_nonnegative("lambda_c", p["lambda_c"]),
                "omega": _in_range("omega", p["omega"], problem.omega_range)}
    for name in ("l", "m"):
        if name in p:
            out[name] = int(require_int_in_range(name, p[name], 2, problem.l_max))
    if "k" in p:
        out["k"] = int(require_int_in_range("k", p["k"], -out["l"], out["l"]))
    if problem.nu_range is not None:
        out["margin"] = _in_range("margin", p["margin"], MARGIN_RANGE)
        nu = out["mu"] / (out["rho"] * out["radius"] ** 2 * out["omega"])
        lo, hi = problem.nu_range
        if not lo * (1 - RANGE_RTOL) <= nu <= hi * (1 + RANGE_RTOL):
            raise ParameterError(f"mu = {out['mu']:g} is invalid: nu = mu / (rho R^2 omega) = "
                                 f"{nu:.4g} must be in [{problem.nu_range[0]:g}, "
                                 f"{problem.nu_range[1]:g}] (the range offered for "
                                 f"{problem.name})")
        return out
    _, zeta = release_scales(problem.name, out)
    lo, hi = problem.zeta_range
    if not lo * (1 - RANGE_RTOL) <= zeta <= hi * (1 + RANGE_RTOL):
        raise ParameterError(f"mu = {out['mu']:g} is invalid: zeta = {ZETA_FORMULA[problem.name]} "
                             f"= {zeta:.4g} must be in [{lo:g}, {hi:g}] (the "
                             "range where the reference is checked against the dispersion "
                             "relation; smaller zeta runs longer)")
    return out


#: zeta of the release problems in cgs inputs (for messages).
ZETA_FORMULA = {"sphere-release": "mu / sqrt(rho R sigma)",
                "fibre-release": "mu / (R sqrt(rho sigma))"}


def release_scales(name: str, p: Mapping[str, float]) -> tuple[float, float]:
    """(T, zeta) of a release problem: the time unit in s in which kappa = 1, and the
    dimensionless viscosity nu = zeta (sphere: T = sqrt(rho R^3 / sigma); 2D fibre, sigma a
    force: T = R sqrt(rho / sigma), nu of (4.5) at omega = 1 / T)."""
    if name == "fibre-release":
        T = p["radius"] * math.sqrt(p["rho"] / p["sigma"])
        return T, fibre_forced(rho=p["rho"], mu=p["mu"], radius=p["radius"], sigma=p["sigma"],
                               omega=1.0 / T)["nu"]
    phys = PhysicalSphere(rho=p["rho"], mu=p["mu"], radius=p["radius"], sigma=p["sigma"])
    return phys.time_scale, phys.zeta


def _in_range(name: str, value: object, bounds: tuple[float, float]) -> float:
    """A real ``value`` in the closed interval ``bounds``; ParameterError naming it otherwise."""
    x = require_positive(name, value)
    if not bounds[0] <= x <= bounds[1]:
        raise ParameterError(f"{name} = {x:g} is invalid: must be in [{bounds[0]:g}, "
                             f"{bounds[1]:g}]")
    return x
