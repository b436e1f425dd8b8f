"""Time stepping of the sphere (discretise/sphere_stepping.py + solvers/stepper.py + simulate).

Independent oracles:
* natural modes: the roots of the exact dispersion relation det D(gamma) = 0 (thesis (7.14)),
  Bessel functions, :func:`spectralshell.natural_modes` (solvers/modes.py; no radial grid);
* Floquet: tau_min of the Hill solver (:func:`spectralshell.floquet`, exact Bessel D(s), Fourier in
  time) and, above it, the least damped Floquet exponent of :func:`spectralshell.exponents` (a
  root of the truncated Hill determinant built from models/sphere.py's exact D(s),
  solvers/hill_exponents.py); for nu = 0, api.exponents of the Mathieu equation;
* Table 6.1: the kind predicted by :func:`spectralshell.stability`;
* energy: the dissipation integral nu int |curl u|^2 dV evaluated on the stepped fields
  (derivations/sphere_energy.py) against the change of kinetic + elastic energy.
"""

import dataclasses

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.integrate import simpson

import spectralshell as ss
from spectralshell.discretise.sphere_stepping import degree_system, scene_blocks, shape_coefficients
from spectralshell.errors import ConvergenceError, ParameterError
from spectralshell.params.physical import TABLE_6_1, sphere_forced_params
from spectralshell.params.simulation import parse_expression
from spectralshell.solvers.rate_fit import fit_rate
from spectralshell.solvers.stepper import integrate

TWO_PI = 2 * np.pi


# ----------------------------------------------------------------------------- oracles
def exact_mode(m, zeta):
    return complex(ss.natural_modes("sphere", m=m, kappa=1.0, nu=zeta, count=1).gamma[0])


def hill_exponent(m, kappa, nu, tau):
    """The least damped Floquet exponent of the viscous sphere (:func:`spectralshell.exponents`)."""
    return complex(ss.exponents("sphere", m=m, kappa=kappa, nu=nu, tau=tau).gamma[0])


def monodromy_multipliers(system, dt):
    run = integrate(system, np.eye(system.size), scheme="SBDF4", dt=dt, t_end=TWO_PI,
                    every=10**6)
    return np.linalg.eigvals(run.final)


def simulate(m, kappa, nu, tau, t_end, scheme="SBDF4", dt=None, **initial):
    scene = {"model": "sphere", "params": {"kappa": kappa, "nu": nu, "tau": tau},
             "initial": {"shape": f"{m}:0:1.0", **initial},
             "simulate": {"t_end": t_end, "scheme": scheme, **({"dt": dt} if dt else {})}}
    return ss.simulate(scene)


# ----------------------------------------------------------------------------- builder
@pytest.mark.parametrize("radial", ["collocation", "banded"])
@pytest.mark.parametrize("m,zeta", [(2, 0.01), (3, 0.01), (2, 0.1), (3, 0.1)])
def test_builder_leading_mode_matches_dispersion_relation(m, zeta, radial):
    """The least damped oscillatory eigenvalue of the reduced ODE (collocation; banded: the
    eigenvalue of the sparse DAE nearest it) with the resolution chosen for tol = 1e-9 is the
    natural mode to 1e-9, and the stated spatial error is an upper bound of the actual one. No
    spurious growth: eigenvalues of the reduced L here, of the banded pencil in
    tests/test_sphere_banded.py."""
    system = degree_system(m=m, kappa=1.0, nu=zeta, tol=1e-9, radial=radial)
    exact = exact_mode(m, zeta)
    actual = abs(system.leading - exact) / abs(exact)
    assert actual <= 1e-9 and system.spatial_error <= 1e-9
    assert actual <= system.spatial_error, (actual, system.spatial_error)
    if radial == "collocation":
        assert np.all(np.linalg.eigvals(system.L).real < 0)


def test_exterior_error_is_stated_honestly():
    """Coarse radial grids (mapped, not truncated, exterior): the stated error (change against
    n - 8) is within a factor 30 of the actual error against the dispersion relation, which is
    far above rounding there (m = 3, zeta = 0.1, n = 24, 32)."""
    exact = exact_mode(3, 0.1)
    for n in (24, 32):
        system = degree_system(m=3, kappa=1.0, nu=0.1, n_radial=n)
        actual = abs(system.leading - exact) / abs(exact)
        assert actual > 1e-7
        assert actual / 30 < system.spatial_error < 30 * actual, (n, actual, system.spatial_error)


