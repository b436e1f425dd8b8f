"""Damped Mathieu equation (thesis (2.2), (2.9)) against independent oracles."""

import numpy as np
import pytest
import scipy.special as special

import spectralshell as ss
from spectralshell.discretise.hill import assemble
from spectralshell.models.mathieu import hill_system
from spectralshell.solvers.marginal import dense_taus, marginal_tau, solve_truncation

# (kind, scipy characteristic-value function, order r). With t = 2x - pi/2 the Mathieu equation
# (2.2) becomes DLMF 28.2.1 y'' + (a - 2q cos 2x) y = 0 with a = 4 kappa, q = 4 kappa tau
# (derivations/mathieu_mapping.py). Period 2 pi in t is period pi in x: harmonic <-> a_{2r},
# b_{2r}; antiperiodic (period 4 pi in t) <-> a_{2r+1}, b_{2r+1} (DLMF 28.2.21-28.2.22).
ORACLES = [("harmonic", special.mathieu_a, 2), ("harmonic", special.mathieu_b, 2),
           ("harmonic", special.mathieu_a, 4), ("harmonic", special.mathieu_b, 4),
           ("subharmonic", special.mathieu_a, 1), ("subharmonic", special.mathieu_a, 3),
           ("subharmonic", special.mathieu_b, 3), ("subharmonic", special.mathieu_b, 5)]


@pytest.mark.parametrize("kind,char_value,order", ORACLES)
@pytest.mark.parametrize("q", [0.3, 1.3, 4.0])
def test_undamped_tau_matches_scipy_mathieu_characteristic_values(kind, char_value, order, q):
    """Oracle: scipy.special.mathieu_a/mathieu_b. At kappa = a_r(q)/4 the curve passes through
    tau = q / (4 kappa), which must be one of the computed marginal amplitudes."""
    a = char_value(order, q)
    assert a > 0  # every chosen (order, q) maps to kappa > 0, inside the model
    kappa = a / 4
    res = ss.floquet("mathieu", kind=kind, kappa=kappa, nu=0.0)
    got = getattr(res, kind).tau
    assert np.min(np.abs(got - q / (4 * kappa))) < 1e-10


@pytest.mark.parametrize("kappa,nu,kind", [(0.25, 0.1, "subharmonic"), (1.1, 0.1, "harmonic"),
                                          (2.3, 0.01, "subharmonic"), (0.3, 1e-9, "subharmonic"),
                                          (1.0, 0.05, "harmonic"), (0.7, 0.5, "harmonic")])
def test_damped_tau_min_gives_monodromy_multiplier_plus_minus_one(kappa, nu, kind, monodromy):
    """Oracle: monodromy matrix from solve_ivp (rtol 1e-12). At tau_min the Floquet multiplier is
    exactly +1 (harmonic) or -1 (subharmonic), thesis 2.2. (Cases with tau_min <= 1.7: at larger
    tau the stiffness is strongly negative, solutions grow by orders of magnitude within a period
    and the integrator's own error exceeds 1e-8.)"""
    m = getattr(ss.floquet("mathieu", kind=kind, kappa=kappa, nu=nu), kind)
    assert m.error_estimate < 1e-10
    target = 1.0 if kind == "harmonic" else -1.0
    # det(M - target I) = (rho_1 - target)(rho_2 - target): unlike the multipliers themselves it is
    # well conditioned when both multipliers meet at -1 (nu -> 0 at a finger tip).
    assert abs(np.linalg.det(monodromy(kappa, nu, m.tau_min) - target * np.eye(2))) < 1e-9


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
@pytest.mark.parametrize("kappa,nu", [(0.3, 0.0), (1.2, 0.1), (2.0, 0.02)])
def test_real_form_and_two_sided_form_have_the_same_real_spectrum(kind, kappa, nu):
    """Second path: the reality-condition packing (2.7)/(2.8) versus the two-sided complex form,
    both by dense QZ at the same truncation."""
    system = hill_system(kappa=kappa, nu=nu)
    real = dense_taus(assemble(system, kind, 20, "real"))
    two_sided = dense_taus(assemble(system, kind, 20, "two-sided"))
    small = lambda t: np.sort(t[(t > 0) & (t < 50)])  # noqa: E731
    np.testing.assert_allclose(small(real), small(two_sided), rtol=1e-9)


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
@pytest.mark.parametrize("kappa,nu", [(0.26, 0.1), (1.5, 0.05), (2.9, 0.3)])
def test_structured_solver_matches_dense_qz(kind, kappa, nu):
    """Fast path (half-size product W) against scipy.linalg.eigvals(A, B) of the same pencil."""
    system = hill_system(kappa=kappa, nu=nu)
    fast, method, _ = solve_truncation(system, kind, 30)
    assert method == "structured"
    dense = dense_taus(assemble(system, kind, 30, "real"))
    dense = dense[(dense > 0) & (dense < 100)]
    np.testing.assert_allclose(fast[fast < 100], dense, rtol=1e-9)


