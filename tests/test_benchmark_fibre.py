"""fibre-parametric (issue 29): Floquet quantities only (the fibre stepper writes no series). The exponents
against the marginal amplitudes of the independent tau-eigenproblem, the eigen-shape against
the marginal solution's null vector, the 2D spring-constant relation against the arc force,
score on synthetic runs with known perturbations, bit-identical writing through the CLI."""

import json
import math

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.models.registry import hill_system
from spectralshell.params.registry import make_params
from spectralshell.runner.benchmark import score
from spectralshell.solvers.marginal_mode import floquet_mode, marginal_mode

from benchmark_cases import cli_writes, refused_in_one_line, user_csv

CASES = ("below", "above")


@pytest.fixture(scope="module")
def reference():
    return ss.benchmark("fibre-parametric")


def test_exponents_change_sign_at_the_marginal_amplitude(reference):
    """tau_min comes from the tau-eigenproblem of the Hill pencil (ss.floquet); the continued
    exponent (another solver) crosses zero there (|Re gamma| < 1e-9), decays below and grows
    above, each with growth per period exp(2 pi Re gamma) and the locked frequency omega / 2."""
    p = json.loads(reference.attrs["params"])
    floquet = json.loads(reference.attrs["floquet"])
    tip = ss.exponents("fibre", m=p["m"], kappa=p["kappa"], nu=p["nu"], tau=p["tau_min"],
                       count=1).gamma[0]
    assert abs(tip.real) < 1e-9 and tip.imag == pytest.approx(0.5)
    for case, sign in zip(CASES, (-1, 1)):
        c = floquet[case]
        assert np.sign(c["gamma_real"]) == sign and c["kind"] == "subharmonic"
        assert c["growth_per_period"] == pytest.approx(math.exp(2 * math.pi * c["gamma_real"]))
        assert c["growth_rate"] == pytest.approx(c["gamma_real"] * p["omega"])
        attrs = reference[f"shape_{case}"].attrs
        assert attrs["exact_growth_rate"] == c["growth_rate"]
        assert attrs["exact_frequency"] == pytest.approx(p["omega"] / 2)
        assert np.max(np.abs(reference[f"shape_{case}"].values)) == 1.0
        assert reference[f"shape_{case}_error"].max() < 1e-10
    assert "writes no\nseries" in reference.attrs["specification"]


def test_floquet_mode_is_the_marginal_solution():
    """At tau_min the eigen-shape of the exponent (dense SVD of T_N(g)) is the null vector of
    the marginal pencil A - tau B (sparse inverse iteration): the same periodic solution."""
    params = {"m": 3, "kappa": 0.02, "nu": 2e-4}
    tip = ss.floquet("fibre", kind="subharmonic", **params).subharmonic
    system = hill_system(make_params("fibre", params))
    gamma = complex(ss.exponents("fibre", tau=tip.tau_min, count=1, **params).gamma[0])
    n = 30
    t = np.linspace(0.0, 4 * np.pi, 50)
    ours = floquet_mode(system, tip.tau_min, gamma, n).evaluate(t)[:, 0]
    theirs = marginal_mode(system, "subharmonic", tip.tau_min, n).evaluate(t)[:, 0]
    theirs *= (ours @ theirs) / (theirs @ theirs)
    assert np.max(np.abs(ours - theirs)) < 1e-8 * np.max(np.abs(ours))
    with pytest.raises(ss.ParameterError, match="not periodic"):
        floquet_mode(system, tip.tau_min, complex(gamma.real, 0.3), n)


def test_spring_constant_of_the_2d_fibre():
    """sigma* = sigma N / (2 pi): the spring forces of N nodes on r = 1 + 0.05 cos(3 s) equal
    the exact arc forces sigma (X_s(s_j + ds/2) - X_s(s_j - ds/2)) to O(ds^2) (the error falls
    by 4 when N doubles)."""
    sigma = 2.0

    def position(s):
        r = 1 + 0.05 * np.cos(3 * s)
        return np.stack([r * np.cos(s), r * np.sin(s)])

    def tangent(s):
        r, dr = 1 + 0.05 * np.cos(3 * s), -0.15 * np.sin(3 * s)
        return np.stack([dr * np.cos(s) - r * np.sin(s), dr * np.sin(s) + r * np.cos(s)])

    errors = []
    for N in (384, 768):
        ds = 2 * np.pi / N
        s = np.arange(N) * ds
        X = position(s)
        springs = sigma * N / (2 * np.pi) * (np.roll(X, -1, 1) - 2 * X + np.roll(X, 1, 1))
        arc = sigma * (tangent(s + ds / 2) - tangent(s - ds / 2))
        errors.append(np.max(np.abs(springs - arc)) / np.max(np.abs(arc)))
    assert errors[0] < 1e-4 and errors[0] / errors[1] == pytest.approx(4.0, rel=0.01)