@pytest.mark.parametrize("radial", ["collocation", "banded"])
def test_explicit_stiffness_split(radial):
    """L + f(t) N at a frozen time is the system with uniform stiffness K(t) = kappa (1 + 2 tau
    sin t): its leading eigenvalue is the natural mode at stiffness K(t), i.e. zeta = nu/sqrt(K),
    gamma = sqrt(K) sigma (dispersion relation scaling). Banded: eigenvalues of the pencil
    (L + f N, M)."""
    kappa, nu, tau, t = 0.5, 0.01, 0.3, 1.1
    system = degree_system(m=2, kappa=kappa, nu=nu, tau=tau, radial=radial)
    K = kappa * (1 + 2 * tau * np.sin(t))
    A = system.L + system.forcing(t) * system.N
    values = (np.linalg.eigvals(A) if radial == "collocation" else
              sla.eigvals(A.toarray(), system.M.toarray()))
    exact = complex(ss.natural_modes("sphere", m=2, kappa=K, nu=nu, count=1).gamma[0])
    assert np.min(np.abs(values - exact)) < 1e-8 * abs(exact)


def test_inviscid_system_is_the_mathieu_equation():
    """nu = 0: no fluid grid; the Floquet exponent of the stepped 2 x 2 system equals the
    Mathieu exponent of api.exponents (Hill's method) at lambda0^2 = kappa m(m+1)(m-1)(m+2)/(2m+1)."""
    system = degree_system(m=2, kappa=0.06, nu=0.0, tau=0.25)
    assert system.size == 2 and system.operators is None
    mu = monodromy_multipliers(system, TWO_PI / 2048)
    hill = ss.exponents("sphere", m=2, kappa=0.06, nu=0.0, tau=0.25).gamma
    assert abs(np.log(np.abs(mu)).max() / TWO_PI - hill.real.max()) < 1e-9


def test_scene_allocates_only_what_is_excited():
    """Only the degrees of the shape are allocated, their orders k as columns of one system; the
    toroidal part only with a twist; degrees 0, 1 of an expression shape are dropped with a
    warning."""
    blocks = scene_blocks(shape={(3, 1): 1.0, (3, -2): 0.5, (5, 0): 1.0}, twist={},
                          kappa=1.0, nu=0.05, tau=0.0, n_radial=16)
    assert [(b.system.m, b.system.component, b.modes) for b in blocks] == [
        (3, "poloidal", ((3, -2), (3, 1))), (5, "poloidal", ((5, 0),))]
    assert blocks[0].initial.shape == (blocks[0].system.size, 2)
    blocks = scene_blocks(shape={(2, 0): 1.0}, twist={(4, 1): 1.0}, kappa=1.0, nu=0.05, tau=0.0,
                          n_radial=16)
    assert [b.system.component for b in blocks] == ["poloidal", "toroidal"]
    with pytest.raises(ParameterError, match="twist"):
        scene_blocks(shape={(2, 0): 1.0}, twist={(2, 0): 1.0}, kappa=1.0, nu=0.0, tau=0.0)
    # 0.3 P2(cos theta) + 0.1 cos(theta) + 0.2: degree 2 with amplitude 0.3 sqrt(4 pi / 5)
    expr = parse_expression("shape", "0.3*(3*cos(theta)**2 - 1)/2 + 0.1*cos(theta) + 0.2")
    coeffs, warnings = shape_coefficients(expr.function, 8)
    assert set(coeffs) == {(2, 0)} and abs(coeffs[2, 0] - 0.3 * np.sqrt(4 * np.pi / 5)) < 1e-13
    assert len(warnings) == 1 and "degrees 0 and 1" in warnings[0]


def test_zeta_near_the_cut_is_refused():
    """zeta = 1 (modes near the branch cut): the real exterior map of the stepper does not resolve
    them, and the builder says so instead of stepping a wrong system."""
    with pytest.raises(ConvergenceError, match="branch cut"):
        degree_system(m=2, kappa=1.0, nu=1.0)


# ----------------------------------------------------------------------------- natural modes
def check_natural_mode(m, zeta, t_end):
    traj = simulate(m, 1.0, zeta, 0.0, t_end, dt=0.005)
    exact = exact_mode(m, zeta)
    (fit,) = traj.fits
    got = complex(fit.growth_rate, fit.frequency)
    assert abs(got - exact) <= 1e-6 * abs(exact), (got, exact)
    assert abs(got - exact) <= fit.error_estimate, (abs(got - exact), fit.error_estimate)


def test_natural_mode_fitted_from_a_run():
    """m = 2, zeta = 0.01: decay rate and frequency fitted from a run started at rest from the
    shape Yr_{2,0} agree with the dispersion relation to 1e-6, within the stated error."""
    check_natural_mode(2, 0.01, 40.0)


