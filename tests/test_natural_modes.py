"""Hill blocks projected onto natural modes (discretise/natural_modes.py).

Oracles: with every mode the projection is a congruence (the cosine truncation's own tau_min,
derivations/natural_mode_blocks.py part 3); inviscid, the projected system is a set of
decoupled Mathieu equations with kappa = w_j^2 (part 2), whose tau_min the Mathieu model gives
(itself checked against scipy's Mathieu characteristic values, tests/test_mathieu.py); with
fewer modes tau_min converges to the cosine truncation's as m grows; the count of natural
frequencies below w against the eigenvalues of models.cochlea.natural_frequencies.
"""

import functools
import math

import numpy as np
import pytest

from spectralshell.discretise.natural_modes import (CROWDING, PROBE_MODES, natural_basis,
                                                    natural_basis_pays, natural_mode_system,
                                                    modes_below)
from spectralshell.errors import ParameterError
from spectralshell.models import mathieu
from spectralshell.models.cochlea import hill_system, natural_frequencies
from spectralshell.params.physical import cochlea_forced
from spectralshell.solvers.marginal import marginal_tau

KINDS = ("harmonic", "subharmonic")


def forced(frequency: float, sigma: float) -> dict:
    """The test cochlea of tests/test_cochlea_sweep.py (mu = 2) at a tone and stiffness."""
    return cochlea_forced(rho=1.0, mu=2.0, sigma=sigma, length=3.5, lambda_c=1.4,
                          omega=2 * math.pi * frequency)


LOW = forced(400.0, 1e8)      # kappa = 14.2: 3 natural frequencies below the forcing one
HIGH = forced(8000.0, 5e8)    # kappa = 0.18: 88 of them


def tau(system, kind, n_temporal=8):
    return marginal_tau(system, kind, n_temporal=n_temporal, tau_max=0.5).tau_min


@pytest.mark.parametrize("kind", KINDS)
def test_all_modes_give_the_cosine_truncations_tau(kind):
    full = hill_system(n_spatial=16, **LOW)
    assert tau(natural_mode_system(full, 16), kind) == pytest.approx(tau(full, kind), abs=1e-12)


def test_inviscid_blocks_are_decoupled_mathieu_modes():
    params = {**LOW, "nu": 0.0}
    full = hill_system(n_spatial=24, **params)
    reduced = natural_mode_system(full, 4)
    w = natural_frequencies(params["kappa"], params["alpha"], np.arange(1, 25))[:4]
    assert np.allclose(np.sqrt(np.diag(reduced.forcing)), w, rtol=1e-12)
    s = np.array([0.3j, 1.7j, 0.5 + 2j])
    D = reduced.unforced(s)
    expected = np.array([np.diag(w**2 + x**2) for x in s])
    assert np.abs(D - expected).max() <= 1e-12 * np.abs(expected).max()
    assert np.allclose(reduced.polynomial[2], np.eye(4), atol=1e-12)
    for kind in KINDS:
        modes = [tau(mathieu.hill_system(kappa=wj**2, nu=0.0), kind) for wj in w]
        expected_tau = min((t for t in modes if t is not None), default=None)
        found = tau(reduced, kind)
        assert (found is None) == (expected_tau is None)
        if found is not None:
            assert found == pytest.approx(expected_tau, abs=1e-10)


def test_fewer_modes_converge_to_the_cosine_truncation():
    """M = 32 cosine modes, N = 8: tau_min of m natural modes against all 32. Measured: harmonic
    off by 1.0e-5, 1.8e-6, 2.5e-7, 6.4e-9 at m = 8, 12, 16, 24; subharmonic 9.1e-9, 3.8e-8,
    8.4e-9, 2.6e-10; m = 4 has no harmonic tau <= 1/2 (its modes do not reach the resonance)."""
    full = hill_system(n_spatial=32, **LOW)
    ladder = (8, 12, 16, 24)
    errors = {kind: [abs(tau(natural_mode_system(full, m), kind) - tau(full, kind)) for m in ladder]
              for kind in KINDS}
    harmonic = errors["harmonic"]
    assert harmonic[0] < 2e-5 and all(b < a / 4 for a, b in zip(harmonic, harmonic[1:]))
    assert max(errors["subharmonic"]) < 1e-7 and errors["subharmonic"][-1] < 1e-9
    assert tau(natural_mode_system(full, 4), "harmonic") is None


