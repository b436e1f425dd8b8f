"""Cochlea sweeps (thesis Fig 5.18): cgs axes (sigma, omega or frequency in Hz), the number of
spatial modes M refined per point, stored and flagged, checked against independent
``ss.floquet`` calls, hand-computed conversions (thesis 5.2, Table 5.1) and the inviscid natural
frequencies. Cheap points: a viscous fluid (mu = 2) and a fixed temporal truncation keep each
solve well under a second."""

import json
import math

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.discretise.natural_modes import (PROBE_MODES, RATIO, START, natural_basis_pays,
                                                natural_mode_system)
from spectralshell.errors import ConvergenceError, ParameterError
from spectralshell.models.cochlea import hill_system, natural_frequencies
from spectralshell.params.physical import cochlea_forced
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.runner import open_sweep, run_sweep, solve
from spectralshell.solvers import spatial_refinement as sr
from sweep_cases import interrupted

CHEAP = {"mu": 2.0}                          # g/(cm s): high modes damped, M converges early
OPTIONS = {"n_temporal": 6, "tau_max": 0.5}  # fixed N: cheap, and exactly reproducible


def scene(grid, params=None, **options):
    return {"model": "cochlea", "ask": ["tau_min"], "params": {**CHEAP, **(params or {})},
            "grid": grid, "tau_min": {**OPTIONS, **options}}


def test_cochlea_scene_axes_units_and_defaults():
    spec = sweep_spec(scene({"frequency": {"start": 100.0, "stop": 1000.0, "num": 3,
                                           "spacing": "log"}, "sigma": [1e7, 1e8]}))
    assert [a.units for a in spec.axes] == ["Hz", "g/(cm^2 s^2)", ""]
    # Table 5.1 fills what is not given (mu is given), and enters the hash
    assert dict(spec.fixed) == {"mu": 2.0, "rho": 1.0, "length": 3.5, "lambda_c": 1.4}
    assert spec.refines_spatial and spec.options.tol_spatial == 1e-3  # the solver's default
    assert sr.TOL_SPATIAL == 1e-3
    fixed = sweep_spec(scene({"omega": [1000.0]}, {"n_spatial": 16}))
    assert not fixed.refines_spatial and fixed.spatial and fixed.options.tol_spatial is None
    # a scene without spatial modes keeps its canonical options (and so its old hash)
    mathieu = sweep_spec({"model": "mathieu", "params": {"nu": 0.0},
                          "grid": {"kappa": [0.2, 0.3]}})
    assert set(mathieu.canonical()["options"]) == {"tol", "n_temporal", "tau_max", "continuation"}


@pytest.mark.parametrize("grid, params, options, fragment", [
    ({"radius": [1.0], "omega": [100.0]}, {}, {}, "radius"),               # the sphere's, not ours
    ({"sigma": [-1e8, 1e8], "omega": [100.0]}, {}, {}, "sigma = -100000000.0"),
    ({"sigma": [1e8], "omega": [100.0], "frequency": [10.0]}, {}, {}, "frequency"),
    ({"sigma": [1e8]}, {}, {}, "omega"),                                     # no frequency at all
    ({"frequency": [0.0, 10.0]}, {}, {}, "frequency = 0.0"),
    ({"frequency": [10.0]}, {"kappa": 1.0, "sigma": 1e8}, {}, "kappa"),     # kappa and its source
    ({"frequency": [10.0]}, {"n_spatial": 16}, {"tol_spatial": 1e-3}, "tol_spatial"),
    ({"frequency": [10.0]}, {}, {"tol_spatial": -1.0}, "tol_spatial"),
])
def test_bad_cochlea_scenes_name_the_parameter(grid, params, options, fragment):
    with pytest.raises(ParameterError, match=fragment):
        sweep_spec(scene(grid, params, **options))


def test_tol_spatial_is_refused_without_spatial_modes():
    with pytest.raises(ParameterError, match="tol_spatial.*no spatial modes"):
        sweep_spec({"model": "mathieu", "grid": {"kappa": [0.2]}, "tau_min": {"tol_spatial": 0.1}})


