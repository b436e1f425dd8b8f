"""Spherical membrane Floquet analysis (thesis chapter 6) against independent evidence."""

import mpmath as mp
import numpy as np
import pytest

import spectralshell as ss
from spectralshell.discretise.hill import assemble
from spectralshell.models.sphere import hill_system, lambda0_squared, poloidal_unforced
from spectralshell.solvers.marginal import dense_taus, marginal_tau, solve_truncation


def mp_poloidal(s, m, kappa, nu):
    """D(s) of derivations/sphere_linear_result.md evaluated in mpmath at 30 digits with mpmath's
    own modified Bessel functions I, K of half-integer order (an oracle for the float kernels)."""
    mp.mp.dps = 30
    s = mp.mpc(s)
    beta = mp.sqrt(s / nu)
    i_ratio = mp.besseli(m + 1.5, beta) / mp.besseli(m + 0.5, beta)
    k_ratio = mp.besselk(m - 0.5, beta) / mp.besselk(m + 0.5, beta)
    P, Q = beta * i_ratio, beta * k_ratio
    q = kappa * (m - 1) * (m + 2)
    yy = s**2 * (mp.mpf(2 * m + 1) / (m * (m + 1)) + m / ((m + 1) * Q) + (m + 1) / (m * P)) + q
    ypsi = s**2 * (m / Q - (m + 1) / P)
    psipsi = s**2 * (1 / Q + 1 / P) + q
    return np.array([[complex(yy), complex(ypsi)], [complex(ypsi / (m * (m + 1))), complex(psipsi)]])


@pytest.mark.parametrize("m", [2, 3, 10, 60])
@pytest.mark.parametrize("nu", [1e-9, 1e-4, 0.006, 10.0])
@pytest.mark.parametrize("s", [0.5j, 1j, 7.5j, 400j, 0.3 + 2j])
def test_unforced_block_matches_mpmath(m, nu, s):
    """Float D(s) (ratio kernels) against mpmath at 30 digits, nu from 1e-9 to 10, n up to 400."""
    got = poloidal_unforced(np.array([s]), m=m, kappa=0.02, nu=nu)[0]
    want = mp_poloidal(s, m, 0.02, nu)
    assert np.all(np.isfinite(got))
    assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))


def test_unforced_block_is_real_in_time_domain():
    """D(conj s) = conj D(s) (real operator), needed by the reality conditions (2.7)/(2.8)."""
    s = np.array([0.2 + 1.5j, 3j, 0.7 + 0.1j])
    a = poloidal_unforced(s, m=3, kappa=0.05, nu=0.01)
    b = poloidal_unforced(s.conj(), m=3, kappa=0.05, nu=0.01)
    np.testing.assert_allclose(b, a.conj(), rtol=1e-14)


def test_inviscid_limit_rate():
    """Viscous tau_min tends to the inviscid Mathieu value (kappa -> lambda0^2, (6.23)) as
    nu -> 0, with the Stokes-layer rate |difference| ~ nu^(1/2)."""
    m, kappa = 3, 0.02
    inviscid = ss.floquet("mathieu", kind="subharmonic", kappa=lambda0_squared(m, kappa),
                          nu=0.0).subharmonic
    assert ss.floquet("sphere", kind="subharmonic", m=m, kappa=kappa, nu=0.0).subharmonic.tau_min \
        == inviscid.tau_min
    nus = np.array([1e-6, 1e-7, 1e-8, 1e-9])
    diff = [abs(ss.floquet("sphere", kind="subharmonic", m=m, kappa=kappa, nu=nu).subharmonic.tau_min
                - inviscid.tau_min) for nu in nus]
    slope = np.polyfit(np.log(nus), np.log(diff), 1)[0]
    assert abs(slope - 0.5) < 0.05
    assert diff[-1] < 2e-4


@pytest.mark.parametrize("case,nu,kappa,m,kind", [(1, 0.006, 0.02, 3, "subharmonic"),
                                                   (2, 0.002, 0.06, 2, "subharmonic"),
                                                   (3, 0.001, 0.0075, 4, "subharmonic"),
                                                   (4, 0.004, 0.25, 2, "harmonic")])
