"""The model-agnostic IMEX stepper (solvers/stepper.py) and the rate fit (solvers/rate_fit.py).

Oracles: matrix exponentials (scipy.linalg.expm) of constant-coefficient systems, closed-form
exponential signals, and the reduced ODE form of the sphere's radial system for the
differential-algebraic (singular M) path.
"""

from types import SimpleNamespace

import numpy as np
import pytest
import scipy.linalg as sla

from spectralshell.discretise.sphere_stepping import degree_system
from spectralshell.errors import ConvergenceError, ParameterError
from spectralshell.solvers.rate_fit import fit_rate
from spectralshell.solvers.stepper import cache_info, integrate


def oscillator(forced=True):
    L = np.array([[-0.2, 1.5], [-1.5, -0.2]])
    N = np.array([[0.0, 0.0], [-1.0, 0.0]])
    return SimpleNamespace(M=np.eye(2), L=L, N=N if forced else None,
                           forcing=(lambda t: 0.4 * np.sin(t)) if forced else None)


def test_factorisations_are_cached_per_system_and_step():
    """A second run of the same matrices at the same step computes no new factorisation; a new
    step size, or changed matrices, does: two for SBDF3 (its implicit matrix, and the one of the
    starting RK443 steps, whose implicit diagonal is constant)."""
    system = oscillator()
    integrate(system, [1.0, 0.0], scheme="SBDF3", dt=0.011, t_end=1.0)
    before = cache_info()["misses"]
    integrate(system, [0.0, 1.0], scheme="SBDF3", dt=0.011, t_end=2.0)
    assert cache_info()["misses"] == before
    integrate(system, [0.0, 1.0], scheme="SBDF3", dt=0.013, t_end=2.0)
    assert cache_info()["misses"] == before + 2
    other = SimpleNamespace(**{**vars(system), "L": system.L * 1.01})
    integrate(other, [0.0, 1.0], scheme="SBDF3", dt=0.013, t_end=2.0)
    assert cache_info()["misses"] == before + 4


def test_columns_are_independent_solutions():
    """A matrix state steps its columns as separate solutions (identity -> propagator), and the
    propagator of a constant system equals expm(L T) to the scheme's accuracy (RK443, h = 0.01)."""
    system = oscillator(forced=False)
    run = integrate(system, np.eye(2), scheme="RK443", dt=0.01, t_end=1.0)
    for j in range(2):
        single = integrate(system, np.eye(2)[:, j], scheme="RK443", dt=0.01, t_end=1.0)
        np.testing.assert_allclose(run.final[:, j], single.final, rtol=1e-13, atol=0)
    np.testing.assert_allclose(run.final, sla.expm(system.L), rtol=0, atol=1e-7)  # 4e-8


def test_run_bookkeeping():
    """The step is adjusted to land on t_end; saved times are uniform; observe and progress."""
    calls = []
    run = integrate(oscillator(), [1.0, 0.0], scheme="SBDF2", dt=0.3, t_end=1.0, every=2,
                    observe=lambda v: v[:1] * 2, progress=calls.append)
    assert run.steps == 4 and run.dt == pytest.approx(0.25)
    np.testing.assert_allclose(run.times, [0.0, 0.5, 1.0])
    assert run.values.shape == (3, 1) and run.values[0, 0] == 2.0
    assert sum(calls) == 4 and run.scheme == "SBDF2"


@pytest.mark.parametrize("name,order", [("SBDF2", 2), ("SBDF3", 3), ("RK222", 2), ("RK443", 3)])
def test_differential_algebraic_form(name, order):
    """Singular M: the sphere's full radial system M dv/dt = (L_fluid + kappa L_stiffness) v
    (psi rows and interface rows algebraic) stepped directly converges, at the scheme's order,
    to the exact solution expm(L T) y0 of its reduced ODE form (tau = 0)."""
    sys0 = degree_system(m=2, kappa=1.0, nu=0.05, n_radial=16)
    ops = sys0.operators
    dae = SimpleNamespace(M=ops.M, L=ops.L_fluid + sys0.kappa * ops.L_stiffness, N=None,
                          forcing=None)
    y0 = sys0.initial_state([1.0, 0.0])
    v0 = sys0.full_state(y0, 0.0)
    T = 1.0
    want = sys0.displacement(sla.expm(sys0.L * T) @ y0)
    errors = [np.max(np.abs(ops.displacement(integrate(dae, v0, scheme=name, dt=dt,
                                                       t_end=T).final) - want))
              for dt in (0.02, 0.01)]
    assert abs(np.log2(errors[0] / errors[1]) - order) < 0.3, errors