@pytest.mark.slow
@pytest.mark.parametrize("m,zeta,t_end", [(3, 0.01, 30.0), (2, 0.1, 20.0), (3, 0.1, 12.0)])
def test_natural_modes_fitted_from_runs(m, zeta, t_end):
    check_natural_mode(m, zeta, t_end)


def test_banded_run_decays_at_the_natural_rate():
    """The sparse DAE (radial='banded'), m = 2, zeta = 0.01, started at rest from the shape and
    stepped by SBDF4 (dt = 0.005) to t = 40: decay rate and frequency fitted on [4, 40] agree
    with the dispersion relation to 1e-6."""
    system = degree_system(m=2, kappa=1.0, nu=0.01, radial="banded")
    run = integrate(system, system.initial_state([1.0, 0.0]), scheme="SBDF4", dt=0.005,
                    t_end=40.0, every=10, observe=lambda y: y[system.membrane.start])
    fit = fit_rate(run.times, run.values, window=(4.0, 40.0))
    exact = exact_mode(2, 0.01)
    assert abs(complex(fit.growth_rate, fit.frequency) - exact) <= 1e-6 * abs(exact)


# ----------------------------------------------------------------------------- Floquet
def check_marginal_multiplier(m, kappa, nu, radial="collocation"):
    res = ss.floquet("sphere", m=m, kappa=kappa, nu=nu, tau_max=0.5)
    for kind, target in (("subharmonic", -1.0), ("harmonic", 1.0)):
        marginal = getattr(res, kind)
        if marginal.tau_min is None:
            continue
        system = degree_system(m=m, kappa=kappa, nu=nu, tau=marginal.tau_min, radial=radial)
        mu = monodromy_multipliers(system, TWO_PI / 1024)
        assert np.min(np.abs(mu - target)) < 1e-6, (kind, mu[np.argmin(np.abs(mu - target))])
        assert np.max(np.abs(mu)) < 1 + 1e-6            # marginal: nothing grows


def test_monodromy_at_tau_min_has_multiplier_minus_one():
    """Case 2 (m = 2, kappa = 0.06, nu = 0.002): at the Hill solver's subharmonic tau_min the
    stepped monodromy has the multiplier -1 to 1e-6 (measured 6e-11)."""
    check_marginal_multiplier(2, 0.06, 0.002)


@pytest.mark.slow
def test_monodromy_at_tau_min_banded():
    """Case 2 with the sparse DAE (radial='banded'): multiplier -1 to 1e-6, nothing grows."""
    check_marginal_multiplier(2, 0.06, 0.002, radial="banded")


@pytest.mark.slow
@pytest.mark.parametrize("m,kappa,nu", [(3, 0.02, 0.006), (2, 0.25, 0.004), (3, 0.07, 0.001)])
def test_monodromy_at_tau_min(m, kappa, nu):
    """Case 1 (m = 3, subharmonic), case 4 (m = 2, harmonic), and the harmonic finger of m = 3
    at kappa = 0.07, nu = 0.001 (tau_min = 0.30)."""
    check_marginal_multiplier(m, kappa, nu)


def test_growth_above_tau_min_is_the_hill_exponent():
    """Case 2 at tau = 0.25 (inside the subharmonic finger): the growth rate of the stepped
    monodromy equals the Hill exponent to 1e-9, and the rate fitted from the trajectory of
    ss.simulate to 1e-6, with a period-doubling frequency 1/2."""
    m, kappa, nu, tau = 2, 0.06, 0.002, 0.25
    system = degree_system(m=m, kappa=kappa, nu=nu, tau=tau)
    mu = monodromy_multipliers(system, TWO_PI / 1024)
    lead = mu[np.argmax(np.abs(mu))]
    assert lead.real < 0 and abs(lead.imag) < 1e-9            # period doubling
    hill = hill_exponent(m, kappa, nu, tau)
    assert abs(hill.imag - 0.5) < 1e-9
    assert abs(np.log(abs(lead)) / TWO_PI - hill.real) < 1e-9
    (fit,) = simulate(m, kappa, nu, tau, 120.0, dt=TWO_PI / 512).fits
    assert abs(fit.growth_rate - hill.real) < 1e-6 and fit.frequency == pytest.approx(0.5, abs=1e-9)
    assert abs(fit.growth_rate - hill.real) <= fit.error_estimate