def test_infinite_and_spurious_eigenvalues_are_not_reported(monodromy):
    """The truncated pencil has infinite eigenvalues (B singular; harmonic Im u_0 slot) and
    truncation-made ones; only tau reproduced by the previous truncation are reported, and each
    reported tau gives a multiplier +1 in the monodromy oracle."""
    kappa, nu = 1.2, 0.1
    system = hill_system(kappa=kappa, nu=nu)
    raw, _, _ = solve_truncation(system, "harmonic", 12)
    res = marginal_tau(system, "harmonic", n_temporal=12)
    assert res.tau.size < raw.size  # the truncation-made large tau are dropped
    assert np.all(np.isfinite(res.tau))
    for tau in res.tau[res.tau < 5]:
        rho = np.linalg.eigvals(monodromy(kappa, nu, tau))
        assert np.min(np.abs(rho - 1)) < 1e-6


@pytest.mark.parametrize("k", [1, 2, 3])
def test_undamped_finger_tips_at_sqrt_kappa_half_integer(k):
    """Closed form (thesis 2.2): undamped fingers touch tau = 0 at sqrt(kappa) = k/2."""
    lo, hi = (k / 2) ** 2 - 0.05, (k / 2) ** 2 + 0.05
    res = ss.tongues("mathieu", kappa=np.linspace(lo, hi, 11), nu=0.0,
                     kind="subharmonic" if k % 2 else "harmonic", workers=1)
    (tip,) = res.tips
    assert abs(tip.kappa - (k / 2) ** 2) < 1e-11
    assert tip.kappa_error < 1e-11
    assert tip.tau <= tip.tau_error  # closed form tau = 0, within the stated error


def test_damped_finger_tip_is_the_minimum_and_marginal(monodromy):
    """The located tip (kappa*, tau*) is marginal (multiplier -1 by the monodromy oracle) and tau
    of the finger is larger at kappa* +- 1e-4 (quadratic growth beyond rounding)."""
    nu = 0.1
    res = ss.tongues("mathieu", kappa=np.linspace(0.2, 0.32, 13), nu=nu, kind="subharmonic",
                     workers=1)
    (tip,) = res.tips
    rho = np.linalg.eigvals(monodromy(tip.kappa, nu, tip.tau))
    assert np.min(np.abs(rho + 1)) < 1e-8
    for dk in (-1e-4, 1e-4):
        near = ss.floquet("mathieu", kind="subharmonic", kappa=tip.kappa + dk, nu=nu).subharmonic
        assert near.tau_min > tip.tau + 1e-10
    assert tip.kappa_error < 1e-10 and tip.tau_error < 1e-10


@pytest.mark.parametrize("kappa,nu,tau", [(1.0, 0.1, 0.3), (0.25, 0.1, 0.4), (0.3, 0.0, 0.1),
                                          (2.3, 0.05, 0.7), (0.6, 1.0, 0.2)])