def test_conversion_is_thesis_5_2_with_table_5_1():
    """kappa = sigma pi/(rho L omega^2), nu = mu pi^2/(rho L^2 omega), alpha = lambda_c L/pi by
    hand, omega = 2 pi f; and the dimensionless ranges printed in Table 5.1 (nu in [8.06e-6,
    1.61e-4], kappa in [0.135, 53.9]), which belong to omega in [100, 2000] s^-1 (ERRATA)."""
    spec = sweep_spec({"model": "cochlea", "grid": {"frequency": [100.0, 1000.0]},
                       "params": {"sigma": 6e5}})
    for f in (100.0, 1000.0):
        p = spec.params_at({"frequency": f})
        w = 2 * math.pi * f
        assert p["kappa"] == pytest.approx(6e5 * math.pi / (3.5 * w * w), rel=1e-14)
        assert p["nu"] == pytest.approx(0.02 * math.pi ** 2 / (3.5 ** 2 * w), rel=1e-14)
        assert p["alpha"] == pytest.approx(1.4 * 3.5 / math.pi, rel=1e-14)
    lo, hi = (spec.params_at({"frequency": w / (2 * math.pi)}) for w in (2000.0, 100.0))
    assert (lo["nu"], hi["nu"]) == (pytest.approx(8.06e-6, abs=5e-9), pytest.approx(1.61e-4, abs=5e-7))
    assert (lo["kappa"], hi["kappa"]) == (pytest.approx(0.135, abs=5e-4), pytest.approx(53.9, abs=0.05))


@pytest.fixture(scope="module")
def refined():
    """A 2 x 2 sweep (frequency x sigma, subharmonic), M refined per point, with continuation."""
    grid = {"frequency": [400.0, 600.0], "sigma": [1e7, 1e8], "kind": ["subharmonic"]}
    return run_sweep(scene(grid), executor="serial")


def test_refined_sweep_equals_independent_floquet_calls(refined):
    ds = refined.dataset
    assert set(ds.data_vars) >= {"n_spatial", "spatial_converged"}
    assert ds["n_spatial"].dims == ds["tau_min"].dims
    for f in (400.0, 600.0):
        for sigma in (1e7, 1e8):
            res = ss.floquet("cochlea", kind="subharmonic", sigma=sigma, omega=2 * math.pi * f,
                             tol_spatial=1e-3, **CHEAP, **OPTIONS)
            m, at = res.subharmonic, ds.sel(frequency=f, sigma=sigma, kind="subharmonic")
            assert m.tau_min is not None and bool(at["has_tau"])
            assert float(at["tau_min"]) == m.tau_min  # same pair of M, same code: bitwise
            assert float(at["error_estimate"]) == m.error_estimate
            assert int(at["n_spatial"]) == res.n_spatial and bool(at["spatial_converged"])
            assert int(at["n_temporal"]) == m.n_temporal == 6
    assert ds["n_spatial"].values.min() == 32 and ds["n_spatial"].values.max() == 48


def test_hz_axis_equals_omega_axis():
    f = [300.0, 500.0]
    common = {"n_spatial": 12}
    by_f = ss.sweep(scene({"frequency": f}, common), executor="serial")
    by_w = ss.sweep(scene({"omega": [2 * math.pi * v for v in f]}, common), executor="serial")
    for name in ("tau_min", "has_tau", "error_estimate", "n_temporal", "n_spatial"):
        np.testing.assert_array_equal(by_f[name].values, by_w[name].values, err_msg=name)
    assert (by_f["n_spatial"].values == 12).all() and by_f["spatial_converged"].values.all()
    assert by_f["frequency"].attrs["units"] == "Hz" and by_w["omega"].attrs["units"] == "rad/s"


