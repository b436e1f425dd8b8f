"""Stress: every public entry point over the whole parameter space (nu in [1e-9, 10] and 0, kappa
in [1e-4, 1e3], m in [2, 60], truncations up to N = 200) returns only finite numbers, each result
carries an error estimate within its tolerance, and a failure is a ConvergenceError whose message
says what to change (or, outside a model's documented domain, a ParameterError naming the parameter).

The fast tests draw few, derandomised examples and cap fixed truncations; the slow ones draw many.
To cover a new model, add a parameter builder to ``BUILDERS`` (test_every_model_is_covered).
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from threadpoolctl import threadpool_limits

import spectralshell as ss
from spectralshell.models.cylinder import ZETA_MIN, lambda0_squared, zeta_max
from spectralshell.models.nonlinear_coefficients import NOT_NORMAL_MODES
from spectralshell.params.registry import models

# words with which a ConvergenceError tells the user what to change
ADVICE = re.compile(r"\b(relax|lower|raise|increase|reduce|decrease|use|choose|report|try|give|set)\b")


def _log(lo: float, hi: float):
    return st.floats(lo, hi).map(lambda x: 10.0 ** x)


def _amplitude(lo: float, hi: float):
    """tau in [lo, hi] as the API accepts it: 0 or of magnitude >= 1e-100 (_validate.REAL_MIN;
    below it the input is refused, tested in test_hostile_exits.py)."""
    return st.floats(lo, hi).filter(lambda x: x == 0.0 or abs(x) >= 1e-100)


def _cylinder_zeta(params: dict) -> tuple[float, float]:
    """zeta = nu/sqrt(kappa) range of the cylinder's natural modes (exponents continue from them)."""
    return ZETA_MIN, zeta_max(params["m"], params["k"], params.get("component", "coupled"))


NU = st.one_of(st.just(0.0), _log(-9, 1))
KAPPA = _log(-4, 3)
DEGREE = st.integers(2, 60)



def _cochlea(draw, m_max: int = 6) -> dict:
    """Graded stiffness with M cosine modes, or one mode K of the uniform membrane (alpha = 0)."""
    alpha = draw(st.one_of(st.just(0.0), _log(-2, 0.7)))
    common = {"kappa": draw(KAPPA), "nu": draw(NU), "alpha": alpha}
    if alpha == 0.0 and draw(st.booleans()):
        return {**common, "spatial_mode": draw(st.integers(1, 60))}
    return {**common, "n_spatial": draw(st.integers(1, m_max))}


def _cylinder(draw) -> dict:
    """One mode (m, k R) of the cylinder: the coupled set (m^2 + k^2 > 1), or with nu > 0 the
    decoupled torsion (m = 0) or axial (k = 0) component."""
    m, k, nu = draw(st.integers(0, 60)), draw(st.one_of(st.just(0.0), _log(-2, 1.3))), draw(NU)
    component = "coupled"
    if nu > 0 and (m == 0) != (k == 0) and draw(st.booleans()):
        component = "torsion" if m == 0 else "axial"
    elif m * m + k * k <= 1.0:
        k += 1.5
    return {"m": m, "k": k, "kappa": draw(KAPPA), "nu": nu, "component": component}


BUILDERS = {
    "mathieu": lambda draw: {"kappa": draw(KAPPA), "nu": draw(NU)},
    "sphere": lambda draw: {"m": draw(DEGREE), "kappa": draw(KAPPA), "nu": draw(NU),
                            "component": draw(st.sampled_from(["poloidal", "toroidal"]))},
    "fibre": lambda draw: {"m": draw(DEGREE), "kappa": draw(KAPPA), "nu": draw(NU),
                           "forcing": draw(st.sampled_from(["both", "pressure", "tangential"]))},
    "cochlea": _cochlea,
    "cylinder": _cylinder,
}


def resonant_index(model: str, params: dict) -> float:
    """lambda0 of the inviscid limit: the Fourier index the truncation N must exceed, so the cost
    of a converged solve grows with it (closed forms: Mathieu, Rayleigh, Lamb, cochlea mode k)."""
    kappa, m = params["kappa"], params.get("m", 2)
    if model == "cylinder":  # lambda0^2 = kappa (m^2 + k^2 - 1)/M(m, k); the tangential sets: none
        coupled = params["component"] == "coupled"
        return math.sqrt(lambda0_squared(m, params["k"], kappa)) if coupled else 0.0
    unit = {"mathieu": 1.0, "fibre": m * (m * m - 1) / 2, "sphere": m * (m + 1) * (m - 1) * (m + 2) / (2 * m + 1),
            "cochlea": (params.get("spatial_mode") or params.get("n_spatial") or 1) / 2}[model]
    return math.sqrt(kappa * unit)


