"""No silent empty answer: the marginal tau of the strongly damped Mathieu equation against a
time-stepped monodromy oracle (issue 23, section 2).

Oracle. With u = exp(-nu t / 2) w, u'' + nu u' + kappa (1 + 2 tau sin t) u = 0 becomes the
undamped Hill equation w'' + (kappa (1 + 2 tau sin t) - nu^2 / 4) w = 0, whose monodromy M_w
has det M_w = 1. A u-multiplier +1 (harmonic) or -1 (subharmonic) is a w-multiplier
+-exp(pi nu), i.e. tr M_w = +-2 cosh(pi nu). M_w is integrated with scipy's DOP853 (rtol 1e-11)
over PIECES sub-intervals whose transfer matrices are multiplied with a running scale, so that
log|tr M_w| stays finite for nu up to 300 (exp(300 pi) overflows a double), all sample
amplitudes in one vectorised integration. F_kind(tau) = sign(tr) exp(log|tr| - log(2 cosh pi nu))
-+ 1 vanishes exactly at a marginal tau of that kind. Nothing here uses the Hill method.

Claims tested, for nu in {10, 30, 100, 300}, several kappa, both kinds: ``ss.floquet`` never
returns an empty list without a finite ``tau_max``; a tau_min it returns is a root of F (a sign
change in +-1e-6 relative) with no sign change of F on a grid below it; where it raises
ConvergenceError, the bound B it states ("proved only for tau <= B") holds on the oracle's grid
and a marginal tau above B exists; with tau_max = B/2 it returns "none" with complete_to >= tau_max.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import spectralshell as ss

PIECES = 64


def oracle(kappa: float, nu: float, tau: np.ndarray, kind: str) -> np.ndarray:
    """F_kind at each amplitude of ``tau`` (module notes): its zeros are the marginal tau."""
    tau = np.atleast_1d(np.asarray(tau, dtype=float))
    k = tau.size

    def rhs(t, y):
        q = kappa * (1 + 2 * tau * math.sin(t)) - nu * nu / 4
        y = y.reshape(4, k)
        return np.concatenate([y[1], -q * y[0], y[3], -q * y[2]])

    M = np.broadcast_to(np.eye(2), (k, 2, 2)).copy()
    log_scale = np.zeros(k)
    edges = np.linspace(0, 2 * np.pi, PIECES + 1)
    start = np.concatenate([np.ones(k), np.zeros(k), np.zeros(k), np.ones(k)])
    for a, b in zip(edges[:-1], edges[1:]):
        y = solve_ivp(rhs, (a, b), start, method="DOP853", rtol=1e-11, atol=1e-12).y[:, -1]
        y = y.reshape(4, k)
        P = np.stack([np.stack([y[0], y[2]], -1), np.stack([y[1], y[3]], -1)], -2)
        M = P @ M
        s = np.abs(M).max(axis=(1, 2))
        M /= s[:, None, None]
        log_scale += np.log(s)
    trace = M[:, 0, 0] + M[:, 1, 1]
    target = math.pi * nu + math.log1p(math.exp(-2 * math.pi * nu))
    ratio = np.sign(trace) * np.exp(np.minimum(log_scale + np.log(np.abs(trace)) - target, 50.0))
    return ratio - 1 if kind == "harmonic" else ratio + 1


def sign_changes(values: np.ndarray) -> int:
    return int(np.count_nonzero(np.diff(np.sign(values)) != 0))


def test_oracle_agrees_with_the_plain_monodromy_at_moderate_damping(monodromy):
    """The scaled oracle against the unscaled monodromy matrix of tests/conftest.py (nu = 3,
    where exp(3 pi) is harmless): F = 0 <=> det(M -+ I) = 0, checked by the sign pattern."""
    kappa, nu = 1.0, 3.0
    taus = np.linspace(1.0, 30.0, 30)
    for kind, sign in (("harmonic", -1), ("subharmonic", 1)):
        ours = oracle(kappa, nu, taus, kind)
        plain = [np.linalg.det(monodromy(kappa, nu, t) + sign * np.eye(2)) for t in taus]
        assert np.array_equal(np.sign(ours) == np.sign(ours[0]),
                              np.sign(plain) == np.sign(plain[0]))


def _check(kappa: float, nu: float, kind: str) -> None:
    try:
        res = ss.floquet("mathieu", kappa=kappa, nu=nu, kind=kind, tol=1e-6)
    except ss.ConvergenceError as exc:
        match = re.search(r"proved only for tau <= ([0-9.e+-]+)", str(exc))
        assert match, str(exc)
        bound = float(match.group(1))
        below = np.linspace(0.0, bound, 48)
        assert sign_changes(oracle(kappa, nu, below, kind)) == 0, "the stated bound is false"
        above = np.geomspace(bound, 200 * bound, 64)
        assert sign_changes(oracle(kappa, nu, above, kind)) > 0, "no marginal tau exists at all?"
        capped = ss.floquet("mathieu", kappa=kappa, nu=nu, kind=kind, tol=1e-6,
                            tau_max=bound / 2)
        m = getattr(capped, kind)
        assert m.tau_min is None and m.complete_to >= bound / 2
        return
    m = getattr(res, kind)
    assert m.tau_min is not None, "an empty answer without a bound"
    t = m.tau_min
    assert sign_changes(oracle(kappa, nu, [t * (1 - 1e-6), t * (1 + 1e-6)], kind)) == 1
    assert sign_changes(oracle(kappa, nu, np.linspace(0.0, t * (1 - 1e-6), 48), kind)) == 0
    assert m.complete_to >= t


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
@pytest.mark.parametrize("kappa, nu", [(0.25, 10.0), (1.0, 10.0), (0.25, 30.0), (2.5, 30.0),
                                       (0.25, 100.0)])
def test_strong_damping_finds_tau_or_states_a_true_bound(kappa, nu, kind):
    _check(kappa, nu, kind)


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
@pytest.mark.parametrize("kappa, nu", [(1.0, 100.0), (0.25, 300.0), (1.0, 300.0)])
def test_strong_damping_finds_tau_or_states_a_true_bound_slow(kappa, nu, kind):
    _check(kappa, nu, kind)


@pytest.mark.parametrize("nu", [1e3, 1e100])
def test_extreme_damping_never_answers_empty_silently(nu):
    """nu = 1e3 .. 1e100 (the largest input accepted): either a tau or a ConvergenceError naming the proved bound."""
    try:
        res = ss.floquet("mathieu", kappa=0.25, nu=nu)
    except ss.ConvergenceError as exc:
        assert "proved only for tau <=" in str(exc) or "did not converge" in str(exc)
        return
    for m in (res.harmonic, res.subharmonic):
        assert m.tau_min is not None and np.isfinite(m.tau_min)


def test_cli_reports_complete_to_and_exits_1(tmp_path):
    from spectralshell.cli import main
    import contextlib
    import io
    import json
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(["floquet", "mathieu", "--kappa", "0.25", "--nu", "30", "--json"])
    assert rc == 1 and "proved only for tau <=" in err.getvalue()
    assert len(err.getvalue().strip().splitlines()) >= 1 and "Traceback" not in err.getvalue()
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        rc = main(["floquet", "mathieu", "--kappa", "0.25", "--nu", "30", "--tau-max", "500",
                   "--json"])
    data = json.loads(out.getvalue())
    assert rc == 0
    for kind in ("harmonic", "subharmonic"):
        assert data[kind]["tau"] == [] and data[kind]["complete_to"] >= 500


@pytest.mark.parametrize("nu", [1e6, 1e10, 1e100])
def test_strongly_damped_exponents_are_refused_or_within_their_estimate(nu):
    """Oracle: for nu >> kappa the exponents of u'' + nu u' + kappa (1 + 2 tau sin t) u = 0 are
    -kappa / nu (quasi-static u' = -(kappa / nu)(1 + 2 tau sin t) u, whose mean of sin t is 0;
    next term O(kappa^2 / nu^3)) and -nu + kappa / nu. At tol = 1e-10 rounding (eps nu) forbids
    an answer: refused, naming the tol that is reachable; at that tol the answer holds it."""
    kappa, tau = 1.0, 0.3
    with pytest.raises(ss.ConvergenceError, match=r"relax tol= to at least") as err:
        ss.exponents("mathieu", kappa=kappa, nu=nu, tau=tau)
    reachable = 2 * float(re.search(r"at least (\S+)$", str(err.value)).group(1))
    res = ss.exponents("mathieu", kappa=kappa, nu=nu, tau=tau, tol=reachable)
    want = np.array([-kappa / nu, -nu + kappa / nu])
    assert res.error_estimate <= reachable
    assert np.max(np.abs(np.sort(res.gamma.real)[::-1] - want)) <= res.error_estimate
    assert np.max(np.abs(res.gamma.imag)) <= res.error_estimate