def test_cochlea_store_resumes_only_missing_chunks(tmp_path):
    sc = {**scene({"frequency": [300.0, 500.0], "sigma": [1e7, 2e7, 4e7]}, {"n_spatial": 10}),
          "sweep": {"chunk": 1}}
    fresh = run_sweep(sc, executor="serial").dataset
    out = tmp_path / "cochlea.zarr"
    interrupted(sc, out, 2)
    assert int(open_sweep(out)["computed"].sum()) == 2 * 2  # two chunks of one point, two kinds
    seen = []
    resumed = run_sweep(sc, executor="serial", out=out, on_chunk=lambda n, r: seen.append(r.index))
    assert len(seen) == 4 and resumed.computed == 8 and resumed.skipped == 4
    back = open_sweep(out)
    for name in ("tau_min", "has_tau", "error_estimate", "n_temporal", "n_spatial",
                 "spatial_converged"):
        np.testing.assert_array_equal(back[name].values, fresh[name].values, err_msg=name)
    assert run_sweep(sc, executor="serial", out=out).computed == 0


def test_unconverged_point_is_kept_flagged_and_hatched(monkeypatch, tmp_path):
    """A point whose M refinement reaches the limit keeps its values at the limit (equal to a
    fixed-M solve there) with spatial_converged false, and the map hatches and counts it."""
    monkeypatch.setattr(solve, "SPATIAL_LIMIT", 32)
    grid = {"frequency": [600.0, 700.0], "sigma": [1e7], "kind": ["subharmonic"]}
    ds = run_sweep(scene(grid, tol_spatial=1e-12), executor="serial").dataset
    assert not ds["spatial_converged"].values.any() and (ds["n_spatial"].values == 32).all()
    at = ds.sel(frequency=600.0, sigma=1e7, kind="subharmonic")
    fixed = ss.floquet("cochlea", kind="subharmonic", sigma=1e7, omega=2 * math.pi * 600.0,
                       n_spatial=32, **CHEAP, **OPTIONS).subharmonic
    assert float(at["tau_min"]) == fixed.tau_min
    assert float(at["error_estimate"]) >= fixed.error_estimate  # the spatial change is in it

    from spectralshell.plots import cochlea as cochlea_plots
    from spectralshell.plots import sweep_plot

    two = ds.isel(sigma=[0, 0]).assign_coords(sigma=[1e7, 2e7])
    two["spatial_converged"].values[:, 1] = True
    assert sweep_plot.unconverged(two, "frequency", "sigma").sum() == 2
    png = cochlea_plots.save_tau_maps([("test", two)], tmp_path / "maps.png", caption="caption")
    assert png.stat().st_size > 0
    assert sweep_plot.save(two, tmp_path / "map.png").stat().st_size > 0


def _factory(frequency: float, sigma: float):
    d = cochlea_forced(rho=1.0, mu=2.0, sigma=sigma, length=3.5, lambda_c=1.4,
                       omega=2 * math.pi * frequency)
    return lambda m: hill_system(n_spatial=m, **d)


def test_refinement_continued_from_a_neighbour_matches_the_independent_one():
    """Starting at the coarsest M of the window the independent refinement passes at gives the
    same values bitwise; starting above it gives the value at a larger M, within tol_spatial."""
    factory, opts = _factory(600.0, 1e8), {"n_temporal": 6, "tau_max": 0.5}
    alone = sr.refine_spatial(factory, ("subharmonic",), options=opts)
    assert (alone.n_spatial_previous, alone.n_spatial) == (24, 48) and alone.converged
    again = sr.refine_spatial(factory, ("subharmonic",), options=opts, start=24)
    assert again.taus["subharmonic"].tau_min == alone.taus["subharmonic"].tau_min
    early = _factory(400.0, 1e8)  # passes at (16, 24, 32) alone
    alone = sr.refine_spatial(early, ("subharmonic",), options=opts)
    above = sr.refine_spatial(early, ("subharmonic",), options=opts, start=24)
    assert alone.n_spatial == 32 and above.n_spatial == 48 and above.converged
    assert abs(above.taus["subharmonic"].tau_min - alone.taus["subharmonic"].tau_min) <= 1e-3
    with pytest.raises(ConvergenceError, match="tol_spatial=1e-12 by n_spatial=32"):
        sr.refine_spatial(factory, ("subharmonic",), options=opts, tol_spatial=1e-12, limit=32)
    with pytest.raises(ParameterError, match="start"):
        sr.refine_spatial(factory, ("subharmonic",), options=opts, start=512)