def test_the_plan_counts_natural_frequencies_below_the_forcing_frequency():
    for params, pays in ((LOW, True), (HIGH, False)):
        probe = hill_system(n_spatial=PROBE_MODES, **params)
        w = natural_frequencies(params["kappa"], params["alpha"], np.arange(1, PROBE_MODES + 1))
        for x in (0.5, 1.0, 2.0):
            assert modes_below(probe, x) == np.count_nonzero(w < x)
        assert natural_basis_pays(probe) is pays
        assert bool(np.count_nonzero(w < 1.0) <= CROWDING) is pays


def test_bad_input_names_the_parameter():
    full = hill_system(n_spatial=8, **LOW)
    for m in (0, 9, 2.5):
        with pytest.raises(ParameterError, match="n_natural"):
            natural_basis(full, m)
    scalar = mathieu.hill_system(kappa=0.3, nu=0.1)
    with pytest.raises(ParameterError, match="no inviscid inertia"):
        natural_mode_system(scalar, 1)
    assert natural_basis_pays(scalar) is False


def test_fig_5_18_cells_in_the_natural_basis_equal_the_cosine_ones(monkeypatch):
    """Cells of the packaged human Fig 5.18 scene at low tones, each planned in the natural
    basis, against the same cells refined in cosine modes throughout (the path before the
    plan): the same answer for each kind (found or not, certified), and tau_min within the sum
    of the two error estimates (each at least its spatial change,
    spatial_refinement.spatial_error). At 232.2 Hz, sigma = 8.3e8 the subharmonic tau_min
    differs by 2.3e-5 between the bases, within that sum."""
    from spectralshell.params.sweep_grid import sweep_spec
    from spectralshell.reports.figures import fig_5_18_scene
    from spectralshell.runner import run_sweep, solve

    scene = fig_5_18_scene("human")
    cells = [{**scene, "grid": {"frequency": [f], "sigma": [s]}}
             for f, s in ((232.2, 8.3e8), (627.1, 7.4e7))]
    for cell in cells:
        spec = sweep_spec(cell)
        params = spec.params_at({a.name: a.values[0] for a in spec.axes if a.name != "kind"})
        assert solve.spatial_basis("cochlea", params)[1] == solve.NATURAL_START  # planned so
    natural = [run_sweep(cell, executor="serial").dataset for cell in cells]
    cosine_basis = lambda model, params: (  # noqa: E731 - the plan without the natural basis
        functools.partial(solve.spatial_system, model, params), solve.SPATIAL_START)
    monkeypatch.setattr(solve, "spatial_basis", cosine_basis)
    cosine = [run_sweep(cell, executor="serial").dataset for cell in cells]
    for nat, cos in zip(natural, cosine):
        for name in ("has_tau", "spatial_converged"):
            np.testing.assert_array_equal(nat[name].values, cos[name].values)
        found = nat["has_tau"].values
        assert found.any() and not found.all()  # one kind attains the minimum, the other not
        gap = np.abs(nat["tau_min"].values - cos["tau_min"].values)[found]
        allowed = (nat["error_estimate"].values + cos["error_estimate"].values)[found]
        assert np.all(gap <= allowed) and np.all(allowed < 1e-3)
        for ds in (nat, cos):  # certified up to tau_min; the other kind up to the minimum
            least = float(ds["tau_min"].values[found].min())
            bound = np.where(found, ds["tau_min"].values, least)
            assert np.all(ds["complete_to"].values >= bound)
