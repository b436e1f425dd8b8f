"""Hostile input: every failure is one line with the right exit status (issue 23, section 5).

Bad input exits 2 with one line on stderr (API: ParameterError naming the parameter); a result
that cannot reach its accuracy exits 1 with one line (API: ConvergenceError); a result is
finite. Never a traceback, OverflowError, TypeError, KeyError or ZeroDivisionError. The CLI runs
in-process (``spectralshell.cli.main``), as in tests/test_cli_fuzz.py.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.params.scene import load_scene, plan
from spectralshell.params.stiffness import amplitude_warnings, threshold_warnings

#: Text the CLI refuses for every real parameter (outside [1e-100, 1e100] in magnitude, or not
#: a finite number).
REFUSED_TEXT = ["1e308", "-1e308", "1e-308", "1e-300", "5e-324", "nan", "inf", "-inf", "1e400",
                "1" + "0" * 400, "0x10", ""]

#: (command line with X where the value goes) over every command's real flags.
NUMERIC_FLAGS = [
    ["floquet", "mathieu", "--kappa", "0.25", "--nu=X"],
    ["floquet", "mathieu", "--nu", "0", "--kappa=X"],
    ["floquet", "mathieu", "--kappa", "0.25", "--tau-max=X"],
    ["floquet", "mathieu", "--kappa", "0.25", "--tol=X"],
    ["floquet", "sphere", "--m", "2", "--kappa", "0.02", "--nu=X"],
    ["floquet", "fibre", "--m", "2", "--nu", "0", "--kappa=X"],
    ["floquet", "cochlea", "--omega=X"],
    ["floquet", "cochlea", "--omega", "1000", "--sigma=X"],
    ["floquet", "cochlea", "--omega", "1000", "--length=X"],
    ["response", "cochlea", "--omega=X"],
    ["response", "cochlea", "--omega", "1000", "--rho=X"],
    ["exponents", "mathieu", "--kappa", "1", "--nu", "0.1", "--tau=X"],
    ["stability", "sphere", "--kappa", "0.02", "--nu", "0.006", "--m", "2:3", "--tau=X"],
    ["modes", "sphere", "--m", "2", "--zeta=X"],
    ["modes", "sphere", "--m", "2", "--radius", "6", "--sigma=X", "--rho", "1", "--mu", "0.01"],
    ["modes", "cochlea", "--sigma=X", "--n-spatial", "8"],
    ["tongues", "mathieu", "--nu=X", "--kappa", "0:1:3"],
    ["tongues", "mathieu", "--nu", "0.1", "--kappa", "0:X:3"],
    ["simulate", "sphere", "--m", "2", "--kappa", "0.06", "--nu", "0.002", "--t-end=X"],
    ["simulate", "sphere", "--m", "2", "--kappa", "0.06", "--nu", "0.002", "--t-end", "1",
     "--dt=X"],
]


def _one_line(err: str) -> None:
    assert err.count("\n") == 1 and err.endswith("\n") and "Traceback" not in err, err


def _run(argv, capsys) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _refused(argv, capsys) -> str:
    code, out, err = _run(argv, capsys)
    assert code == 2 and out == "", (argv, code, out, err)
    _one_line(err)
    assert err.startswith("spectralshell: error: ")
    return err


@pytest.mark.parametrize("template", NUMERIC_FLAGS, ids=lambda t: "-".join(t[:2] + [t[-1].split("=")[0]]))
@given(text=st.sampled_from(REFUSED_TEXT))
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
def test_extreme_numbers_are_refused_in_one_line(template, text, capsys):
    argv = [a.replace("X", text) for a in template]
    err = _refused(argv, capsys)
    assert "must be" in err or "invalid" in err


def _finite_json(text: str) -> dict:
    def refuse(constant):
        raise AssertionError(f"{constant} in the JSON output")
    return json.loads(text, parse_constant=refuse)


@given(value=st.one_of(st.floats(min_value=1e-100, max_value=1e100),
                       st.floats(min_value=-1e100, max_value=-1e-100), st.just(-0.0),
                       st.just(0.0)))
@example(value=1e100)
@example(value=-1e100)
@example(value=1e-100)
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
def test_accepted_extremes_give_a_finite_result_or_one_line(value, capsys):
    """Within the accepted range the cheap Mathieu commands exit 0 with finite JSON, 1 with one
    line (not converged), or 2 with one line (e.g. a negative kappa)."""
    for argv in (["floquet", "mathieu", "--kappa", "0.25", "--nu", repr(value), "--json"],
                 ["floquet", "mathieu", "--kappa", repr(value), "--nu", "0.1", "--json"],
                 ["exponents", "mathieu", "--kappa", "1", "--nu", "0.1", "--tau", repr(value),
                  "--json"]):
        code, out, err = _run(argv, capsys)
        assert code in (0, 1, 2), (argv, code, err)
        if code == 0:
            _finite_json(out)
            assert "Traceback" not in err
        else:
            _one_line(err)


API_CALLS = {
    "floquet-nu": lambda v: ss.floquet("mathieu", kappa=0.25, nu=v),
    "floquet-kappa": lambda v: ss.floquet("sphere", m=2, kappa=v, nu=0.006),
    "floquet-omega": lambda v: ss.floquet("cochlea", omega=v, n_spatial=8),
    "floquet-mu": lambda v: ss.floquet("cochlea", omega=1000.0, mu=v, n_spatial=8),
    "response-omega": lambda v: ss.response("cochlea", omega=v),
    "exponents-tau": lambda v: ss.exponents("mathieu", kappa=1.0, nu=0.1, tau=v),
    "stability-tau": lambda v: ss.stability("sphere", kappa=0.02, nu=0.006, tau=v, m="2"),
    "modes-sigma": lambda v: ss.natural_modes("sphere", m=2, physical={
        "radius": 6.0, "sigma": v, "rho": 1.0, "mu": 0.01}),
    "tau-map-sigma": lambda v: ss.tau_map("sphere", x=("sigma", [v]), y=("bpm", [60.0]), m="2",
                                          physical={"rho": 1.0, "mu": 0.04, "radius": 2.0},
                                          workers=1),
}

HOSTILE = st.one_of(st.sampled_from([1e308, -1e308, 1e-308, 5e-324, math.inf, -math.inf,
                                     math.nan, 10**400, -(10**400), "6", "0.1", None, [1.0],
                                     True]),
                    st.floats(min_value=1e101, max_value=1e308),
                    st.floats(min_value=1e-320, max_value=1e-101))


@pytest.mark.parametrize("name", API_CALLS)
@given(value=HOSTILE)
@settings(max_examples=15, deadline=None)
def test_api_raises_only_parameter_errors(name, value):
    with pytest.raises(ss.ParameterError) as info:
        API_CALLS[name](value)
    assert "=" in str(info.value)


def test_derived_parameters_name_the_inputs():
    """kappa = sigma pi / (rho L omega^2) out of range names omega, not only kappa."""
    with pytest.raises(ss.ParameterError, match=r"kappa = sigma pi / \(rho L omega\^2\) from .*"
                                                 r"omega = 1e-60"):
        ss.floquet("cochlea", omega=1e-60, n_spatial=8)
    with pytest.raises(ss.ParameterError, match=r"omega = 1e\+308 is invalid"):
        ss.floquet("cochlea", omega=1e308, n_spatial=8)


@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")
def test_bessel_argument_is_named_as_nu():
    import numpy as np

    from spectralshell.models import fibre, sphere

    with pytest.raises(ss.ParameterError, match=r"^nu = 1e-50 is out of reach") as info:
        sphere._p_q(2, np.array([1e300j]), 1e-50)
    assert not str(info.value).startswith("z")
    with pytest.raises(ss.ParameterError, match=r"^nu = 1e-50 is out of reach"):
        fibre.unforced(np.array([1e300j]), m=2, kappa=0.02, nu=1e-50)


@pytest.mark.parametrize("axis", [("bogus", "1:2:3"), ("bogus", [1.0]), "kappa", ("kappa",),
                                  ("sigma", [1e3])])
def test_tau_map_axis_names_are_checked(axis):
    with pytest.raises(ss.ParameterError, match=r"kappa'?, '?nu"):
        ss.tau_map("sphere", x=axis, y=("nu", [0.01]), m="2", workers=1)


def test_tau_map_physical_keys_are_checked():
    common = dict(x=("sigma", [1e3]), y=("bpm", [60.0]), m="2", workers=1)
    with pytest.raises(ss.ParameterError, match="physical bogus is unknown"):
        ss.tau_map("sphere", physical={"rho": 1, "mu": 0.04, "radius": 2, "bogus": 1}, **common)
    with pytest.raises(ss.ParameterError, match="radius is missing"):
        ss.tau_map("sphere", physical={"rho": 1, "mu": 0.04}, **common)
    with pytest.raises(ss.ParameterError, match="rho = '1'"):
        ss.tau_map("sphere", physical={"rho": "1", "mu": 0.04, "radius": 2}, **common)


# ---------------------------------------------------------------------------------- scenes

def test_non_utf8_scene_names_file_and_offset(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_bytes(b'model = "mathieu"\n# \xff\n[params]\nkappa = 1\n')
    for argv in (["run", str(path), "--out", str(tmp_path / "o")],
                 ["sweep", str(path), "--out", str(tmp_path / "x.zarr")],
                 ["simulate", str(path)]):
        err = _refused(argv, capsys)
        assert "bad.toml" in err and "not UTF-8" in err and "offset 20" in err


@pytest.mark.parametrize("scene, key", [
    ({"model": "mathieu", "params": {"kappa": "0.25", "nu": 0}}, "kappa = '0.25'"),
    ({"model": "sphere", "params": {"m": "2", "kappa": 0.02, "nu": 0}}, "m = '2'"),
    ({"model": "mathieu", "params": {"kappa": 1}, "ask": "floquet"}, "ask = 'floquet'"),
    ({"model": "mathieu", "params": {"kappa": 1}, "ask": ["tongues"],
      "tongues": {"kappa": {"start": 0, "stop": 1, "num": "6"}}}, "num = '6'"),
    ({"model": "mathieu", "params": {"kappa": 1}, "ask": ["exponents"],
      "exponents": {"tau": "0.3"}}, "exponents.tau = '0.3'"),
])
def test_scene_strings_are_not_numbers(scene, key):
    with pytest.raises(ss.ParameterError, match="is invalid") as info:
        plan(scene)
    assert key in str(info.value)


@pytest.mark.parametrize("scene, key", [
    ({"model": "mathieu", "ask": "tau_min", "params": {"nu": 0.1},
      "grid": {"kappa": {"start": 0.1, "stop": 1, "num": 3}}}, "ask = 'tau_min'"),
    ({"model": "mathieu", "params": {"nu": 0.1},
      "grid": {"kappa": {"start": 0.1, "stop": 1, "num": "6"}}}, "num = '6'"),
])
def test_sweep_scene_strings_are_type_errors(scene, key):
    with pytest.raises(ss.ParameterError, match="is invalid") as info:
        ss.sweep(scene, executor="serial")
    assert key in str(info.value)


def test_scene_text_still_parses_numbers_in_range_strings():
    """'start:stop:num' is text by design: its parts are read as numbers."""
    assert plan({"model": "mathieu", "params": {"kappa": 1.0, "nu": 0.0}, "ask": ["tongues"],
                 "tongues": {"kappa": "0:1:3"}}).tasks[0].options["kappa"].size == 3
    assert load_scene('model = "mathieu"\n')["model"] == "mathieu"


# ------------------------------------------------------------------------------ output paths

@pytest.mark.parametrize("flag, bad, expected", [
    ("--png", "{dir}", "it is a directory"),
    ("--png", "{dir}/out.xyz", "ending in .png"),
    ("--png", "{dir}/missing/out.png", "does not exist"),
    ("--csv", "/dev/null", "it is a device"),
    ("--npz", "{dir}", "it is a directory"),
    ("--npz", "{dir}/out.png", "ending in .npz"),
])
def test_tongues_output_paths(flag, bad, expected, tmp_path, capsys):
    argv = ["tongues", "mathieu", "--nu", "0.1", "--kappa", "0:1:3", flag,
            bad.replace("{dir}", str(tmp_path))]
    assert expected in _refused(argv, capsys)


def test_fifo_is_refused(tmp_path, capsys):
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    assert "FIFO" in _refused(["response", "cochlea", "--omega", "1000", "--png", str(fifo)], capsys)


def test_plot_png_suffix(tmp_path, capsys):
    err = _refused(["plot", str(tmp_path / "store.zarr"), "--png", str(tmp_path / "x.txt")], capsys)
    assert "ending in .png" in err


def test_simulate_output_paths(tmp_path, capsys):
    base = ["simulate", "sphere", "--m", "2", "--kappa", "0.06", "--nu", "0.002", "--t-end", "1"]
    assert "directory" in _refused(base + ["--npz", str(tmp_path)], capsys)
    (tmp_path / "run_shape.png").mkdir()  # the shape PNG written next to --png
    assert "run_shape.png" in _refused(base + ["--png", str(tmp_path / "run.png")], capsys)


def test_existing_regular_file_is_replaced(tmp_path, capsys):
    csv = tmp_path / "out.csv"
    csv.write_text("old\n")
    code, _, err = _run(["tongues", "mathieu", "--nu", "0.1", "--kappa", "0:1:3", "--no-tips",
                         "--csv", str(csv)], capsys)
    assert code == 0 and csv.read_text().startswith("kind,kappa,tau"), err


# ----------------------------------------------------------------------------- simulate steps

def test_step_count_bound_names_t_end_and_dt(capsys):
    err = _refused(["simulate", "sphere", "--m", "2", "--kappa", "0.06", "--nu", "0.002",
                    "--t-end", "1e100"], capsys)
    assert "simulate.t_end = 1e+100" in err and "50,000,000" in err and "dt" in err


# ------------------------------------------------------------------------------ tau warnings

def test_amplitude_warning_states_the_true_condition():
    assert amplitude_warnings(0.5) == [] and amplitude_warnings(-0.5) == []
    for tau in (-1.0, 1.0):
        (w,) = amplitude_warnings(tau)
        assert w.startswith("|tau| = 1 > 1/2")


def test_threshold_warning_only_when_tau_min_exceeds_half():
    assert threshold_warnings({"harmonic": [0.3], "subharmonic": [None]}) == []
    (w,) = threshold_warnings({"harmonic": [0.3], "subharmonic": [0.7]})
    assert w.startswith("subharmonic tau_min = 0.7 > 1/2")
    (w,) = threshold_warnings({"harmonic": [0.3, 0.9, None]})
    assert "at 1 of 3 points" in w


def test_floquet_flags_tau_min_not_larger_marginal_tau():
    """kappa = 0.25, nu = 0.01: the subharmonic tau_min lies below 1/2, further marginal tau of
    the same kind above it; only a kind whose tau_min exceeds 1/2 is flagged."""
    res = ss.floquet("mathieu", kappa=0.25, nu=0.01)
    assert res.subharmonic.tau_min < 0.5 < res.subharmonic.tau.max()
    assert not any(w.startswith("subharmonic") for w in res.warnings)
    assert any(w.startswith("harmonic tau_min") for w in res.warnings) == (
        res.harmonic.tau_min is not None and res.harmonic.tau_min > 0.5)
