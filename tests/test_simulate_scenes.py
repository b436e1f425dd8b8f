"""`simulate fibre|cochlea --png` and fibre / cochlea simulation scenes (issue 28 §1).

The figure: a valid PNG whose axes name the quantity and unit, with the fitted growth and the
leading Floquet exponent drawn as straight lines whose slopes are checked against the run's fit
and against ``ss.exponents`` (the independent Hill-system oracle). The scenes: the run of a scene
is the run of the same keywords given to ``ss.simulate`` (bit for bit), and a malformed scene is
refused in one line, exit 2, before any work and before its output directory is made.
"""

import json
import math

import numpy as np
import pytest
from matplotlib.axes import Axes

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.runner.simulate import leading_exponent
from test_figure_labels import svg_text

PNG = b"\x89PNG\r\n\x1a\n"
FIBRE = {"m": 3, "kappa": 0.02, "nu": 2e-4, "tau": 0.124}
FIBRE_RUN = {"t_end": 70.0, "n_inner": 24, "n_outer": 32}
COCHLEA = {"kappa": 1.0, "nu": 1e-3, "alpha": 0.5, "n_spatial": 2, "tau": 0.3}
COCHLEA_RUN = {"t_end": 70.0, "n_vertical": 24}


@pytest.fixture(scope="module")
def fibre_run():
    return ss.simulate("fibre", **FIBRE, **FIBRE_RUN)


def _slope(line) -> float:
    """d log y / d x of a straight line on the log axis (x in forcing periods)."""
    x, y = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
    return math.log(y[-1] / y[0]) / (x[-1] - x[0])


def test_the_figure_draws_the_fit_and_the_exponent_as_slopes(fibre_run):
    """Axis labels with units; the dashed line rises at the fitted growth rate and the dotted
    one at Re gamma of ss.exponents, 2 pi rate per forcing period; the run's fit agrees with
    Re gamma within its stated error."""
    gamma = leading_exponent(fibre_run)
    assert gamma == complex(ss.exponents("fibre", count=1, **FIBRE).gamma[0])
    assert abs(fibre_run.growth_rate - gamma.real) <= fibre_run.error_estimate
    ax = ss.plot.stepped(fibre_run, exponent=gamma)
    assert isinstance(ax, Axes) and fibre_run.plot().get_ylabel() == ax.get_ylabel()
    assert ax.get_xlabel() == "time t / 2π (forcing periods)"
    assert ax.get_yscale() == "log" and "(dimensionless)" in ax.get_ylabel()
    assert "X^r" in ax.get_ylabel()
    data, fitted, reference = ax.lines
    np.testing.assert_allclose(data.get_xdata(), fibre_run.times / (2 * math.pi))
    assert _slope(fitted) == pytest.approx(2 * math.pi * fibre_run.growth_rate, rel=1e-9)
    assert _slope(reference) == pytest.approx(2 * math.pi * gamma.real, rel=1e-9)
    assert len(ss.plot.stepped(fibre_run).lines) == 2      # no exponent given: none drawn


def test_the_svg_names_every_line_and_both_axes(fibre_run, tmp_path):
    from spectralshell.plots import stepped

    text = svg_text(lambda p: stepped.save(fibre_run, p, exponent=0.00803769 + 0.5j),
                    tmp_path / "run.svg")
    letters = "".join(text.split())  # mathtext labels come letter by letter
    for needle in ("time t / 2π (forcing periods)", "(dimensionless)", "steppedXr",
                   "fitted growth rate +0.00803", "Floquet exponent Re γ = +0.00803769",
                   "κ = 0.02", "τ = 0.124", "m = 3"):
        assert "".join(needle.split()) in letters, needle


def test_cli_png_of_the_cochlea(tmp_path, capsys):
    png = tmp_path / "run.png"
    argv = ["simulate", "cochlea", *(f"--{k.replace('_', '-')}={v}"
                                     for k, v in {**COCHLEA, **COCHLEA_RUN}.items()),
            "--png", str(png)]
    assert main(argv) == 0
    assert png.read_bytes()[:8] == PNG and f"wrote {png}" in capsys.readouterr().out
    assert not list(tmp_path.glob("*_shape*"))     # the membrane shape is the sphere's only


@pytest.mark.parametrize("bad, needle", [("{dir}", "directory"), ("{dir}/run.txt", ".png"),
                                         ("{dir}/missing/run.png", "missing")])
def test_cli_png_bad_paths_refused_in_one_line_before_the_run(bad, needle, tmp_path, capsys):
    argv = ["simulate", "fibre", "--m", "3", "--kappa", "0.02", "--nu", "2e-4", "--png",
            bad.replace("{dir}", str(tmp_path))]
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and needle in err


def _toml(value) -> str:
    return f'"{value}"' if isinstance(value, str) else repr(value)