def test_table_6_1_cases_unstable_mode_and_kind(case, nu, kappa, m, kind):
    """Thesis 6.4.2 / Fig 6.6: at tau = 0.45 exactly one degree in 2..6 is unstable in each case,
    the observed one, with period doubling in cases 1-3 and a harmonic response in case 4."""
    unstable = []
    for degree in range(2, 7):
        res = ss.floquet("sphere", m=degree, kappa=kappa, nu=nu)
        for k in ("harmonic", "subharmonic"):
            t = getattr(res, k)
            assert t.error_estimate < 1e-10
            if t.tau_min < 0.45:
                unstable.append((degree, k))
    assert unstable == [(m, kind)]


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_structured_matches_dense_for_2x2_blocks(kind):
    system = hill_system(m=2, kappa=0.06, nu=0.002)
    fast, method, _ = solve_truncation(system, kind, 30)
    dense = dense_taus(assemble(system, kind, 30, "real"))
    two_sided = dense_taus(assemble(system, kind, 30, "two-sided"))
    small = lambda t: np.sort(t[(t > 0) & (t < 20)])  # noqa: E731
    assert method == "structured"
    np.testing.assert_allclose(small(fast), small(dense), rtol=1e-9)
    np.testing.assert_allclose(small(two_sided), small(dense), rtol=1e-9)


@pytest.mark.parametrize("bad,fragment", [({"m": 1}, "rigid translation"), ({"m": 2.5}, "m = 2.5"),
                                          ({"m": 0}, "enclosed volume"), ({"kappa": 0.0}, "kappa = 0.0"),
                                          ({"nu": -1e-3}, "nu = -0.001"),
                                          ({"component": "spiral"}, "component = 'spiral'")])
def test_bad_sphere_parameters(bad, fragment):
    params = {"m": 3, "kappa": 0.02, "nu": 0.006, **bad}
    with pytest.raises(ss.ParameterError, match=fragment):
        ss.floquet("sphere", **params)


def test_numpy_strings_come_back_plain():
    """Names drawn from numpy arrays (np.str_) are accepted and reported as plain str, in results
    and in messages (no "np.str_('sphere')")."""
    res = ss.floquet(np.str_("sphere"), m=3, kappa=0.02, nu=0.006, kind=np.str_("subharmonic"))
    assert type(res.model) is str and res.params["component"] == "poloidal"
    assert type(ss.exponents(np.str_("sphere"), tau=0.3, m=2, kappa=0.1, nu=0.01).model) is str
    with pytest.raises(ss.ParameterError, match="nu is missing: model 'sphere' has"):
        ss.exponents(np.str_("sphere"), tau=0.3, m=2, kappa=0.1)


def test_cli_sphere_floquet_json(capsys):
    from spectralshell.cli import main
    import json
    assert main(["floquet", "sphere", "--m", "3", "--kappa", "0.02", "--nu", "0.006", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["model"] == "sphere" and data["params"]["m"] == 3
    api = ss.floquet("sphere", m=3, kappa=0.02, nu=0.006)  # the CLI is plumbing over the API
    assert data["subharmonic"]["tau_min"] == api.subharmonic.tau_min


def test_tau_max_skips_truncation_the_answer_does_not_use():
    """Asking only for tau <= 1/2 keeps the same physical values but stops the truncation early:
    near tau = 1/2 the Psi row (stiffness q (1 + 2 tau sin t), barely damped at small nu) makes
    the large-tau marginal values converge slowly (thesis 6.3: the tau > 1/2 subharmonic curve)."""
    system = hill_system(m=6, kappa=1.4, nu=2.4e-4)
    full = marginal_tau(system, "subharmonic", tol=1e-10)
    capped = marginal_tau(system, "subharmonic", tol=1e-10, tau_max=0.5)
    assert full.tau_min > 0.5 and capped.tau_min is None and capped.complete_to >= 0.5
    assert capped.n_temporal < full.n_temporal / 3
    harmonic_full = marginal_tau(system, "harmonic", tol=1e-10)
    harmonic = marginal_tau(system, "harmonic", tol=1e-10, tau_max=0.5)
    assert harmonic.tau_min == pytest.approx(harmonic_full.tau_min, abs=1e-10)
    np.testing.assert_allclose(harmonic.tau, harmonic_full.tau[harmonic_full.tau <= 0.5], atol=1e-9)


def test_a_fold_is_reported_as_no_finger_tip():
    """m = 2, nu = 0.002: the harmonic finger's two real tau (2.74 and 3.31 at kappa = 0.017, QZ
    of the dense pencil) merge and turn complex before kappa = 0.019, where the smallest real tau
    is near 20. tau_min(kappa) has a sampled minimum there but no smooth tip: refine_tip must say
    so instead of returning a tip."""
    from spectralshell.errors import ConvergenceError
    from spectralshell.solvers.tongues import refine_tip

    def factory(kappa):
        return hill_system(m=2, kappa=kappa, nu=0.002)

    def positive_taus(kappa):
        tau = dense_taus(assemble(factory(kappa), "harmonic", 40, "real"))
        return tau[tau > 0]

    below, above = positive_taus(0.017), positive_taus(0.019)
    assert np.sum(below < 4) == 2 and not np.any(above < 10)  # the fold lies in between
    with pytest.raises(ConvergenceError, match="not smooth there"):
        refine_tip(factory, "harmonic", 0.017, 0.019, float(below.min()))