@st.composite
def model_params(draw, models=tuple(BUILDERS), cap: float | None = None):
    """(model, params); with ``cap`` only parameters whose resonant index is <= cap (fast tests)."""
    model = draw(st.sampled_from(models))
    params = BUILDERS[model](draw)
    if cap is not None:
        assume(resonant_index(model, params) <= cap)
    return model, params


def _finite_json(result) -> None:
    """No NaN or inf anywhere in what the user receives (the JSON form of the result)."""
    json.dumps(result.to_dict(), allow_nan=False)


def attempt(fn):
    """The result of ``fn``, or None after a ConvergenceError that says what to change."""
    try:
        return fn()
    except ss.ConvergenceError as exc:
        assert ADVICE.search(str(exc)), f"ConvergenceError without advice: {exc}"
        assert "\n" not in str(exc)
        return None


def check_marginal(m, tol: float | None, warnings: tuple[str, ...] = ()) -> None:
    """Finite, non-negative tau; converged to tol, else (rounding-limited, e.g. a multiple tau = 0
    at a finger tip) the result says so in a warning naming the kind and its error estimate."""
    assert np.all(np.isfinite(m.tau)) and np.all(m.tau >= 0)
    if m.tau_min is None:
        return
    assert math.isfinite(m.tau_min) and math.isfinite(m.error_estimate) and m.error_estimate >= 0
    if tol is not None and m.error_estimate > tol:  # converged to tol, not a fixed truncation
        flag = f"{m.kind} tau_min = {m.tau_min:.6g} is resolved only to {m.error_estimate:.1e}"
        assert any(w.startswith(flag) for w in warnings), (m.tau_min, m.error_estimate, warnings)


FAST = settings(max_examples=8, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
CAP = 30.0  # fast tests: resonant index <= 30, so converged truncations stay below N ~ 60
SLOW = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@pytest.fixture(autouse=True)
def one_blas_thread():
    """Timing robustness on a shared machine: a loaded box makes multi-threaded BLAS spin."""
    with threadpool_limits(1):
        yield


def test_every_model_is_covered():
    assert set(models()) <= set(BUILDERS), f"add a parameter builder for {set(models()) - set(BUILDERS)}"


# ----------------------------------------------------------------- floquet


def _floquet(model, params, kind, tol, n_temporal, tau_max):
    res = attempt(lambda: ss.floquet(model, kind=kind, tol=tol, n_temporal=n_temporal, tau_max=tau_max,
                                     **params))
    if res is None:
        return
    _finite_json(res)
    for k in ("harmonic", "subharmonic"):
        m = getattr(res, k)
        assert (m is None) == (kind not in ("both", k))
        if m is not None:  # a fixed truncation (N, or M spatial modes) has no tolerance to meet
            fixed = n_temporal is not None or params.get("n_spatial") is not None
            check_marginal(m, None if fixed else tol, res.warnings)
            if tau_max is not None:
                assert np.all(m.tau <= tau_max)


# the converged path is bounded by tau_max = 1/2 in the fast test (the physical range); fixed
# truncations are capped at N = 40 there (N = 200 costs seconds per solve for m ~ 60)
@FAST
@given(mp=model_params(cap=CAP), kind=st.sampled_from(["both", "harmonic", "subharmonic"]))
def test_floquet_converged_physical_range(mp, kind):
    _floquet(*mp, kind, 1e-8, None, 0.5)


@FAST
@given(mp=model_params(), n=st.integers(1, 40), kind=st.sampled_from(["harmonic", "subharmonic"]))
def test_floquet_fixed_truncation(mp, n, kind):
    _floquet(*mp, kind, 1e-10, n, None)


@pytest.mark.slow
@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kappa=KAPPA, nu=NU, alpha=_log(-2, 0.7), n_spatial=st.sampled_from([100, 200, 300]),
       kind=st.sampled_from(["harmonic", "subharmonic"]))
def test_floquet_cochlea_thesis_size_blocks(kappa, nu, alpha, n_spatial, kind):
    """M up to 300 spatial modes (the thesis ran M = 250) at N = 20: finite or advised failure."""
    params = {"kappa": kappa, "nu": nu, "alpha": alpha, "n_spatial": n_spatial}
    _floquet("cochlea", params, kind, 1e-10, 20, None)


@pytest.mark.slow
@SLOW
@given(mp=model_params(), kind=st.sampled_from(["both", "harmonic", "subharmonic"]),
       tol=st.sampled_from([1e-6, 1e-10]), tau_max=st.sampled_from([None, 0.5, 2.0]))
