"""Sweeps, tau maps and the cost estimate of the sphere with a non-uniform kappa (issue 28,
part 2: "the same in scenes and sweeps").

Oracles: independent ``ss.floquet`` calls at every point (the per-point API, with its own
refinement and critical-mode content), a clean run for a resumed store, and the per-degree
systems of the uniform model for the price of a truncation.
"""

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.errors import ParameterError
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.runner.sweep import run_sweep
from spectralshell.runner.store import open_sweep
from sweep_cases import interrupted

KAPPA = "0.02*(1 + 0.3*cos(theta)**2)"
NUS = [0.006, 0.008, 0.01]
SCENE = {"model": "sphere", "params": {"kappa": KAPPA, "l_max": 4}, "grid": {"nu": NUS},
         "tau_min": {"tol": 1e-8}, "sweep": {"chunk": 1}}
NONUNIFORM_VARIABLES = ("l_max", "critical_l", "critical_k", "critical_share")


@pytest.fixture(scope="module")
def clean():
    return run_sweep(SCENE, executor="serial")


def test_a_sweep_equals_floquet_at_every_point(clean):
    ds = clean.dataset
    assert set(NONUNIFORM_VARIABLES) <= set(ds.data_vars)
    assert ds["l_max"].attrs["long_name"].startswith("degree truncation")
    for i, nu in enumerate(NUS):
        res = ss.floquet("sphere", kappa=KAPPA, nu=nu, l_max=4, tol=1e-8, tau_max=0.5)
        for q, kind in enumerate(("harmonic", "subharmonic")):
            m, at = getattr(res, kind), (i, q)
            assert bool(ds["has_tau"].values[at]) == (m.tau_min is not None)
            assert int(ds["l_max"].values[at]) == res.l_max == 4
            if m.tau_min is None:
                assert np.isnan(ds["tau_min"].values[at])
                assert int(ds["critical_l"].values[at]) == 0
                continue
            assert ds["tau_min"].values[at] == pytest.approx(m.tau_min, abs=1e-12)
            assert ds["error_estimate"].values[at] == pytest.approx(m.error_estimate, abs=1e-12)
            assert int(ds["n_temporal"].values[at]) == m.n_temporal
            lead = res.content[kind][0]
            assert (int(ds["critical_l"].values[at]), int(ds["critical_k"].values[at])) == \
                (lead["l"], lead["k"])
            assert ds["critical_share"].values[at] == pytest.approx(lead["share"], abs=1e-12)
    # the subharmonic tongue of degree 3 lies below 1/2 at each nu; the harmonic one above it
    assert ds["has_tau"].values[:, 1].all() and not ds["has_tau"].values[:, 0].any()
    assert (ds["critical_l"].values[:, 1] == 3).all()


def test_a_sweep_stores_what_each_point_proves(clean):
    """Every point stores complete_to, floquet's at the point capped at tau_max (issue 23,
    section 2): the empty harmonic points proved up to 1/2, each subharmonic tau_min proved
    the smallest of its sectors (complete_to = tau_min); none is uncertified."""
    from spectralshell.results.maps import uncertified

    ds = clean.dataset
    assert clean.uncertified == 0 and not uncertified(ds).any()
    np.testing.assert_array_equal(ds["complete_to"].values[:, 0], 0.5)
    np.testing.assert_array_equal(ds["complete_to"].values[:, 1], ds["tau_min"].values[:, 1])
    res = ss.floquet("sphere", kappa=KAPPA, nu=NUS[0], l_max=4, tol=1e-8, tau_max=0.5)
    assert (res.harmonic.complete_to, res.subharmonic.complete_to) == \
        tuple(ds["complete_to"].values[0])


def test_a_resumed_sweep_equals_a_clean_run(clean, tmp_path):
    out = tmp_path / "nonuniform.zarr"
    interrupted(SCENE, out, 1)
    assert int(open_sweep(out)["computed"].sum()) == 2       # one chunk: one nu, both kinds
    resumed = run_sweep(SCENE, executor="serial", out=out)
    assert (resumed.computed, resumed.skipped) == (4, 2)
    for ds in (resumed.dataset, open_sweep(out)):
        assert list(ds.data_vars) == list(clean.dataset.data_vars)
        for name in ds.data_vars:
            np.testing.assert_array_equal(ds[name].values, clean.dataset[name].values,
                                          err_msg=name)


def test_a_uniform_scene_keeps_its_variables():
    spec = sweep_spec({"model": "sphere", "params": {"kappa": 0.02, "nu": 0.006},
                       "grid": {"m": [2, 3]}})
    assert not spec.nonuniform
    ranged = sweep_spec({"model": "sphere", "params": {"nu": 0.006},   # a range's text
                         "grid": {"kappa": "0.01:0.2:3", "m": [2]}})
    assert not ranged.nonuniform and ranged.shape == (3, 1, 2)
    from spectralshell.runner.solve import variables
    assert set(variables(spec)) == {"tau_min", "has_tau", "error_estimate", "n_temporal",
                                    "complete_to"}