@pytest.mark.parametrize("kappa", [0.01, 0.05, 0.3])
def test_resonance_reach_counts_the_inviscid_natural_frequencies(kappa):
    """reaches_resonance (inertia of D(i w)) against the eigenvalues of kappa diag(sqrt(k/2)) C
    diag(sqrt(k/2)) (models.cochlea.natural_frequencies), inviscid, for several M and tau_max."""
    for m in (8, 16, 32, 64):
        system = hill_system(kappa=kappa, nu=0.0, alpha=1.56, n_spatial=m)
        top = natural_frequencies(kappa, 1.56, np.arange(1, m + 1))[-1]
        for kind, w in sr.RESONANCE.items():
            for tau_max in (0.5, 0.2):
                expected = top * math.sqrt(1 + 2 * tau_max) > w
                assert sr.reaches_resonance(system, kind, tau_max) == expected
        assert sr.reaches_resonance(system, "harmonic")  # tau_max = inf: always


def test_no_tau_at_short_truncations_is_not_taken_for_convergence():
    """Table 5.1 at f = 20 kHz, sigma = 1e8: no subharmonic tau <= 1/2 at M = 16, 32 (nor 64),
    where the modes do not reach the resonance; the refinement goes on and finds it, in
    agreement with an independent fixed M = 256."""
    omega = 2 * math.pi * 20000.0
    opts = {"kind": "subharmonic", "sigma": 1e8, "omega": omega, "tau_max": 0.5, "n_temporal": 8}
    short = ss.floquet("cochlea", n_spatial=32, **opts).subharmonic
    assert short.tau_min is None
    auto = ss.floquet("cochlea", **opts)
    fixed = ss.floquet("cochlea", n_spatial=256, **opts).subharmonic
    assert auto.n_spatial >= 128 and auto.subharmonic.tau_min is not None
    assert abs(auto.subharmonic.tau_min - fixed.tau_min) <= auto.subharmonic.error_estimate + 1e-3
    assert 0.04 < auto.subharmonic.tau_min < 0.06


def test_packaged_fig_5_18_scenes():
    from spectralshell.reports.figures import FIGURES, fig_5_18_scene

    assert "fig-5.18" in FIGURES
    for panel, length, lam, sigma, f in (("human", 3.5, 1.4, (1e7, 2e9), (50.0, 20000.0)),
                                         ("gerbil", 1.3, 3.7, (1.5e8, 2e9), (100.0, 50000.0))):
        spec = sweep_spec(fig_5_18_scene(panel))
        assert spec.shape == (200, 200, 2) and spec.refines_spatial
        assert dict(spec.fixed)["length"] == length and dict(spec.fixed)["lambda_c"] == lam
        assert spec.axis("sigma").values[0] == sigma[0] and spec.axis("sigma").values[-1] == pytest.approx(sigma[1])
        assert spec.axis("frequency").values[0] == f[0] and spec.axis("frequency").values[-1] == pytest.approx(f[1])
        assert spec.options.tol == 1e-4 and spec.options.tol_spatial == 1e-3
        small = sweep_spec(fig_5_18_scene(panel, 5))
        assert small.shape == (5, 5, 2) and small.options == spec.options


@pytest.mark.slow
def test_fig_5_18_at_a_tiny_resolution(tmp_path):
    """The figure command at 2 x 2 points per panel (the corners of the thesis's ranges): PNG,
    JSON with the Hz reading, the stores; a rerun resumes from the stores and computes nothing."""
    from spectralshell.reports import figures

    paths = figures._cochlea_tau_maps(tmp_path, progress=False, workers=None, size=2)
    assert all(p.exists() for p in paths)
    data = json.loads((tmp_path / "fig-5.18.json").read_text())
    assert data["frequency"]["axis"].startswith("f in Hz")
    assert "0.80 decade" in data["frequency"]["other_reading"]
    for name in ("human", "gerbil"):
        panel = data["panels"][name]
        assert len(panel["tau_min"]) == 2 and panel["points_computed"] == 8
    figures._cochlea_tau_maps(tmp_path, progress=False, workers=None, size=2)
    data = json.loads((tmp_path / "fig-5.18.json").read_text())
    assert all(p["points_computed"] == 0 for p in data["panels"].values())