def _scene(path, model, tables, out):
    lines = [f'model = "{model}"']
    for table, values in {**tables, "output": {"dir": str(out)}}.items():
        lines += [f"[{table}]", *(f"{k} = {_toml(v)}" for k, v in values.items())]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_fibre_scene_is_the_run_of_its_keywords(fibre_run, tmp_path, capsys):
    """`spectralshell simulate fibre.toml`: the keywords in [params], [initial], [simulate]
    give exactly ss.simulate's run, written to the scene's directory (JSON, NPZ, figure)."""
    out = tmp_path / "out"
    scene = _scene(tmp_path / "fibre.toml", "fibre",
                   {"params": FIBRE, "initial": {"amplitude": 1.0}, "simulate": FIBRE_RUN}, out)
    assert main(["simulate", str(scene)]) == 0
    capsys.readouterr()
    with np.load(out / "fibre.npz") as z:
        np.testing.assert_array_equal(z["values"], fibre_run.values)
    data = json.loads((out / "fibre.json").read_text())
    assert data["growth_rate"] == fibre_run.growth_rate and data["params"] == fibre_run.params
    assert (out / "fibre.png").read_bytes()[:8] == PNG
    again = tmp_path / "again"      # `spectralshell run` runs it too, into --out
    assert main(["run", str(scene), "--out", str(again), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["growth_rate"] == fibre_run.growth_rate
    with np.load(again / "fibre.npz") as z:
        np.testing.assert_array_equal(z["values"], fibre_run.values)


def test_the_planner_points_a_simulation_scene_to_simulate():
    with pytest.raises(ParameterError, match="simulation scene.*ss.simulate"):
        ss.run_scene({"model": "fibre", "params": FIBRE, "simulate": FIBRE_RUN})


def test_a_cochlea_scene_is_the_run_of_its_keywords():
    scene = {"model": "cochlea", "params": COCHLEA, "simulate": COCHLEA_RUN}
    by_scene = ss.simulate(scene)
    by_keywords = ss.simulate("cochlea", **COCHLEA, **COCHLEA_RUN)
    np.testing.assert_array_equal(by_scene.values, by_keywords.values)
    assert by_scene.fit == by_keywords.fit and by_scene.params == by_keywords.params


@pytest.mark.parametrize("model, change, needle", [
    ("fibre", {"simulate": {"n_radial": 24}}, "simulate.n_radial is unknown"),
    ("fibre", {"simulate": {"tau": 0.3}}, "simulate.tau is unknown"),       # belongs in [params]
    ("fibre", {"params": {"m": 1}}, "m = 1"),
    ("fibre", {"params": {"kappa": "0.02"}}, "kappa = '0.02'"),
    ("fibre", {"initial": {"shape": "2:0"}}, "initial.shape is unknown"),
    ("fibre", {"output": {"dir": 3}}, "output.dir"),
    ("fibre", {"model": "mathieu"}, "model = 'mathieu'"),
    ("cochlea", {"params": {"n_spatial": None}}, "params.n_spatial is missing"),
    ("cochlea", {"params": {"alpha": -1.0}}, "alpha"),
    ("cochlea", {"simulate": "fast"}, "simulate = 'fast'"),
])
def test_a_malformed_scene_is_refused_in_one_line_before_any_work(model, change, needle,
                                                                   tmp_path, capsys):
    base = {"fibre": {"params": dict(FIBRE), "simulate": dict(FIBRE_RUN)},
            "cochlea": {"params": dict(COCHLEA), "simulate": dict(COCHLEA_RUN)}}[model]
    scene = {"model": model, **base, "output": {"dir": str(tmp_path / "out")}}
    for key, value in change.items():
        if isinstance(value, dict) and isinstance(scene.get(key), dict):
            scene[key] = {k: v for k, v in {**scene[key], **value}.items() if v is not None}
        else:
            scene[key] = value
    with pytest.raises(ParameterError, match=needle.replace("(", r"\(")):
        ss.simulate(scene)
    path = tmp_path / "bad.toml"
    path.write_text("\n".join(
        [f"{k} = {_toml(v)}" for k, v in scene.items() if not isinstance(v, dict)]
        + [line for k, v in scene.items() if isinstance(v, dict)
           for line in (f"[{k}]", *(f"{n} = {_toml(x)}" for n, x in v.items()))]) + "\n")
    assert main(["simulate", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and needle in err
    assert not (tmp_path / "out").exists()


def test_a_run_setting_out_of_range_is_refused_by_the_stepper_before_its_work():
    """The run's settings are the stepper's to check (t_end >= 20 pi, the step count, the
    price): refused before an eigenproblem."""
    with pytest.raises(ParameterError, match="t_end = 5"):
        ss.simulate({"model": "fibre", "params": FIBRE, "simulate": {"t_end": 5.0}})
    with pytest.raises(ParameterError, match="max_seconds"):
        ss.simulate({"model": "cochlea", "params": {**COCHLEA, "n_spatial": 2000}})