def test_tau_map_over_nu_and_l_max_equals_floquet():
    ds = ss.tau_map("sphere", kappa=KAPPA, x=("nu", [0.006, 0.01]), y=("l_max", [4]),
                    kind="subharmonic", workers=1)
    assert ds["tau_min"].dims == ("nu", "l_max", "kind") and "l_max" not in ds.data_vars
    for i, nu in enumerate((0.006, 0.01)):
        res = ss.floquet("sphere", kappa=KAPPA, nu=nu, l_max=4, kind="subharmonic", tol=1e-8,
                         tau_max=0.5)
        assert ds["tau_min"].values[i, 0, 0] == pytest.approx(res.subharmonic.tau_min, abs=1e-12)


@pytest.mark.parametrize("scene, words", [
    ({"params": {"kappa": KAPPA}, "grid": {"m": [2, 3], "nu": [0.01]}}, "'m' is invalid"),
    ({"params": {"nu": 0.01}, "grid": {"kappa": [0.1], "l_max": [4]}}, "kappa = [0.1] is invalid"),
    ({"params": {"kappa": KAPPA, "l_max": 4}, "grid": {"nu": [0.01]},
      "tau_min": {"tol_spatial": 1e-4}}, "tol_spatial = 0.0001 is invalid with a fixed l_max"),
    ({"params": {"kappa": KAPPA}, "grid": {"nu": [0.01], "l_max": [4, 99]}}, "l_max"),
    ({"params": {"kappa": KAPPA}, "grid": {"nu": [0.0, 0.01]}}, "nu = 0"),
    ({"params": {"kappa": KAPPA, "nu": 0.01}, "grid": {"sigma": [1.0]}}, "'sigma' is invalid"),
])
def test_bad_nonuniform_scenes_are_refused(scene, words):
    with pytest.raises(ParameterError) as info:
        sweep_spec({"model": "sphere", **scene})
    assert words in str(info.value) and "\n" not in str(info.value)


def test_tau_map_refuses_degrees_with_a_nonuniform_kappa():
    with pytest.raises(ParameterError, match="m = 3 is invalid with a non-uniform kappa"):
        ss.tau_map("sphere", kappa=KAPPA, m=3, x=("nu", [0.01]), y=("l_max", [4]))


def test_a_capped_solve_keeps_a_later_sector_below_the_cap():
    """With tau_max, a first sector without a tau below it no longer hides a later sector's
    (it raised a TypeError): the capped subharmonic tau_min is the uncapped one."""
    capped = ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, tol=1e-10, tau_max=0.5)
    free = ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, tol=1e-10)
    assert free.subharmonic.tau_min < 0.5 < free.harmonic.tau_min
    assert capped.harmonic.tau_min is None
    assert capped.subharmonic.tau_min == pytest.approx(free.subharmonic.tau_min, abs=1e-9)


ASYMMETRIC = "0.02*(1 + 0.2*sin(theta)*cos(phi) + 0.1*cos(theta))"


def test_a_uniform_kappa_is_priced_as_the_per_degree_solves():
    """The price of a truncation (before any solve) is that of the per-degree systems of the
    uniform model when kappa is uniform: the sectors are the degrees' poloidal pairs and
    toroidal slots."""
    from spectralshell.discretise.sphere_nonuniform import nonuniform_sphere
    from spectralshell.models.registry import hill_system
    from spectralshell.params.sphere import SphereParams
    from spectralshell.runner.nonuniform import Price
    from spectralshell.solvers.cost import solve_seconds

    sphere = nonuniform_sphere(kappa=lambda t, p: 0.02 + 0 * t, nu=0.006, l_max=6)
    price = Price.of(sphere, 2, None)
    per_degree = [hill_system(SphereParams(m=l, kappa=0.02, nu=0.006, component=c))
                  for l in range(2, 7) for c in ("poloidal", "toroidal")]
    assert price.seconds == pytest.approx(sum(solve_seconds(s, 2) for s in per_degree),
                                          rel=1e-12)
    assert price.block == 2


def test_a_costly_truncation_is_refused_before_any_work(monkeypatch):
    import spectralshell.runner.nonuniform as nonuniform

    def no_solve(*args, **kwargs):
        raise AssertionError("a sector was solved before the price was checked")

    with monkeypatch.context() as patch:
        patch.setattr(nonuniform, "marginal_tau", no_solve)
        with pytest.raises(ParameterError) as info:      # priced ~27 min at l_max = 12
            ss.floquet("sphere", kappa=ASYMMETRIC, nu=0.006, l_max=12)
        text = str(info.value)
        assert "l_max = 12" in text and "blocks <= " in text and "max_seconds=" in text
        assert "SPECTRALSHELL_MAX_SECONDS" in text and "\n" not in text
        with pytest.raises(ParameterError, match="above the limit of 0.001"):
            ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, max_seconds=1e-3)
    ok = ss.floquet("sphere", kappa=KAPPA, nu=0.006, l_max=4, max_seconds=10, tau_max=0.5)
    assert ok.subharmonic.tau_min is not None


def test_cli_refuses_a_costly_truncation_with_one_line(capsys):
    from spectralshell.cli import main
    code = main(["floquet", "sphere", "--kappa", ASYMMETRIC, "--nu", "0.006", "--l-max", "12"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "--max-seconds" in err