def test_spatial_change_caps_at_tau_max():
    """A tau_min just below tau_max at one M and none at the other: the capped values differ by
    tau_max - tau_min; without a cap the change is unknown (None)."""
    from spectralshell.results.records import MarginalTau

    def m(tau):
        return MarginalTau(kind="subharmonic", tau=np.array([] if tau is None else [tau]),
                           tau_min=tau, n_temporal=20, n_previous=14,
                           error_estimate=None if tau is None else 1e-9, method="structured")

    assert sr.spatial_change(m(0.4995), m(None), 0.5) == pytest.approx(5e-4, abs=1e-15)
    assert sr.spatial_change(m(None), m(0.3), 0.5) == pytest.approx(0.2, abs=1e-15)
    assert sr.spatial_change(m(0.4995), m(None)) is None
    assert sr.spatial_change(m(None), m(None), 0.5) == 0.0
    assert sr.spatial_change(m(0.25), m(0.2), 0.5) == pytest.approx(0.05, abs=1e-15)
    assert sr.spatial_error(m(0.4995), 5e-4).error_estimate == 5e-4
    assert sr.spatial_error(m(0.4995), None).error_estimate == 0.4995


def test_neighbours_tau_min_is_the_solvers_hint_and_changes_nothing_but_speed(monkeypatch):
    """Continuation passes a point's neighbour's tau_min to the shift-invert cover of its big
    truncations (M = 32, N = 20: half order 672, above KRYLOV_MIN_ORDER) as the first shift
    (the truncation N = 15 compared with it starts from its shifts instead); the values equal
    independent solves (continuation off) within the error estimates."""
    import spectralshell.solvers.marginal as marginal

    seen, real = [], marginal.interval_taus

    def spy(hill, tau_max, *, hint=None, **kw):
        if len(hill.diag) == 21:  # N = 20
            seen.append(hint)
        return real(hill, tau_max, hint=hint, **kw)

    monkeypatch.setattr(marginal, "interval_taus", spy)
    sc = scene({"frequency": [50.0], "sigma": [1.0e7, 1.1e7], "kind": ["harmonic"]},
               {"n_spatial": 32, "mu": 0.02}, n_temporal=20)
    off = run_sweep({**sc, "tau_min": {**sc["tau_min"], "continuation": False}},
                    executor="serial").dataset
    assert seen == [None, None]  # both points reach the cover, without a hint
    seen.clear()
    on = run_sweep(sc, executor="serial").dataset
    first = float(on["tau_min"].values.ravel()[0])
    assert seen == [None, first]  # the second point starts at the first one's tau_min
    a, b = off["tau_min"].values.ravel(), on["tau_min"].values.ravel()
    bound = off["error_estimate"].values.ravel() + on["error_estimate"].values.ravel()
    assert off["has_tau"].values.all() and on["has_tau"].values.all()
    assert np.all(np.abs(a - b) <= np.maximum(bound, 1e-14))


