"""The release from rest by exact Laplace inversion (solvers/laplace.py): against the closed
form of a damped oscillator, against the sphere's independent time stepper (sphere-release's
reference) within both error bounds, and its pole/continuous-spectrum split against a plain
Talbot inversion that uses no natural modes."""

import json

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.errors import ParameterError
from spectralshell.models.registry import hill_system
from spectralshell.params.registry import make_params
from spectralshell.runner.benchmark import real_harmonic
from spectralshell.solvers.laplace import release, release_transforms, talbot
from spectralshell.solvers.rate_fit import fit_rate


def test_damped_oscillator_closed_form():
    """D(s) = s^2 + nu s + kappa (Mathieu at tau = 0, no branch cut): X(0) = X0 at rest gives
    X = X0 e^(-nu t/2) (cos w t + nu/(2 w) sin w t), w^2 = kappa - nu^2/4, to 1e-12."""
    kappa, nu, x0 = 2.0, 0.3, 0.7
    system = hill_system(make_params("mathieu", {"kappa": kappa, "nu": nu}))
    w = np.sqrt(kappa - nu * nu / 4)
    t = np.linspace(0.0, 30.0, 301)
    run = release(system.unforced, np.array([x0]), t, [complex(-nu / 2, w)])
    decay = np.exp(-nu * t / 2)
    position = x0 * decay * (np.cos(w * t) + nu / (2 * w) * np.sin(w * t))
    velocity = -x0 * decay * (w + nu * nu / (4 * w)) * np.sin(w * t)
    assert np.max(np.abs(run.position[:, 0] - position)) < 1e-12 * x0
    assert np.max(np.abs(run.velocity[:, 0] - velocity)) < 1e-12 * x0
    assert np.max(run.position_error) < 1e-12


@pytest.fixture(scope="module")
def sphere():
    """sphere-release's reference (the SBDF4 stepper) and the Laplace release at its times."""
    ds = ss.benchmark("sphere-release")
    p = json.loads(ds.attrs["params"])
    system = hill_system(make_params("sphere", {"m": p["l"], "kappa": 1.0, "nu": p["zeta"]}))
    modes = ss.natural_modes("sphere", m=p["l"], kappa=1.0, nu=p["zeta"]).gamma
    run = release(system.unforced, np.array([p["epsilon"], 0.0]), ds["t"].values / p["T"],
                  modes)
    return ds, p, system, run


def test_sphere_release_matches_the_time_stepper(sphere):
    """Modal amplitude and pole velocity of the Laplace release = the independent time stepper's
    at every sample to within the sum of both error bounds (two resolutions each) plus a
    rounding floor of 1e-12 of the largest value (the bounds are differences of runs and do not
    see rounding: the amplitude decays by e^-12 over the series); the Laplace bound is the
    smaller (measured 7e-13 against 8e-11 cm)."""
    ds, p, _, run = sphere
    R, T = p["radius"], p["T"]
    pole = real_harmonic(p["l"], p["k"], 0.0, 0.0)
    for name, ours, bound in (
            ("amplitude", R * run.position[:, 0], R * run.position_error[:, 0]),
            ("u_r_pole", pole * R / T * run.velocity[:, 0],
             pole * R / T * run.velocity_error[:, 0])):
        ref, ref_bound = ds[name].values, ds[name + "_error"].values
        floor = 1e-12 * np.max(np.abs(ref))
        assert np.all(np.abs(ours - ref) <= bound + ref_bound + floor), name
        assert np.max(bound) < np.max(ref_bound)


def test_sphere_late_decay_matches_the_dispersion_relation(sphere):
    """The decay rate and frequency fitted (DMD) from the Laplace release over sphere-release's
    fit window (the mode's decay by e^-12 after 4 periods) agree with the least damped root of
    the sphere's dispersion relation to 1e-8 in units of 1/T."""
    ds, p, _, run = sphere
    window = tuple(v / p["T"] for v in ds.attrs["fit_window"])
    fit = fit_rate(ds["t"].values / p["T"], run.position[:, 0], window=window)
    mode = complex(ss.natural_modes("sphere", m=p["l"], kappa=1.0, nu=p["zeta"], count=1).gamma[0])
    assert abs(fit.growth_rate - mode.real) < 1e-8
    assert abs(fit.frequency - mode.imag) < 1e-8


def test_split_matches_a_plain_talbot_inversion(sphere):
    """At early times, where a Talbot contour of 40 nodes encloses the natural modes, the
    transform inverted as a whole (no modes used) equals the residues plus the continuous part
    to 1e-11: the residues and the pole list are right."""
    _, p, system, _ = sphere
    x0 = np.array([p["epsilon"], 0.0])
    t = np.linspace(0.05, 1.5, 30)
    plain = talbot(release_transforms(system.unforced, x0), t, 40)
    modes = ss.natural_modes("sphere", m=p["l"], kappa=1.0, nu=p["zeta"]).gamma
    run = release(system.unforced, x0, t, modes)
    assert np.max(np.abs(plain[0] - run.position)) < 1e-11 * p["epsilon"]
    assert np.max(np.abs(plain[1] - run.velocity)) < 1e-11 * p["epsilon"]


def test_bad_times_are_refused():
    system = hill_system(make_params("mathieu", {"kappa": 2.0, "nu": 0.3}))
    with pytest.raises(ParameterError, match="t is invalid"):
        release(system.unforced, np.array([1.0]), np.array([-1.0, 1.0]), [complex(-0.15, 1.4)])
