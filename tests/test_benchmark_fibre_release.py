"""fibre-release (issue 29) by exact Laplace inversion: the late-time decay against the fibre's
dispersion relation over the offered range, the early times against a plain Talbot inversion
that uses no natural modes, the velocity against the amplitude's derivative, score on
synthetic runs with known perturbations, bit-identical writing through the CLI, bad input."""

import math

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.models.registry import hill_system
from spectralshell.params.registry import make_params
from spectralshell.runner.benchmark import score_window
from spectralshell.solvers.laplace import release, release_transforms, talbot

from benchmark_cases import (amplitude_scorer, check_rate_and_noise, check_self_score,
                             cli_writes, reference_params, refused_in_one_line,
                             timed_benchmark)


@pytest.fixture(scope="module")
def reference():
    return timed_benchmark("fibre-release")


def _mu(zeta, p):
    """mu giving zeta = mu / (R sqrt(rho sigma)) at the default R, rho, sigma."""
    return zeta * p["radius"] * math.sqrt(p["rho"] * p["sigma"])


@pytest.mark.parametrize("zeta, m", [(1e-3, 2), (1e-3, 12), (0.05, 2), (0.05, 12)])
def test_range_corners_match_the_dispersion_relation(reference, zeta, m):
    """The decay rate and frequency fitted (DMD, over the decay by e^-12 after 4 periods of
    transient) from the series agree with the least damped root of the fibre's dispersion
    relation to 1e-8 in units of 1/T at the corners of the offered range (measured <= 1.3e-9);
    the series has decayed to the continuous spectrum's tail by its end."""
    ds = ss.benchmark("fibre-release", mu=_mu(zeta, reference_params(reference)), m=m)
    T = reference_params(ds)["T"]
    mode = complex(ss.natural_modes("fibre", m=m, kappa=1.0, nu=zeta, count=1).gamma[0])
    assert abs(ds.attrs["fitted_growth_rate"] * T - mode.real) < 1e-8
    assert abs(ds.attrs["fitted_frequency"] * T - mode.imag) < 1e-8
    a = np.abs(ds["amplitude"].values)
    assert np.max(a[-32:]) < 1e-4 * a[0]


def test_reference_starts_at_rest_and_is_bounded(reference):
    """A(0) = epsilon R, u_r(0) = 0; error bounds below 1e-10 of the largest value; written in
    under a minute (measured ~4 s)."""
    p = reference_params(reference)
    assert reference["amplitude"].values[0] == p["epsilon"] * p["radius"]
    assert reference["u_r"].values[0] == 0.0
    for name in ("amplitude", "u_r"):
        scale = np.max(np.abs(reference[name].values))
        assert np.max(reference[name + "_error"].values) < 1e-10 * scale
        assert reference[name].attrs["units"] == {"amplitude": "cm", "u_r": "cm/s"}[name]
    assert reference.attrs["seconds"] < 60


def test_early_times_match_a_plain_talbot_inversion(reference):
    """Up to t = T / 2, where a 40-node Talbot contour encloses both natural modes with margin
    (it crosses the imaginary axis near 34 / T; the fast Stokes-layer mode has |Im gamma| ~ 12 / T),
    the transform inverted as a whole (no modes used) equals the reference method's residues
    plus continuous part to 1e-11 of A0."""
    p = reference_params(reference)
    system = hill_system(make_params("fibre", {"m": p["m"], "kappa": 1.0, "nu": p["zeta"]}))
    modes = ss.natural_modes("fibre", m=p["m"], kappa=1.0, nu=p["zeta"]).gamma
    t = np.linspace(0.01, 0.5, 25)
    x0 = np.array([p["epsilon"], 0.0])
    plain = talbot(release_transforms(system.unforced, x0), t, 40)
    run = release(system.unforced, x0, t, modes)
    assert np.max(np.abs(plain[0] - run.position)) < 1e-11 * p["epsilon"]
    assert np.max(np.abs(plain[1] - run.velocity)) < 1e-11 * p["epsilon"]


def test_velocity_is_the_derivative_of_the_amplitude(reference):
    """u_r (inverted from its own transform -D^-1 K X0) = d/dt of the amplitude series (cubic
    spline, 32 samples per period: error ~1e-4 of max |u_r|)."""
    t, a, u = (reference[k].values for k in ("t", "amplitude", "u_r"))
    derivative = CubicSpline(t, a)(t, 1)
    inner = slice(4, -4)
    assert np.max(np.abs(derivative[inner] - u[inner])) < 1e-3 * np.max(np.abs(u))


def test_score_reports_known_perturbations(reference, tmp_path):
    """Synthetic user runs: the reference itself (zero error), a clock offset (L2 error =
    shift ||u_r|| / ||A||), a wrong decay rate (fitted rate = reference fit + delta), noise
    (L2 error = ||noise|| / ||A||, rate within 5 standard errors), a different sampling (every
    third sample: small L2 error, the same rate)."""
    t, a = reference["t"].values, reference["amplitude"].values
    guess = complex(reference.attrs["exact_growth_rate"], reference.attrs["exact_frequency"])

    run = amplitude_scorer("fibre-release", reference, tmp_path)
    same = run("same", t, a)
    check_self_score(same, guess)

    shift = 0.02 * 2 * math.pi / guess.imag
    shifted = run("shift", t - shift, a)
    expected = shift * np.linalg.norm(reference["u_r"].values) / np.linalg.norm(a)
    assert shifted.relative_l2 == pytest.approx(expected, rel=0.05)
    assert shifted.growth_rate == pytest.approx(same.growth_rate, rel=1e-4)

    check_rate_and_noise(run, score_window(reference)[0], t, a, same, guess,
                         np.random.default_rng(29))

    sparse = run("sparse", t[::3], a[::3])
    assert 0 < sparse.relative_l2 < 1e-2
    assert abs(sparse.growth_rate - same.growth_rate) < 1e-4 * abs(guess.real)


def test_cli_writes_the_same_bytes(reference, tmp_path, capsys):
    """write through the CLI = write_netcdf / write_csv of the same computation (bit for bit);
    list and show name it; bad input exits 2 with one line."""
    ref = reference.copy()
    del ref.attrs["seconds"]
    cli_writes("fibre-release", ref, tmp_path, capsys)
    assert main(["benchmark", "list"]) == 0
    assert "fibre-release" in capsys.readouterr().out
    assert main(["benchmark", "show", "fibre-release", "--m", "3"]) == 0
    text = capsys.readouterr().out
    assert "m = 3" in text and "sigma* = sigma / Delta s = sigma N / (2 pi)" in text
    refused_in_one_line((["benchmark", "show", "fibre-release", "--m", "13"],
                         ["benchmark", "show", "fibre-release", "--l", "3"],
                         ["benchmark", "show", "fibre-release", "--mu", "10"],
                         ["benchmark", "write", "fibre-release", "--out", str(tmp_path),
                          "--m", "x"]),
                        capsys)