def test_floquet_converged_slow(mp, kind, tol, tau_max):
    _floquet(*mp, kind, tol, None, tau_max)


@pytest.mark.slow
@SLOW
@given(mp=model_params(), n=st.integers(1, 200), kind=st.sampled_from(["harmonic", "subharmonic"]))
def test_floquet_fixed_truncation_slow(mp, n, kind):
    _floquet(*mp, kind, 1e-10, n, None)


# ----------------------------------------------------------------- exponents


def _exponents(model, params, tau, n_temporal):
    still = model == "sphere" and params["nu"] == 0.0 and params["component"] == "toroidal"
    if still:  # no restoring force: refused, naming why
        with pytest.raises(ss.ParameterError, match=r"^parameters .* are invalid for Floquet exponents"):
            ss.exponents(model, tau=tau, n_temporal=n_temporal, **params)
        return
    zeta = params["nu"] / math.sqrt(params["kappa"])
    if model == "cylinder" and params["nu"] > 0 and not \
            _cylinder_zeta(params)[0] <= zeta <= _cylinder_zeta(params)[1]:
        with pytest.raises(ss.ParameterError, match=r"^zeta = .* is invalid: .* continued from"):
            ss.exponents(model, tau=tau, n_temporal=n_temporal, **params)
        return
    if model == "cochlea" and params["nu"] > 0 and "spatial_mode" in params:  # no natural modes
        with pytest.raises(ss.ParameterError, match=r"^n_spatial = None is invalid .* continued from"):
            ss.exponents(model, tau=tau, n_temporal=n_temporal, **params)
        return
    res = attempt(lambda: ss.exponents(model, tau=tau, n_temporal=n_temporal, **params))
    if res is None:
        return
    _finite_json(res)
    assert np.all(np.isfinite(res.gamma)) and np.all(np.abs(res.gamma.imag) <= 0.5 + 1e-12)
    if res.complete_in is not None:  # a viscous model: the listed exponents lie in the counted range
        lo, hi = res.complete_in
        assert np.all((res.gamma.real > lo) & (res.gamma.real <= hi))
    assert math.isfinite(res.error_estimate)
    if res.spatial_change is not None:  # n_spatial = M: the change from M // 2 is included
        assert res.error_estimate >= res.spatial_change
    if n_temporal is None:  # converged in N: what exceeds tol is the spatial change
        assert res.error_estimate <= 1e-10 or res.error_estimate == res.spatial_change


@FAST
@given(mp=model_params(cap=CAP), tau=_amplitude(0.0, 0.5), n=st.one_of(st.none(), st.integers(1, 40)))
def test_exponents(mp, tau, n):
    _exponents(*mp, tau, n)


@pytest.mark.slow
@SLOW
@given(mp=model_params(), tau=_amplitude(-2.0, 2.0), n=st.one_of(st.none(), st.integers(1, 200)))
def test_exponents_slow(mp, tau, n):
    _exponents(*mp, tau, n)


# ----------------------------------------------------------------- stability


def _stability(model, params, tau, width):
    lo = min(params["m"], 60 - width)
    params = {k: v for k, v in params.items() if k != "m"}
    res = attempt(lambda: ss.stability(model, tau=tau, m=f"{lo}:{lo + width}", tol=1e-8, **params))
    if res is None:
        return
    _finite_json(res)
    assert [d["m"] for d in res.modes] == list(range(lo, lo + width + 1))
    for d in res.modes:
        below = [t for k in ("harmonic", "subharmonic") for t in d.get(f"tau_{k}", [])]
        assert all(math.isfinite(t) and 0 <= t < tau for t in below)
        assert d["unstable"] == (d["kind"] is not None)


@FAST
@given(mp=model_params(("sphere", "fibre"), cap=CAP), tau=_amplitude(0.01, 0.5), width=st.integers(0, 2))
def test_stability(mp, tau, width):
    _stability(*mp, tau, width)


@pytest.mark.slow
@SLOW
@given(mp=model_params(("sphere", "fibre")), tau=_amplitude(0.0, 1.0), width=st.integers(0, 4))
def test_stability_slow(mp, tau, width):
    _stability(*mp, tau, width)


# ----------------------------------------------------------------- tongues


def _tongues(model, params, spread):
    params = dict(params)
    kappa = params.pop("kappa")
    grid = kappa * np.array([1.0, 1.0 + spread, 1.0 + 2 * spread])
    res = attempt(lambda: ss.tongues(model, kappa=grid, tol=1e-8, tau_max=0.5, workers=1, **params))
    if res is None:
        return
    _finite_json(res)
    for row in res.rows:
        for m in row.values():
            check_marginal(m, None if params.get("n_spatial") is not None else 1e-8)
    for tip in res.tips:
        assert all(math.isfinite(v) for v in (tip.kappa, tip.tau, tip.kappa_error, tip.tau_error))
        assert grid[0] <= tip.kappa <= grid[-1]


