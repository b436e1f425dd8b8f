"""Ince-Strutt diagrams drawn as traced curves (issue 26): each boundary is a continuous curve
whose vertices are marginal amplitudes, and the shaded regions are the unstable ones. Oracles:
scipy's Mathieu characteristic values (undamped) and the monodromy matrix integrated by
solve_ivp (damped), both independent of the Hill method."""

import numpy as np
import pytest
from matplotlib.path import Path
from scipy import special

import spectralshell as ss
from conftest import mathieu_monodromy
from spectralshell.plots import ince_strutt
from spectralshell.solvers.tongues import (BOUNDARY_DTAU, BOUNDARY_MIN_DKAPPA, link_boundaries,
                                           match_taus)

KAPPA = (0.0, 3.0)


@pytest.fixture(scope="module")
def diagrams():
    """Figs 2.2 and 2.3: the undamped and a damped Mathieu diagram on the figures' grid."""
    return {nu: ss.tongues("mathieu", kappa="0:3:301", nu=nu, tau_max=1.0, workers=1)
            for nu in (0.0, 0.1)}


@pytest.mark.parametrize("nu", [0.0, 0.1])
def test_boundaries_are_continuous_curves(diagrams, nu):
    """Between consecutive vertices tau moves by at most the refinement's step, unless the
    kappa interval is already as small as the refinement goes (a near-vertical branch)."""
    res = diagrams[nu]
    min_dkappa = BOUNDARY_MIN_DKAPPA * (KAPPA[1] - KAPPA[0])
    assert {b.kind for b in res.boundaries} == {"harmonic", "subharmonic"}
    for b in res.boundaries:
        assert b.kappa.size >= 20
        dk, dt = np.abs(np.diff(b.kappa)), np.abs(np.diff(b.tau))
        assert np.all((dt <= BOUNDARY_DTAU) | (dk <= min_dkappa)), (b.kind, dk[dt > BOUNDARY_DTAU])
    # three tongues below tau = 1 on [0, 3], each one curve from tau = 1 down to its tip and on
    assert len(res.boundaries) == 3


@pytest.mark.parametrize("nu", [0.0, 0.1])
def test_every_marginal_point_and_tip_lies_on_a_curve(diagrams, nu):
    res = diagrams[nu]
    for kind in res.kinds:
        vertices = {(k, t) for b in res.boundaries if b.kind == kind
                    for k, t in zip(b.kappa.tolist(), b.tau.tolist())}
        for k, t in zip(*res.points(kind)):
            if t <= 1.0:
                assert (float(k), float(t)) in vertices
    for tip in res.tips:
        assert min(np.hypot(b.kappa - tip.kappa, b.tau - tip.tau).min()
                   for b in res.boundaries if b.kind == tip.kind) < 1e-9


def test_undamped_vertices_lie_on_the_mathieu_characteristic_curves(diagrams):
    """Oracle: with a = 4 kappa, q = 4 kappa tau (tests/test_mathieu.py) every vertex is a point
    of a_r(q) or b_r(q), r even for harmonic and odd for subharmonic."""
    orders = {"harmonic": (0, 2, 4, 6), "subharmonic": (1, 3, 5, 7)}
    for b in diagrams[0.0].boundaries:
        for kappa, tau in zip(b.kappa, b.tau):
            q = 4 * kappa * tau
            values = [special.mathieu_a(r, q) for r in orders[b.kind]]
            values += [special.mathieu_b(r, q) for r in orders[b.kind] if r > 0]
            assert min(abs(v - 4 * kappa) for v in values) < 1e-8 * max(1.0, q), (b.kind, kappa, tau)


def test_damped_vertices_have_a_floquet_multiplier_of_their_kind(diagrams):
    """Oracle: at a vertex the monodromy matrix has the multiplier +1 (harmonic) or -1
    (subharmonic): det(M - (+-1) I) = 0 (checked at every 12th vertex)."""
    for b in diagrams[0.1].boundaries:
        target = 1.0 if b.kind == "harmonic" else -1.0
        for kappa, tau in list(zip(b.kappa, b.tau))[::12]:
            M = mathieu_monodromy(kappa, 0.1, tau)
            assert abs(np.linalg.det(M - target * np.eye(2))) < 1e-7, (b.kind, kappa, tau)


def test_shading_is_where_the_monodromy_has_a_multiplier_beyond_the_unit_circle(diagrams):
    """Oracle: solve_ivp's monodromy at points of a (kappa, tau) grid away from the boundaries:
    a real multiplier > 1 (harmonic) or < -1 (subharmonic) exactly where that kind is shaded."""
    res = diagrams[0.1]
    shaded = {kind: [Path(q) for q in ince_strutt.unstable_bands(
        [b for b in res.boundaries if b.kind == kind], 1.0)] for kind in res.kinds}
    checked = 0
    for kappa in np.linspace(0.1, 2.9, 15):
        for tau in np.linspace(0.05, 0.95, 10):
            near = min(np.min(np.hypot(b.kappa - kappa, b.tau - tau)) for b in res.boundaries)
            if near < 0.03:
                continue
            rho = np.linalg.eigvals(mathieu_monodromy(kappa, 0.1, tau))
            real = rho[np.abs(rho.imag) < 1e-9].real
            for kind, beyond in (("harmonic", real > 1), ("subharmonic", real < -1)):
                inside = any(p.contains_point((kappa, tau)) for p in shaded[kind])
                assert inside == bool(beyond.any()), (kind, kappa, tau, rho)
            checked += 1
    assert checked > 80


