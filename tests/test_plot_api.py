"""The public drawing API (issue 26): ``ss.plot.*`` and ``result.plot`` take ``ax=None``, return
the Axes they drew on, and never touch the user's matplotlib backend."""

import subprocess
import sys

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure

import spectralshell as ss
from spectralshell.errors import ParameterError


@pytest.fixture(scope="module")
def results():
    """One small result of each type with a picture."""
    return {
        "tongues": ss.tongues("mathieu", kappa="0.1:1.5:15", nu=0.1, workers=1),
        "floquet": ss.floquet("mathieu", kappa=0.25, nu=0.1),
        "natural_modes": ss.natural_modes("sphere", m=2, kappa=1, nu=0.01),
        "response": ss.response("cochlea", omega=1000, n_spatial=16),
        "trajectory": ss.simulate({"params": {"kappa": 1.0, "nu": 0.05},
                                   "initial": {"shape": "2:0"},
                                   "simulate": {"t_end": 6.0, "n_radial": 16}}),
        "tau_map": ss.tau_map("mathieu", x=("kappa", "0.2:0.3:3"), y=("nu", "0.01:0.1:3"),
                              workers=1),
    }


NAMES = ["tongues", "floquet", "natural_modes", "response", "trajectory", "tau_map"]


@pytest.mark.parametrize("name", NAMES)
def test_without_ax_a_new_figure_is_made_and_its_axes_returned(results, name):
    ax = getattr(ss.plot, name)(results[name])
    assert isinstance(ax, Axes) and isinstance(ax.figure, Figure)
    assert ax.get_xlabel() and ax.get_ylabel()
    assert ax.lines or ax.collections  # something was drawn


@pytest.mark.parametrize("name", NAMES)
def test_drawing_goes_onto_the_given_axes(results, name):
    fig = Figure()
    given = fig.add_subplot(1, 2, 2)
    drawn = getattr(ss.plot, name)(results[name], ax=given)
    assert drawn is given
    assert given.lines or given.collections
    assert fig.axes[0] is given  # no other axes of the figure drawn on (a map's colour bar aside)


@pytest.mark.parametrize("name", [n for n in NAMES if n != "tau_map"])
def test_a_result_draws_itself_as_the_function_does(results, name):
    fig = Figure()
    ax = fig.add_subplot()
    assert results[name].plot(ax=ax) is ax
    reference = getattr(ss.plot, name)(results[name])
    assert len(ax.lines) == len(reference.lines)
    assert ax.get_title() == reference.get_title()


def test_draw_dispatches_a_dataset_and_refuses_a_result_without_picture(results):
    assert isinstance(ss.plot.draw(results["tau_map"]), Axes)
    exps = ss.exponents("mathieu", kappa=1, nu=0.1, tau=0.3)
    with pytest.raises(ParameterError, match="ExponentsResult"):
        ss.plot.draw(exps)


def test_the_floquet_picture_marks_every_marginal_tau(results):
    res = results["floquet"]
    ax = ss.plot.floquet(res, tau_max=25.0)
    xs = np.concatenate([line.get_xdata() for line in ax.lines if line.get_marker() in "+o"])
    expected = np.concatenate([m.tau[m.tau <= 25.0] for m in res.marginals()])
    np.testing.assert_array_equal(np.sort(xs), np.sort(expected))


def test_notebook_use_leaves_the_backend_and_pyplot_alone(tmp_path):
    """``ss.plot`` and ``result.plot`` in a session with its own backend: the backend stays,
    pyplot is never imported, and ``import spectralshell`` does not import matplotlib."""
    code = f"""
import sys
import spectralshell as ss
assert "matplotlib" not in sys.modules
import matplotlib
matplotlib.use("svg")
ax = ss.plot.tongues(ss.tongues("mathieu", kappa="0.1:1:5", nu=0.1, workers=1, tips=False))
ss.floquet("mathieu", kappa=0.25, nu=0.1).plot(ax=ax.figure.add_subplot(2, 1, 2))
ax.figure.savefig(r"{tmp_path / 'both.png'}")
assert matplotlib.get_backend() == "svg", matplotlib.get_backend()
assert "matplotlib.pyplot" not in sys.modules
"""
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "both.png").stat().st_size > 5_000