def test_score_reports_known_perturbations(reference, tmp_path):
    """Synthetic runs exp(g t) p(t) from the reference's exponent and eigen-shape: the exact
    rate (to 1e-12 relative, frequency omega / 2), a transient (the next Floquet solution,
    amplitude 1: rate within 1e-6), a wrong rate (+10 %), noise (within 5 standard errors);
    a run that ends before the fit window is refused."""
    floquet = json.loads(reference.attrs["floquet"])
    omega = json.loads(reference.attrs["params"])["omega"]
    end = reference.attrs["score_window"][1]
    rng = np.random.default_rng(4)

    def run(name, t, x, case):
        res, _, _ = score("fibre-parametric",
                          user_csv(tmp_path / f"{name}.csv", t, {f"amplitude_{case}": x}),
                          reference=reference)
        (q,) = res.quantities
        assert q.relative_l2 is None and q.reference_growth_rate is None
        return q

    for case in CASES:
        c = floquet[case]
        shape, dt = np.array(c["shape"]), c["shape_t"][1]
        n = np.arange(int(end / dt) + 2)
        t = n * dt
        x = np.exp(c["growth_rate"] * t) * shape[n % shape.size]
        exact = run(f"exact-{case}", t, x, case)
        assert abs(exact.growth_rate - c["growth_rate"]) < 1e-12 * abs(c["growth_rate"])
        assert exact.frequency == pytest.approx(omega / 2, rel=1e-12)
        transient = x + np.exp(c["next_growth_rate"] * t) * shape[(n + 16) % shape.size]
        q = run(f"transient-{case}", t, transient, case)
        assert abs(q.growth_rate - c["growth_rate"]) < 1e-6 * abs(c["growth_rate"])
        q = run(f"wrong-{case}", t, x * np.exp(0.1 * c["growth_rate"] * t), case)
        assert q.growth_rate == pytest.approx(1.1 * c["growth_rate"], rel=1e-9)
        noisy = x + 1e-3 * np.max(np.abs(x)) * rng.standard_normal(t.size)
        q = run(f"noise-{case}", t, noisy, case)
        assert abs(q.growth_rate - c["growth_rate"]) < 5 * q.fit_error
    half = t.size // 2
    short = user_csv(tmp_path / "short.csv", t[:half], {"amplitude_above": x[:half]})
    with pytest.raises(ss.ParameterError, match="must cover the fit window"):
        score("fibre-parametric", short, reference=reference)


def test_cli_writes_the_same_bytes(reference, tmp_path, capsys):
    """write through the CLI = write_netcdf / write_csv of the same computation; bad input
    exits 2 with one line."""
    cli_writes("fibre-parametric", reference, tmp_path, capsys)
    refused_in_one_line((["benchmark", "show", "fibre-parametric", "--m", "13"],
                         ["benchmark", "show", "fibre-parametric", "--l", "3"],
                         ["benchmark", "show", "fibre-parametric", "--mu", "1"]),
                        capsys)


def test_low_viscosity_needs_a_small_margin():
    """At nu = 5e-5 (the offered range's end) the exponent at 0.9 tau_min is not locked to the
    forcing (no periodic eigen-shape): refused, naming the margin; at margin 0.02 it is."""
    with pytest.raises(ss.ParameterError, match="smaller margin"):
        ss.benchmark("fibre-parametric", mu=0.005)
    ds = ss.benchmark("fibre-parametric", mu=0.005, margin=0.02)
    floquet = json.loads(ds.attrs["floquet"])
    assert floquet["below"]["gamma_real"] < 0 < floquet["above"]["gamma_real"]
    assert floquet["below"]["gamma_imag"] == 0.5