def test_minimum_over_kinds_sweep_equals_the_joint_refinement_and_caps_the_other_kind():
    """over_kinds = 'minimum': per point the smaller tau_min of the two kinds equals
    refine_minimum called directly (same code path, in the natural basis the plan picks at
    these low-frequency points: bitwise) and the separate (cosine-basis) per-kind
    refinement within tol_spatial; the other kind, resolved only below the minimum, has
    has_tau False and tau_min NaN; the option changes the scene hash and is refused where M
    is not refined per point."""
    grid = {"frequency": [400.0], "sigma": [1e7, 1e8]}
    alone = run_sweep(scene(grid, over_kinds="minimum", continuation=False),
                      executor="serial").dataset
    joint = run_sweep(scene(grid, over_kinds="minimum"), executor="serial").dataset  # continued
    each = run_sweep(scene(grid), executor="serial").dataset
    for sigma in (1e7, 1e8):
        factory = _factory(400.0, sigma)
        # the plan of runner.solve.spatial_basis: natural modes where few lie below the forcing
        assert natural_basis_pays(factory(PROBE_MODES))
        direct = sr.refine_minimum(lambda M, f=factory: natural_mode_system(f(M), M // RATIO),
                                   ("harmonic", "subharmonic"), options=OPTIONS,
                                   tol_spatial=1e-3, start=START, strict=False)
        per_kind = each.sel(frequency=400.0, sigma=sigma)
        reference = float(per_kind["tau_min"].where(per_kind["has_tau"]).min())
        for ds in (alone, joint):
            at = ds.sel(frequency=400.0, sigma=sigma)
            has = at["has_tau"].values
            assert has.sum() == 1  # the minimising kind only
            best = float(at["tau_min"].values[has][0])
            assert np.isnan(at["tau_min"].values[~has]).all()
            assert abs(best - reference) <= 1e-3
        best_alone = float(alone.sel(frequency=400.0, sigma=sigma)["tau_min"].min())
        assert best_alone == sr.minimum(direct.taus)
    assert sweep_spec(scene(grid, over_kinds="minimum")).digest != sweep_spec(scene(grid)).digest
    with pytest.raises(ParameterError, match="over_kinds"):
        sweep_spec(scene(grid, {"n_spatial": 16}, over_kinds="minimum"))
    with pytest.raises(ParameterError, match="over_kinds"):
        sweep_spec({"model": "mathieu", "grid": {"kappa": [0.2]},
                    "tau_min": {"over_kinds": "minimum"}})
    with pytest.raises(ParameterError, match="over_kinds"):
        sweep_spec(scene(grid, over_kinds="smallest"))


@pytest.mark.slow
def test_coarse_fig_5_18_map_on_the_fast_path_equals_the_dense_one(monkeypatch):
    """Both Fig 5.18 panels (the packaged scenes) at 3 x 3 points inside their ranges (not the
    corner f = 50 Hz, sigma = 2e9, whose subharmonic climbs to N = 300: minutes of dense eig),
    M fixed at 16, both kinds, N converged: the sweep's path (Arnoldi on W and shift-invert
    covers from (N + 1) M >= 250; counted, so the test fails if it never leaves the dense eig)
    against every truncation solved by the dense eig of W (method 'dense', marginal.py), cell
    by cell: the same truncation pairs and the same answer (found or not), tau_min and its error
    estimate to rounding, and each answer certified complete up to tau_min (or tau_max where
    there is none) on both paths."""
    from spectralshell.reports.figures import fig_5_18_scene
    from spectralshell.solvers import marginal

    arnoldi = []
    original = marginal.smallest_taus
    monkeypatch.setattr(marginal, "smallest_taus",
                        lambda *a, **k: arnoldi.append(1) or original(*a, **k))
    for panel in ("human", "gerbil"):
        arnoldi.clear()
        scene = fig_5_18_scene(panel)
        options = {k: v for k, v in scene["tau_min"].items()
                   if k not in ("over_kinds", "tol_spatial")}
        point = {**scene, "params": {**scene["params"], "n_spatial": 16}, "tau_min": options,
                 "grid": {"frequency": [200.0, 2000.0, 15000.0], "sigma": [3e7, 3e8, 1.5e9]}}
        fast = run_sweep(point, executor="serial").dataset
        used = len(arnoldi)
        with monkeypatch.context() as m:
            m.setattr(solve, "SWEEP_METHOD", "dense")
            dense = run_sweep(point, executor="serial").dataset
        assert used > 0 and len(arnoldi) == used  # the fast path left dense eig; dense did not
        for name in ("has_tau", "n_temporal", "computed"):
            np.testing.assert_array_equal(fast[name].values, dense[name].values)
        found = dense["has_tau"].values
        assert found.any() and not found.all()
        np.testing.assert_allclose(fast["tau_min"].values[found], dense["tau_min"].values[found],
                                   rtol=1e-10)
        np.testing.assert_allclose(fast["error_estimate"].values[found],
                                   dense["error_estimate"].values[found], rtol=1e-6, atol=1e-12)
        for ds in (fast, dense):
            bound = np.where(found, ds["tau_min"].values, options["tau_max"])
            assert np.all(ds["complete_to"].values >= bound)