@pytest.mark.slow
@pytest.mark.parametrize("case", [1, 2, 3, 4])
def test_table_6_1_cases(case):
    """Table 6.1 at tau = 0.45: the degree ss.stability predicts unstable grows with the
    predicted kind (frequency 1/2: period doubling, cases 1-3; harmonic, case 4) at the Hill
    exponent's rate (1e-6); a stable neighbouring degree decays."""
    p = sphere_forced_params(dataclasses.asdict(TABLE_6_1[case]))
    kappa, nu, tau = p["kappa"], p["nu"], 0.45
    st = ss.stability("sphere", tau=tau, m="2:8", kappa=kappa, nu=nu)
    unstable = [x for x in st.modes if x["unstable"]]
    assert len(unstable) == 1
    m, kind = unstable[0]["m"], unstable[0]["kind"]
    assert kind == ("harmonic" if case == 4 else "subharmonic")
    (fit,) = simulate(m, kappa, nu, tau, 160.0, dt=TWO_PI / 512).fits
    assert fit.growth_rate > 0
    assert abs(fit.frequency % 1.0 - (0.0 if kind == "harmonic" else 0.5)) < 1e-9
    hill = hill_exponent(m, kappa, nu, tau)
    assert abs(hill.imag - (0.0 if kind == "harmonic" else 0.5)) < 1e-9
    assert abs(fit.growth_rate - hill.real) < 1e-6
    stable = next(x["m"] for x in st.modes if not x["unstable"] and abs(x["m"] - m) == 1)
    (fit,) = simulate(stable, kappa, nu, tau, 160.0, dt=TWO_PI / 512).fits
    assert fit.growth_rate < 0


# ----------------------------------------------------------------------------- energy
def energy_balance(system, y0, t_end, dt):
    run = integrate(system, y0, scheme="SBDF4", dt=dt, t_end=t_end, every=5)
    E = np.array([system.energy(y, t) for y, t in zip(run.values, run.times)])
    total, dissipation = E[:, 0] + E[:, 1], E[:, 2]
    start = len(run.times) // 10          # after the initial vortex-sheet transient
    change = total[-1] - total[start]
    lost = simpson(dissipation[start:], x=run.times[start:])
    return change, lost, total[0]


@pytest.mark.parametrize("component,m,nu,radial", [
    ("poloidal", 2, 0.01, "collocation"), ("toroidal", 2, 0.1, "collocation"),
    ("poloidal", 2, 0.01, "banded"), ("toroidal", 2, 0.1, "banded")])
def test_energy_decreases_at_the_dissipation_rate(component, m, nu, radial):
    """tau = 0: kinetic + elastic energy changes by minus the time integral of the viscous
    dissipation nu int |curl u|^2 dV, to 1e-8 of the initial energy (quadrature, time step);
    banded: the integrals of BandedOperators.kinetic_dissipation on the coefficient state."""
    system = degree_system(m=m, kappa=1.0, nu=nu, component=component, radial=radial)
    y0 = system.initial_state([1.0, 0.0] if component == "poloidal" else [1.0])
    change, lost, initial = energy_balance(system, y0, 5.0, 0.002)
    assert change < -0.1 * initial                       # a real decrease ...
    assert abs(change + lost) < 1e-8 * initial, (change, -lost)   # ... at the dissipation rate


def test_inviscid_energy_is_conserved():
    """nu = 0, tau = 0: potential-flow kinetic + elastic energy is constant (SBDF4, 1e-8)."""
    system = degree_system(m=3, kappa=1.0, nu=0.0)
    run = integrate(system, system.initial_state([1.0]), scheme="SBDF4", dt=0.002, t_end=10.0)
    e0 = sum(system.energy(system.initial_state([1.0]), 0.0)[:2])
    e1 = sum(system.energy(run.final, 10.0)[:2])
    assert abs(e1 - e0) < 1e-8 * e0


@pytest.mark.slow
def test_energy_balance_stronger_viscosity():
    system = degree_system(m=3, kappa=1.0, nu=0.1)
    change, lost, initial = energy_balance(system, system.initial_state([1.0, 0.0]), 5.0, 0.001)
    assert abs(change + lost) < 1e-8 * initial      # measured 7e-10 (1.2e-8 at dt = 0.002)


@pytest.mark.slow
def test_energy_derivation_script_passes():
    """derivations/sphere_energy.py: the kinetic-energy and dissipation integrals used by
    DegreeSystem.energy, re-derived on explicit harmonics (~40 s)."""
    import subprocess
    import sys
    from pathlib import Path

    script = Path(__file__).resolve().parents[1] / "derivations" / "sphere_energy.py"
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