def test_exponents_match_monodromy_multipliers(kappa, nu, tau, monodromy):
    """Oracle: eigenvalues of the solve_ivp monodromy matrix (rtol 1e-12) are exp(2 pi gamma)."""
    res = ss.exponents("mathieu", kappa=kappa, nu=nu, tau=tau)
    rho = np.linalg.eigvals(monodromy(kappa, nu, tau))
    distance = np.abs(res.multipliers[:, None] - rho[None, :])
    assert np.all(distance.min(axis=1) < 1e-9) and np.all(distance.min(axis=0) < 1e-9)
    assert np.all(np.abs(res.gamma.imag) <= 0.5) and np.all(np.diff(res.gamma.real) <= 0)
    # Liouville: the exponents sum to -nu/2 per component (trace of the system matrix is -nu).
    assert abs(res.gamma.real.sum() + nu) < 1e-10


def test_growth_rate_is_positive_exactly_inside_the_finger():
    """Re gamma > 0 just above tau_min and < 0 just below (nu = 0.1, principal finger)."""
    kappa, nu = 0.26, 0.1
    tmin = ss.floquet("mathieu", kind="subharmonic", kappa=kappa, nu=nu).subharmonic.tau_min
    assert ss.exponents("mathieu", kappa=kappa, nu=nu, tau=tmin + 1e-3).gamma[0].real > 0
    assert ss.exponents("mathieu", kappa=kappa, nu=nu, tau=tmin - 1e-3).gamma[0].real < 0


def test_exact_resonance_reports_zero_with_its_uncertainty():
    """At sqrt(kappa) = 3/2, nu = 0, the unforced block is singular: tau = 0 is exact, and the
    defective eigenvalue's rounding spread is the reported error (no false precision)."""
    res = ss.floquet("mathieu", kind="subharmonic", kappa=2.25, nu=0.0).subharmonic
    assert res.tau_min == 0.0 and res.method == "qz"
    assert 0 < res.error_estimate < 1e-6


def test_no_stiffness_has_no_marginal_tau():
    res = ss.floquet("mathieu", kappa=0.0, nu=0.1)
    assert res.harmonic.tau_min is None and res.harmonic.tau.size == 0


def test_fixed_truncation_reports_its_error_and_convergence_error_raised():
    res = ss.floquet("mathieu", kind="subharmonic", kappa=0.26, nu=0.1, n_temporal=3)
    tight = ss.floquet("mathieu", kind="subharmonic", kappa=0.26, nu=0.1).subharmonic
    err = abs(res.subharmonic.tau_min - tight.tau_min)
    assert res.subharmonic.n_temporal == 3 and err <= res.subharmonic.error_estimate
    with pytest.raises(ss.ConvergenceError, match="did not converge"):
        marginal_tau(hill_system(kappa=0.26, nu=0.1), "subharmonic", tol=1e-15, n_max=4)


def test_error_estimate_bounds_the_true_error():
    """The reported estimate bounds |tau_min - tau_min(N = 60)|."""
    for kappa in (0.26, 1.3, 2.8):
        res = ss.floquet("mathieu", kappa=kappa, nu=0.05)
        ref = ss.floquet("mathieu", kappa=kappa, nu=0.05, n_temporal=60)
        for kind in ("harmonic", "subharmonic"):
            got, exact = getattr(res, kind), getattr(ref, kind)
            assert abs(got.tau_min - exact.tau_min) <= max(got.error_estimate, 1e-14)


def test_resonance_beyond_the_truncation_limit_fails_at_once_saying_what_to_change():
    """sqrt(kappa) = 500 forcing frequencies: no truncation N <= 400 reaches the resonance."""
    with pytest.raises(ss.ConvergenceError, match="lower the stiffness"):
        marginal_tau(hill_system(kappa=2.5e5, nu=0.1), "harmonic")