@FAST
@given(mp=model_params(cap=CAP), spread=_log(-3, 0))
def test_tongues_at_a_few_kappa(mp, spread):
    _tongues(*mp, spread)


@pytest.mark.slow
@SLOW
@given(mp=model_params(), spread=_log(-4, 0))
def test_tongues_slow(mp, spread):
    _tongues(*mp, spread)


# ----------------------------------------------------------------- natural modes


def _modes(model, params, count, precision):
    zeta = params["nu"] / math.sqrt(params["kappa"])
    call = lambda: ss.natural_modes(model, count=count, precision=precision, **params)  # noqa: E731
    if params["nu"] == 0.0 and params.get("component") == "toroidal":
        with pytest.raises(ss.ParameterError, match="toroidal"):
            call()
        return
    lo, hi = _cylinder_zeta(params) if model == "cylinder" else (1e-10, 1e3)
    if params["nu"] > 0 and not lo <= zeta <= hi:  # the documented domain of the mode solvers
        with pytest.raises(ss.ParameterError, match=r"^zeta = .* is invalid: must be in"):
            call()
        return
    if params["nu"] == 0.0 and count == 2:  # the inviscid models have one mode: flagged, not refused
        res = call()
        assert res.gamma.size == 1 and "count = 2" in res.warnings[0]
        return
    try:
        res = attempt(call)
    except ss.ParameterError as exc:  # the fibre's zeta domain narrows with m (modes coalesce)
        assert model == "fibre" and re.match(r"^zeta = .* is invalid: must be in", str(exc)), exc
        return
    if res is None:
        return
    _finite_json(res)
    assert np.all(np.isfinite(res.gamma)) and np.all(np.isfinite(res.error_estimate))
    # one of each conjugate pair: Im gamma >= 0, up to the error of a root on the real axis
    assert np.all(res.gamma.imag >= -res.error_estimate) and np.all(res.gamma.real <= 0)
    assert np.all(res.error_estimate <= 1e-10 * np.abs(res.gamma))


@FAST
@given(mp=model_params(("sphere", "fibre", "cylinder")), count=st.sampled_from([None, 1, 2]),
       precision=st.sampled_from([None, 20]))
def test_natural_modes(mp, count, precision):
    model, params = mp
    if params.get("component") == "toroidal" and count == 2:
        count = 1
    _modes(model, params, count, precision)


@pytest.mark.slow
@SLOW
@given(mp=model_params(("sphere", "fibre", "cylinder")), count=st.sampled_from([None, 1]),
       precision=st.sampled_from([None, 30]))
def test_natural_modes_slow(mp, count, precision):
    _modes(*mp, count, precision)


# ----------------------------------------------------------------- nonlinear coefficients


@FAST
@given(m=st.integers(2, 60), data=st.data())
def test_lp_coefficient(m, data):
    k = data.draw(st.integers(-m, m))
    defined = m <= 8 and (m, abs(k)) not in NOT_NORMAL_MODES
    if not defined:
        with pytest.raises(ss.ParameterError, match=r"^(m|k) = .* is invalid"):
            ss.lp_coefficient(m, k)
        return
    for volume in ("reference", "literal"):
        c = ss.lp_coefficient(m, k, volume=volume)
        assert math.isfinite(c) and -10 < c < 1


def test_rounding_limited_tau_zero_is_flagged():
    """At the subharmonic tip sqrt(kappa) = 3/2 of the undamped Mathieu equation tau = 0 is a
    double eigenvalue: the value converges in N but rounding splits it by ~sqrt(eps) (~6e-8), above
    tol = 1e-10, so the result says so (found by test_floquet_converged_slow); the converged
    harmonic value is not flagged."""
    res = ss.floquet("mathieu", kappa=2.25, nu=0.0, tol=1e-10)
    sub, har = res.subharmonic, res.harmonic
    assert sub.tau_min == 0.0 and 1e-10 < sub.error_estimate < 1e-6
    assert har.error_estimate <= 1e-10
    flags = [w for w in res.warnings if "resolved only to" in w]
    assert len(flags) == 1 and flags[0].startswith("subharmonic tau_min = 0 is resolved only to")
    assert not [w for w in ss.floquet("mathieu", kappa=2.25, nu=0.0, n_temporal=20).warnings
                if "resolved only to" in w]  # a fixed truncation has no tol to meet
