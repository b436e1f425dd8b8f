"""Sweeps of a model with spatial modes are priced before any work (issue 23, section 4): over
the seconds limit they are refused in one line naming the limit and how to raise it, before any
point is solved (checked by making every solve fail, not by a clock); under it the estimate
labels the progress bar. The certificate of an empty answer is part of the price."""

import contextlib
import io

import pytest

from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.models.registry import hill_system
from spectralshell.params.registry import make_params
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.runner import run_sweep, solve
from spectralshell.runner.sweep import priced_sweep, sweep_cost
from spectralshell.solvers import cost
from spectralshell.solvers.marginal import coarser

#: Fig 5.18's gerbil at 100 Hz and 5 kHz: the low frequency needs N up to 400 at M = 32, priced
#: at hours per point.
DEAR = {"model": "cochlea", "ask": ["tau_min"],
        "params": {"rho": 1.0, "mu": 0.02, "length": 1.3, "lambda_c": 3.7},
        "grid": {"frequency": [100.0, 5000.0], "sigma": [1.5e8, 2e9]},
        "tau_min": {"tol": 1e-4, "tau_max": 0.5}}


@pytest.fixture
def no_solve(monkeypatch):
    """Any point solved fails the test: the refusal must come first."""
    def refuse(*args, **kwargs):
        raise AssertionError("a point was solved before the price was checked")
    monkeypatch.setattr(solve, "solve_chunk", refuse)


def test_over_budget_sweep_is_refused_before_any_solve(no_solve, tmp_path):
    with pytest.raises(ParameterError, match=r"4 cochlea points .* seconds \(estimated\), above "
                                             r"the limit of 600; raise it with max_seconds="):
        run_sweep(DEAR, executor="serial", out=tmp_path / "s.zarr")
    assert not (tmp_path / "s.zarr").exists()


def test_cli_refusal_is_one_line_naming_the_flag(no_solve, tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text('model = "cochlea"\nask = ["tau_min"]\n[params]\nmu = 0.02\n'
                     'length = 1.3\nlambda_c = 3.7\n[grid]\nfrequency = [100.0, 5000.0]\n'
                     'sigma = [1.5e8, 2e9]\n[tau_min]\ntol = 1e-4\n')
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(["sweep", str(scene), "--out", str(tmp_path / "s.zarr")])
    assert rc == 2 and len(err.getvalue().strip().splitlines()) == 1
    assert "--max-seconds" in err.getvalue() and "SPECTRALSHELL_MAX_SECONDS" in err.getvalue()


def test_the_estimate_is_the_mean_point_price_and_labels_the_bar():
    """Four points, all sampled: the estimate is their summed least price (both kinds), and
    with the limit raised the label states it."""
    spec = sweep_spec(DEAR)
    seconds, dearest = sweep_cost(spec, spec.size)
    single = [cost.spatial_cost(lambda m, p=spec.params_at({"frequency": f, "sigma": s}):
                                hill_system(make_params("cochlea", {**p, "n_spatial": m})),
                                spec.kinds, upper=False).seconds
              for f in (100.0, 5000.0) for s in (1.5e8, 2e9)]
    assert seconds == pytest.approx(sum(single), rel=1e-12)
    assert dearest.seconds == max(single) and dearest.n_temporal == 400
    assert priced_sweep(spec, spec.size, 1e12).startswith("about ")


def test_the_certificate_is_priced_for_a_viscous_block_model_only():
    """An empty viscous cochlea kind is proved by the zero count at both truncations of the
    pair: priced COUNT_NODES nodes of COUNT_SECONDS (N + 1) M^3 each; nothing for the Mathieu
    equation (its spectra certify) or a 2 x 2 block model (the compiled count)."""
    system = hill_system(make_params("cochlea", {"kappa": 0.1, "nu": 0.01, "alpha": 1.0,
                                                 "n_spatial": 128}))
    n_previous = coarser(15)  # the pair of a fixed n_temporal = 15: (12, 15)
    expected = cost.COUNT_NODES * cost.COUNT_SECONDS * 128 ** 3 * (n_previous + 1 + 16)
    assert cost.certify_seconds(system, (n_previous, 15)) == pytest.approx(expected)
    assert cost.solve_seconds(system, 1, n_temporal=15) == pytest.approx(
        cost.truncation_seconds(128, n_previous) + cost.truncation_seconds(128, 15) + expected)
    for model, params in (("mathieu", {"kappa": 0.3, "nu": 0.1}),
                          ("sphere", {"kappa": 0.3, "nu": 0.01, "m": 2})):
        assert cost.certify_seconds(hill_system(make_params(model, params)), (11, 15)) == 0.0
