"""Maps and sweeps state how far each empty answer is proved (issue 23, section 2): every point
stores ``complete_to``; an empty point the zero count cannot prove is kept as uncertified, never
as "none", drawn apart, warned of by the API and exits the CLI with status 1. Checked against
dense QZ of both truncations, and against the values before the certificate."""

import contextlib
import io
import json

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import UncertifiedWarning
from spectralshell.models.registry import hill_system
from spectralshell.params.registry import make_params
from spectralshell.params.sweep_grid import SolverOptions
from spectralshell.plots import sweep_plot
from spectralshell.plots._canvas import subplots
from spectralshell.results.maps import minimum_map, uncertified
from spectralshell.solvers import marginal
from spectralshell.solvers.marginal import TruncationSchedule

from test_certified_empty import qz_in_strip, qz_real_below

#: The viscous sphere at m = 2 over (kappa, nu): 20 of the 24 points (both kinds) have no
#: tau <= 1/2.
SPHERE_MAP = {"x": ("kappa", "0.05:1.5:4"), "y": ("nu", "0.001:0.05:3"), "m": 2}
SCENE = {"model": "sphere", "ask": ["tau_min"], "params": {"m": 2},
         "grid": {"kappa": [0.05, 0.5, 1.5], "nu": [0.001, 0.05]}}


@pytest.fixture(scope="module")
def sphere_map():
    return ss.tau_map("sphere", **SPHERE_MAP, workers=1)


def _uncertifiable(monkeypatch):
    """No empty answer can be proved: the contour path declines, the zero count fails."""
    monkeypatch.setattr(marginal, "smallest_real_tau", lambda *args, **kwargs: None)
    monkeypatch.setattr(marginal, "none_up_to", lambda hill, tau_max, solves=None: False)


def test_certified_empty_points_have_no_real_tau_by_qz(sphere_map):
    """Each empty point states complete_to = tau_max, and QZ of both truncations of its pair
    (the solver's schedule: n_temporal and the one before) has no real tau <= 1/2 nor any
    eigenvalue in the thinnest strip around [0, 1/4]."""
    ds = sphere_map
    empty = ~ds["has_tau"].values
    assert 0 < empty.sum() < empty.size and not uncertified(ds).any()
    np.testing.assert_array_equal(ds["complete_to"].values[empty], 0.5)
    found = ds["has_tau"].values
    assert np.all(ds["complete_to"].values[found] >= ds["tau_min"].values[found])
    for idx in zip(*np.nonzero(empty)):
        point = {d: ds[d].values[i].item() for d, i in zip(ds["tau_min"].dims, idx)}
        system = hill_system(make_params("sphere", {"kappa": point["kappa"],
                                                   "nu": point["nu"], "m": int(point["m"])}))
        sequence = TruncationSchedule.of(system).sequence()
        n = int(ds["n_temporal"].values[idx])
        for truncation in (n, sequence[sequence.index(n) - 1]):
            assert not qz_real_below(system, point["kind"], truncation, 0.5).size
            assert not qz_in_strip(system, point["kind"], truncation, 0.5).size


def test_values_are_those_before_the_certificate(sphere_map, monkeypatch):
    """Where every point is certified, the map is the one solved without the certificate
    (marginal_tau's keywords before issue 23): tau_min, has_tau, error_estimate and n_temporal
    bitwise equal."""
    old = SolverOptions.marginal_kwargs
    monkeypatch.setattr(SolverOptions, "marginal_kwargs",
                        lambda self: {k: v for k, v in old(self).items() if k != "certify_empty"})
    before = ss.tau_map("sphere", **SPHERE_MAP, workers=1)
    for name in ("tau_min", "has_tau", "error_estimate", "n_temporal"):
        np.testing.assert_array_equal(before[name].values, sphere_map[name].values)


def test_uncertified_points_are_marked_and_warned(monkeypatch):
    """With the count made to fail, the empty points are uncertified (complete_to 0), the
    API warns with their number and what to change, and the minimum map marks those cells."""
    _uncertifiable(monkeypatch)
    with pytest.warns(UncertifiedWarning, match=r"20 of 24 points .*tau_max"):
        ds = ss.tau_map("sphere", **SPHERE_MAP, workers=1)
    bad = uncertified(ds)
    np.testing.assert_array_equal(bad.values, ~ds["has_tau"].values)
    np.testing.assert_array_equal(ds["complete_to"].values[bad.values], 0.0)
    cells = minimum_map(ds, "kappa", "nu")["uncertified"].values
    np.testing.assert_array_equal(cells, bad.any(["m", "kind"]).transpose("nu", "kappa").values)
    assert cells.any()


def test_a_minimum_is_unproved_where_another_kind_is(monkeypatch):
    """A cell whose value comes from one kind is unproved when the other kind's empty answer is
    (a real tau of it could lie below), proved when it is proved only below the value."""
    import xarray as xr

    tau = xr.DataArray([[0.3, np.nan]], dims=("x", "kind"),
                       coords={"x": [1.0], "kind": ["harmonic", "subharmonic"]})
    base = xr.Dataset({"tau_min": tau, "has_tau": tau.notnull(),
                       "computed": tau.notnull() | True}, attrs={"tau_max": 0.5})
    for complete_to, unproved in ((0.0, True), (0.3, False), (0.5, False)):
        ds = base.assign(complete_to=tau.copy(data=[[0.3, complete_to]]))
        assert bool(uncertified(ds).any()) is unproved


def run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


def test_cli_sweep_exits_1_with_one_line(tmp_path, monkeypatch):
    """spectralshell sweep: certified, status 0 and uncertified 0; with the count made to fail,
    the store is written, the JSON counts the uncertified points, and one line on stderr
    says what to change (status 1); plot draws them apart and names them in the legend."""
    scene = tmp_path / "s.toml"
    scene.write_text('model = "sphere"\nask = ["tau_min"]\n[params]\nm = 2\n[grid]\n'
                     'kappa = [0.05, 0.5, 1.5]\nnu = [0.001, 0.05]\n')
    rc, out, err = run(["sweep", str(scene), "--out", str(tmp_path / "a.zarr"),
                        "--executor", "serial", "--json"])
    assert rc == 0 and json.loads(out)["uncertified"] == 0, err
    _uncertifiable(monkeypatch)
    rc, out, err = run(["sweep", str(scene), "--out", str(tmp_path / "b.zarr"),
                        "--executor", "serial", "--json"])
    summary = json.loads(out)
    assert rc == 1 and summary["uncertified"] > 0 and summary["computed"] == 12
    assert len(err.strip().splitlines()) == 1 and "not proved" in err and "tau_max" in err
    ds = ss.open_sweep(tmp_path / "b.zarr")
    assert int(uncertified(ds).sum()) == summary["uncertified"]
    fig, ax = subplots(figsize=(6.0, 4.5))
    sweep_plot.draw(ax, ds)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert sweep_plot.UNCERTIFIED_LABEL in labels
