"""The window rule of the refinement in M (solvers.spatial_refinement, module notes): the ladder
of M, and a Fig 5.18 point where two M a doubling apart agree by chance long before tau_min
has converged. Oracle: tau_min at a much larger M (convergence under refinement: at M = 256 and
384 it agrees to 1e-8) and the values at the intermediate M."""

import math

import pytest

from spectralshell.models.cochlea import hill_system
from spectralshell.params.physical import cochlea_forced
from spectralshell.solvers import spatial_refinement as sr
from spectralshell.solvers.marginal import marginal_tau


def test_ladder_has_half_of_each_m_two_steps_below():
    """finer_spatial climbs by 3/2 or 4/3 through the powers of two and their 3/2 multiples, so that
    a window (finer^-2 L, finer^-1 L, L) always spans L / 2 .. L, and from any start two steps
    at most double M (so that start <= limit // 2 fits a first window)."""
    assert sr.spatial_ladder(16, 1024) == (16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512,
                                           768, 1024)
    assert sr.spatial_ladder(1, 8) == (1, 2, 3, 4, 6, 8)
    assert sr.spatial_ladder(20, 40) == (20, 24, 32)
    for m in range(2, 5000):
        up = sr.finer_spatial(m)
        assert m < up <= 2 * m and sr.finer_spatial(up) <= 2 * m
        on_ladder = m & (m - 1) == 0 or (m % 3 == 0 and (m // 3) & (m // 3 - 1) == 0)
        if on_ladder and m >= 4:
            assert sr.finer_spatial(sr.finer_spatial(m // 2)) == m and up / m in (1.5, 4 / 3)


#: Human cochlea of the Fig 5.18 scene (Table 5.1, mu = 0.02 g/(cm s)) at one point of its
#: 200 x 200 grid (the seeded sample of validation/bench_sweep.py): f = 2826 Hz,
#: sigma = 2.72e8 g cm^-2 s^-2. Its smallest tau is subharmonic.
POINT = cochlea_forced(rho=1.0, mu=0.02, sigma=271523632.7464241, length=3.5, lambda_c=1.4,
                       omega=2 * math.pi * 2825.601438658897)
OPTIONS = {"tol": 1e-4, "tau_max": 0.5, "certify_empty": "mark"}


def factory(m):
    return hill_system(n_spatial=m, **POINT)


def test_a_chance_agreement_a_doubling_apart_is_not_taken_for_convergence():
    """tau_min at M = 32 and 64 agree to 1e-4 (the pair rule would stop there, error estimate
    6e-5) while M = 48 between them is 0.018 off and the converged value is 3.6e-3 away. The
    window rule refines on and reports a value within its error estimate (and tol_spatial) of
    tau_min at M = 256."""
    sub = {m: marginal_tau(factory(m), "subharmonic", **OPTIONS).tau_min for m in (32, 48, 64)}
    reference = marginal_tau(factory(256), "subharmonic", **OPTIONS)
    assert abs(sub[64] - sub[32]) < 1e-4
    assert abs(sub[48] - sub[64]) > 1e-2 and abs(sub[64] - reference.tau_min) > 3e-3

    found = sr.refine_minimum(factory, ("harmonic", "subharmonic"), options=OPTIONS,
                              tol_spatial=1e-3)
    low = found.taus["subharmonic"]
    assert found.converged and sr.minimum(found.taus) == low.tau_min
    assert found.n_spatial > 64 and found.n_spatial_previous == found.n_spatial // 2
    error = sr.spatial_error(low, found.change["subharmonic"]).error_estimate
    assert abs(low.tau_min - reference.tau_min) <= min(error, 1e-3)
    # the harmonic kind: nothing below the minimum, proved at the returned M
    harmonic = found.taus["harmonic"]
    assert harmonic.tau_min is None and harmonic.complete_to == found.caps["harmonic"]
    assert found.caps["harmonic"] == low.tau_min