def test_the_figure_draws_the_traced_curves_with_one_legend(diagrams, tmp_path):
    fig_axes = ss.plot.tongues(diagrams[0.1])
    drawn = [line for line in fig_axes.lines if line.get_linestyle() == "-"]
    assert len(drawn) == len(diagrams[0.1].boundaries)
    for line, b in zip(drawn, diagrams[0.1].boundaries):
        np.testing.assert_array_equal(line.get_xdata(), b.kappa)
        np.testing.assert_array_equal(line.get_ydata(), b.tau)
    labels = [t.get_text() for t in fig_axes.get_legend().get_texts()]
    assert {"harmonic boundary", "subharmonic boundary", "harmonic unstable (γ = 0)",
            "subharmonic unstable (γ = i/2)", "finger tips"} <= set(labels)
    assert len(labels) == len(set(labels))
    # the tips on tau = 0 sit inside the axes, not cut by its edge
    assert fig_axes.get_ylim()[0] < 0


def test_a_multi_panel_figure_has_one_legend(diagrams, tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    saved = []
    original = Figure.savefig
    monkeypatch.setattr(Figure, "savefig", lambda fig, *a, **k: (saved.append(fig),
                                                                 original(fig, *a, **k)))
    ince_strutt.save(list(diagrams.values()), tmp_path / "two.png", columns=2)
    fig, = saved
    assert len(fig.legends) == 1 and all(ax.get_legend() is None for ax in fig.axes)


def test_linking_joins_a_fold_and_keeps_branches_apart():
    """A fold: two branches merge between kappa = 1 and 2 (columns of 3 and 1 values); the
    pair joins, the third continues."""
    kappas = np.array([0.0, 1.0, 2.0])
    taus = [np.array([0.2, 0.3, 0.8]), np.array([0.24, 0.26, 0.79]), np.array([0.78])]
    curves = link_boundaries("harmonic", kappas, taus)
    ordered = sorted(c.tau.tolist() if c.tau[0] < c.tau[-1] else c.tau[::-1].tolist()
                     for c in curves)
    assert ordered == [[0.2, 0.24, 0.26, 0.3], [0.78, 0.79, 0.8]]
    assert match_taus(np.array([0.1, 0.5, 0.9]), np.array([0.52])) == [(1, 0)]


def test_a_branch_missed_at_the_converging_truncation_is_filled_in():
    """Fibre m = 2, nu = 2e-4: at kappa = 0.172 the pair of truncations that converges tau_min
    does not settle the upper branch (tau = 0.760), so the grid row lists tau_min only, and
    says so (complete_to at that branch). The boundary re-solves the row with every=True;
    oracle: a fixed N = 60 solve has the same tau."""
    res = ss.tongues("fibre", m=2, nu=2e-4, kappa="0.166:0.2:18", tau_max=1.0, workers=1,
                     tips=False)
    row = res.rows[3]
    assert res.kappa[3] == pytest.approx(0.172) and row["subharmonic"].tau.size == 1
    assert row["subharmonic"].complete_to == pytest.approx(0.76, abs=1e-3)
    at = [t for b in res.boundaries if b.kind == "subharmonic"
          for k, t in zip(b.kappa, b.tau) if k == res.kappa[3]]
    reference = ss.floquet("fibre", m=2, nu=2e-4, kappa=float(res.kappa[3]), tau_max=1.0,
                           n_temporal=60, kind="subharmonic").subharmonic.tau
    assert len(at) == 2 and reference.size == 2
    np.testing.assert_allclose(sorted(at), reference, atol=1e-10)


def test_a_finger_narrower_than_the_grid_step_has_its_tip_located():
    """Cochlea, single mode k = 1, alpha = 0, against omega: the subharmonic finger near
    omega = 343 rad/s is narrower than a 10 rad/s grid step, so across [330, 350] the tau nearest
    the sampled minimum (0.193 at 340) jumps between branches; refine_tip refuses that bracket
    (it once returned a 'tip' at tau = 0.68 on the finger's side) and find_tips narrows it.
    Oracle: independent floquet solves at the tip and 0.02 rad/s either side: the tip's tau is
    the marginal tau there, and both neighbours lie higher."""
    import functools

    from spectralshell.runner import map_points
    from spectralshell.runner.floquet import family_system
    from spectralshell.solvers.tongues import find_tips, refine_tip

    factory = functools.partial(family_system, "cochlea", {"alpha": 0.0, "spatial_mode": 1},
                                "omega")
    grid = np.array([330.0, 340.0, 350.0])
    rows = map_points(factory, list(grid), ("subharmonic",), executor="serial", tol=1e-10)
    with pytest.raises(ss.ConvergenceError, match="jumps"):
        refine_tip(factory, "subharmonic", 330.0, 350.0, rows[1]["subharmonic"].tau_min)
    (tip,), failures = find_tips(factory, grid, rows, ("subharmonic",))
    assert not failures and tip.tau < rows[1]["subharmonic"].tau_min

    def tau_min(omega):
        return ss.floquet("cochlea", omega=omega, alpha=0.0, spatial_mode=1,
                          kind="subharmonic").subharmonic.tau_min

    assert abs(tau_min(tip.kappa) - tip.tau) < 1e-8
    assert tau_min(tip.kappa - 0.02) > tip.tau and tau_min(tip.kappa + 0.02) > tip.tau
