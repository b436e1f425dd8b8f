"""An empty answer of a viscous model is proved by the zero count or refused (issue 23, section
2), and the count replaces the cochlea's empty truncation solves (issue 25); checked against
dense QZ of the same truncations."""

import contextlib
import io
import json

import numpy as np
import pytest
import scipy.linalg as sla

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.models.sphere import hill_system as sphere
from spectralshell.params.physical import CARDIAC, PhysicalSphere, bpm_to_rad_per_s
from spectralshell.solvers import marginal
from spectralshell.solvers.marginal import Pencils, dense_taus, marginal_tau, truncation_taus

from test_contour_blocks import cochlea, qz_squares, real_squares
from test_marginal_fast import cochlea_like

#: The atrium (Fig 6.13) at sigma = 15000 dyn/cm, 300 beats/min, m = 2: no tau <= 1/2 of
#: either kind; the subharmonic tau_min is 0.53209597, just above.
SPHERE = PhysicalSphere(rho=CARDIAC["rho"], mu=CARDIAC["mu"], radius=CARDIAC["radius"],
                        sigma=15000.0, omega=bpm_to_rad_per_s(300.0)).forced()
SUBHARMONIC_MIN = 0.53209597


def system():
    return sphere(m=2, kappa=SPHERE["kappa"], nu=SPHERE["nu"])


def qz_real_below(system, kind, n, tau_max):
    """Real tau in [0, tau_max] of truncation n by QZ of the real form."""
    tau = dense_taus(Pencils(system, kind).get(n, "real")[0])
    return tau[(tau >= 0) & (tau <= tau_max)]


def qz_in_strip(system, kind, n, tau_max, half=1e-6):
    """Eigenvalues z = tau^2 of truncation n (QZ) in [-a, tau_max^2] x [-a, a],
    a = half tau_max^2."""
    z = qz_squares(Pencils(system, kind).get(n, "two-sided")[0])
    a = half * tau_max ** 2
    return z[(z.real > -a) & (z.real < tau_max ** 2) & (np.abs(z.imag) < a)]


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
@pytest.mark.parametrize("tau_max", [0.5, 0.53])
def test_empty_answer_is_certified(kind, tau_max):
    """No tau <= tau_max (0.53 lies just below the subharmonic 0.53209597): the answer says
    complete_to = tau_max, and QZ of both truncations of the pair has no real tau, nor any
    eigenvalue in the thinnest strip, below it."""
    found = marginal_tau(system(), kind, tol=1e-9, tau_max=tau_max, method="dense",
                         certify_empty=True)
    assert found.tau_min is None and found.complete_to == tau_max
    for n in (found.n_temporal, found.n_previous):
        assert not qz_real_below(system(), kind, n, tau_max).size
        assert not qz_in_strip(system(), kind, n, tau_max).size


def test_tau_just_above_the_bound_is_found():
    """With tau_max = 0.535 the subharmonic tau_min = 0.53209597 (QZ of the same truncation)
    is returned, not an empty answer."""
    found = marginal_tau(system(), "subharmonic", tol=1e-9, tau_max=0.535, method="dense",
                         certify_empty=True)
    reference = qz_real_below(system(), "subharmonic", found.n_temporal, 0.535)
    assert found.tau_min == pytest.approx(reference[0], rel=1e-9)
    assert found.tau_min == pytest.approx(SUBHARMONIC_MIN, abs=1e-8)


def test_uncertified_empty_answer_is_refused(monkeypatch):
    """Where the count cannot prove the strip empty, the solve raises (saying what to
    change), a fixed truncation claims nothing (complete_to 0), and without certify_empty
    the answer is as before."""
    monkeypatch.setattr(marginal, "none_up_to", lambda hill, tau_max, solves=None: False)
    with pytest.raises(ss.ConvergenceError, match="zero count cannot prove.*tau_max="):
        marginal_tau(system(), "harmonic", tol=1e-9, tau_max=0.5, certify_empty=True)
    fixed = marginal_tau(system(), "harmonic", n_temporal=20, tau_max=0.5, certify_empty=True)
    assert fixed.tau_min is None and fixed.complete_to == 0.0
    plain = marginal_tau(system(), "harmonic", tol=1e-9, tau_max=0.5)
    assert plain.tau_min is None and plain.complete_to >= 0.5


def run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


def test_floquet_cli_states_the_certified_bound(monkeypatch):
    """spectralshell floquet: a certified empty answer states complete_to = tau_max (rc 0);
    an uncertifiable one exits 1 with one line."""
    argv = ["floquet", "sphere", "--m", "2", "--kappa", repr(SPHERE["kappa"]), "--nu",
            repr(SPHERE["nu"]), "--tau-max", "0.5", "--json"]
    rc, out, _ = run(argv)
    data = json.loads(out)
    assert rc == 0
    for kind in ("harmonic", "subharmonic"):
        assert data[kind]["tau"] == [] and data[kind]["complete_to"] == 0.5
    monkeypatch.setattr(marginal, "none_up_to", lambda hill, tau_max, solves=None: False)
    rc, out, err = run(argv)
    assert rc == 1 and "zero count cannot prove" in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_cochlea_count_replaces_empty_truncation(kind, monkeypatch):
    """The viscous cochlea (M = 8, N = 12, the count allowed from N = 1): below its smallest
    real tau (QZ) the count proves the truncation empty (method 'contour'); just above it the
    count declines and the truncation is solved as before, with the same tau as the dense
    path."""
    monkeypatch.setattr(marginal, "COUNT_MIN_N", 1)
    cochlea_system = cochlea(8)
    hill = Pencils(cochlea_system, kind).get(12, "two-sided")[0]
    z = qz_squares(hill)
    smallest = float(np.sqrt(real_squares(z).min()))
    assert smallest < 0.5
    below = truncation_taus(cochlea_system, kind, 12, tau_max=0.99 * smallest,
                            count_first=True)
    assert below.method == "contour" and not below.tau.size
    assert below.complete_to == 0.99 * smallest
    assert not qz_in_strip(cochlea_system, kind, 12, 0.99 * smallest, half=1e-4).size
    above = truncation_taus(cochlea_system, kind, 12, tau_max=1.01 * smallest,
                            count_first=True)
    dense = truncation_taus(cochlea_system, kind, 12, method="dense")
    assert above.method != "contour"
    assert above.tau[0] == pytest.approx(smallest, rel=1e-8)
    assert above.tau[0] == pytest.approx(dense.tau[0], rel=1e-10)


def test_solve_after_an_empty_truncation_counts(monkeypatch):
    """Coupled oscillators (block size 20) with nothing below tau_max = 1/2, the count allowed
    from N = 1: the truncation after the first (Krylov) one is proved empty by the count, and
    the answer is the dense path's, with the same truncation pair."""
    monkeypatch.setattr(marginal, "COUNT_MIN_N", 1)
    monkeypatch.setattr(marginal, "KRYLOV_MIN_ORDER", 200)
    coupled = cochlea_like(20, kappa=0.02)
    counted = marginal_tau(coupled, "harmonic", tol=1e-10, tau_max=0.5)
    dense = marginal_tau(coupled, "harmonic", tol=1e-10, tau_max=0.5, method="dense")
    assert counted.method == "contour" and counted.complete_to >= 0.5
    assert counted.tau_min is None and dense.tau_min is None
    assert (counted.n_temporal, counted.n_previous) == (dense.n_temporal, dense.n_previous)