def test_bad_input_and_blow_up():
    system = oscillator()
    for kwargs, name in ((dict(dt=0.0), "dt"), (dict(dt=float("nan")), "dt"),
                         (dict(t_end=-1.0), "t_end"), (dict(every=0), "every"),
                         (dict(scheme="RK4"), "scheme")):
        args = dict(scheme="SBDF2", dt=0.1, t_end=1.0) | kwargs
        with pytest.raises(ParameterError, match=name):
            integrate(system, [1.0, 0.0], **args)
    with pytest.raises(ParameterError, match="v0"):
        integrate(system, [1.0, 0.0, 0.0], scheme="SBDF2", dt=0.1, t_end=1.0)
    # an explicit term far beyond the stability limit: the state overflows -> ConvergenceError
    wild = SimpleNamespace(M=np.eye(1), L=np.array([[-1.0]]), N=np.array([[200.0]]),
                           forcing=lambda t: 1.0)
    with pytest.raises(ConvergenceError, match="reduce dt"):
        integrate(wild, [1.0], scheme="SBDF1", dt=0.1, t_end=100.0)


# ----------------------------------------------------------------------------- rate fit
def test_fit_unforced_sum_of_exponentials():
    """x = e^{-0.3 t} cos(2 t) + 0.2 e^{-1.5 t} + 0.1 e^{-0.9 t} sin(5 t): the dominant rate and
    frequency are recovered to rounding; the error estimate is small and honest."""
    t = np.linspace(0, 40, 4001)
    x = np.exp(-0.3 * t) * np.cos(2 * t) + 0.2 * np.exp(-1.5 * t) \
        + 0.1 * np.exp(-0.9 * t) * np.sin(5 * t)
    fit = fit_rate(t, x)
    assert abs(fit.growth_rate + 0.3) < 1e-9 and abs(fit.frequency - 2.0) < 1e-9
    assert fit.error_estimate < 1e-8


def test_fit_forced_floquet_signal():
    """x = e^{0.05 t} p(t) with p = cos(t/2) + 0.3 cos(3 t/2 + 1) (a period-doubling response,
    multiplier -e^{0.1 pi}) plus a decaying harmonic one: growth 0.05, frequency 1/2."""
    t = np.arange(0, 40 * 2 * np.pi + 1e-9, 2 * np.pi / 32)
    x = np.exp(0.05 * t) * (np.cos(t / 2) + 0.3 * np.cos(1.5 * t + 1)) \
        + np.exp(-0.2 * t) * (1 + 0.5 * np.sin(t))
    fit = fit_rate(t, x, period=2 * np.pi)
    assert abs(fit.growth_rate - 0.05) < 1e-9 and abs(fit.frequency - 0.5) < 1e-9
    assert abs(fit.multiplier + np.exp(0.1 * np.pi)) < 1e-8
    y = np.exp(0.02 * t) * (0.2 + np.sin(t))          # harmonic: dominant harmonic at 1
    fit = fit_rate(t, y, period=2 * np.pi)
    assert abs(fit.growth_rate - 0.02) < 1e-9 and abs(fit.frequency - 1.0) < 1e-9


def test_fit_input_errors():
    t = np.linspace(0, 1, 50)
    with pytest.raises(ParameterError, match="uniform"):
        fit_rate(t**2, t)
    with pytest.raises(ParameterError, match="period"):
        fit_rate(t, np.sin(t), period=0.0123)
    with pytest.raises(ConvergenceError, match="zero"):
        fit_rate(t, np.zeros_like(t))
