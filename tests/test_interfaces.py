"""The API and CLI contracts of the foundation issue: JSON shapes, errors, exit codes, files."""

import json
import os
import stat
import subprocess
import sys

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.results.modes import mode_kind


def run_cli(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_floquet_json_has_exact_shape(capsys):
    code, out, err = run_cli(capsys, "floquet", "mathieu", "--kappa", "0.25", "--nu", "0.1", "--json")
    assert code == 0
    data = json.loads(out)  # exactly one JSON object on stdout
    assert data["model"] == "mathieu" and data["params"] == {"kappa": 0.25, "nu": 0.1}
    for kind in ("harmonic", "subharmonic"):
        assert {"tau", "tau_min", "n_temporal", "error_estimate"} <= set(data[kind])
    assert data["subharmonic"]["tau_min"] == pytest.approx(ss.floquet(
        "mathieu", kappa=0.25, nu=0.1).subharmonic.tau_min, abs=0)


def test_fixed_truncation_and_kind_flags(capsys):
    code, out, _ = run_cli(capsys, "floquet", "mathieu", "--kappa", "1", "--nu", "0.1",
                           "--kind", "harmonic", "--n-temporal", "12", "--json")
    data = json.loads(out)
    assert code == 0 and data["subharmonic"] is None and data["harmonic"]["n_temporal"] == 12


def test_exponents_json(capsys):
    code, out, _ = run_cli(capsys, "exponents", "mathieu", "--kappa", "1", "--nu", "0.1",
                           "--tau", "0.3", "--json")
    data = json.loads(out)
    assert code == 0 and len(data["exponents"]) == 2
    assert set(data["exponents"][0]) == {"re", "im"}


def test_tongues_writes_png_csv_npz_and_json(capsys, tmp_path):
    png, csv, npz = tmp_path / "d.png", tmp_path / "d.csv", tmp_path / "d.npz"
    code, out, _ = run_cli(capsys, "tongues", "mathieu", "--nu", "0.1", "--kappa", "0:3:31",
                           "--png", str(png), "--csv", str(csv), "--npz", str(npz), "--json")
    assert code == 0
    data = json.loads(out)
    assert len(data["kappa"]) == 31 and len(data["tips"]) == 3
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert csv.read_text().splitlines()[0] == "kind,kappa,tau"
    arrays = np.load(npz)
    assert arrays["subharmonic_tau"].size == arrays["subharmonic_kappa"].size > 0
    assert not list(tmp_path.glob(".partial-*"))
    umask = os.umask(0)
    os.umask(umask)
    for path in (png, csv, npz):  # as a plainly created file, not mkstemp's owner-only 0600
        assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask


@pytest.mark.parametrize("args", [
    ["floquet", "mathieu", "--kappa", "-1"],
    ["floquet", "mathieu", "--kappa", "abc"],
    ["floquet", "mathieu", "--kappa", "nan"],
    ["floquet", "mathieu", "--kappa", "1", "--nu", "-0.1"],
    ["floquet", "fibreglass", "--kappa", "1"],
    ["floquet", "mathieu", "--kappa", "1", "--kind", "both-ways"],
    ["floquet", "mathieu", "--kappa", "1", "--n-temporal", "x"],
    ["floquet", "mathieu", "--kappa", "1", "--tol", "-1"],
    ["floquet", "mathieu"],
    ["floquet", "mathieu", "--kappa", "1", "--bogus", "2"],
    ["tongues", "mathieu", "--kappa", "3:0:10"],
    ["tongues", "mathieu", "--kappa", "0:3:0"],
    ["tongues", "mathieu", "--kappa", "0:3"],
    ["tongues", "mathieu", "--kappa", "0:1:5", "--png", "/nonexistent-dir/x.png"],
    ["exponents", "mathieu", "--kappa", "1"],
    ["figure", "fig-99.9"],
    [],
])
def test_bad_input_is_one_line_and_exit_2(capsys, args):
    code, out, err = run_cli(capsys, *args)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and err.startswith("spectralshell: error:")


def test_api_errors_name_parameter_value_and_range():
    with pytest.raises(ss.ParameterError, match=r"nu = -1.0 is invalid: must be a finite real number >= 0"):
        ss.floquet("mathieu", kappa=1.0, nu=-1.0)
    with pytest.raises(ValueError, match=r"kind = 'x' is invalid: must be one of"):
        ss.floquet("mathieu", kind="x", kappa=1.0)
    with pytest.raises(ss.ParameterError, match=r"model = 'sphere2' is invalid"):
        ss.floquet("sphere2", kappa=1.0)
    with pytest.raises(ss.ParameterError, match=r"n_temporal = 0 is invalid: must be an integer in \[1, 400\]"):
        ss.floquet("mathieu", kappa=1.0, n_temporal=0)


def test_negative_stiffness_is_computed_but_flagged(capsys):
    res = ss.exponents("mathieu", kappa=1.0, nu=0.1, tau=0.7)
    assert res.gamma.size == 2 and any("stiffness" in w and "negative" in w for w in res.warnings)
    code, out, err = run_cli(capsys, "exponents", "mathieu", "--kappa", "1", "--nu", "0.1",
                             "--tau", "0.7")
    assert code == 0 and "negative" in err


def test_results_are_reproducible_and_carry_provenance():
    a = ss.floquet("mathieu", kappa=0.7, nu=0.02)
    b = ss.floquet("mathieu", kappa=0.7, nu=0.02)
    assert a.to_dict() == b.to_dict()
    assert a.provenance["version"] == ss.__version__ and a.provenance["options"]["tol"] == 1e-10


def test_provenance_names_the_library_versions():
    """Dense eigensolvers round differently between numpy/scipy/BLAS builds: every result says
    which ones computed it (floquet, natural modes, the CLI's JSON)."""
    import platform

    import mpmath
    import numpy
    import scipy
    from threadpoolctl import threadpool_info

    want = {"python": platform.python_version(), "numpy": numpy.__version__,
            "scipy": scipy.__version__, "mpmath": mpmath.__version__}
    for result in (ss.floquet("mathieu", kappa=0.7, nu=0.02),
                   ss.natural_modes("sphere", m=2, kappa=1.0, nu=0.01)):
        libs = result.provenance["libraries"]
        assert {k: libs[k] for k in want} == want
        # the BLAS builds (dense eigensolvers' rounding) are named; an OpenMP runtime that a
        # later import loads (SHTns) is not: the lookup is once per process, at the first result
        assert all(f"{d['internal_api']} {d['version']}" in libs["blas"]
                   for d in threadpool_info() if d["user_api"] == "blas")
    data = json.loads(subprocess.run(
        [sys.executable, "-m", "spectralshell", "modes", "sphere", "--m", "2", "--zeta", "0.01",
         "--json"], capture_output=True, text=True, check=True).stdout)
    assert data["provenance"]["libraries"]["numpy"] == numpy.__version__


def test_tongues_serial_and_parallel_agree():
    serial = ss.tongues("mathieu", kappa="0.1:2:12", nu=0.05, workers=1, tips=False)
    parallel = ss.tongues("mathieu", kappa="0.1:2:12", nu=0.05, workers=2, tips=False)
    assert serial.to_dict()["subharmonic"] == parallel.to_dict()["subharmonic"]


def test_version_and_module_entry_point():
    out = subprocess.run([sys.executable, "-m", "spectralshell", "--version"], capture_output=True,
                         text=True, check=True).stdout
    assert out.strip() == f"spectralshell {ss.__version__}"


def test_demo_writes_summary_png_and_json(capsys, tmp_path):
    code, out, err = run_cli(capsys, "demo", "--out", str(tmp_path))
    assert code == 0
    assert "tau_min" in out and "finger tip" in out
    assert (tmp_path / "ince_strutt.png").stat().st_size > 10_000
    data = json.loads((tmp_path / "demo.json").read_text())
    assert set(data) == {"floquet", "tongues", "exponents"}


@pytest.mark.parametrize("name", ["fig-2.2", "fig-2.3"])
def test_figures_reproduce(capsys, tmp_path, name):
    code, out, _ = run_cli(capsys, "figure", name, "--out", str(tmp_path), "--workers", "1")
    assert code == 0 and (tmp_path / f"{name}.png").exists()
    data = json.loads((tmp_path / f"{name}.json").read_text())
    for panel in data:  # drawn as traced curves: three tongues below tau = 1 on [0, 3]
        assert len(panel["boundaries"]) == 3
        assert {b["kind"] for b in panel["boundaries"]} == {"harmonic", "subharmonic"}
    if name == "fig-2.2":  # undamped: fingers touch the axis at sqrt(kappa) = k/2, k = 1..3
        tips = sorted(t["kappa"] for t in data[0]["tips"])
        np.testing.assert_allclose(tips, [0.25, 1.0, 2.25], atol=1e-11)


def test_figure_list_names_every_figure(capsys):
    from spectralshell.reports.figures import FIGURES

    code, out, _ = run_cli(capsys, "figure", "list")
    assert code == 0
    assert [line.split()[0] for line in out.splitlines()] == list(FIGURES)


def test_floquet_tau_max_flag_and_the_hint_when_tau_min_runs_away(capsys):
    """The toroidal sphere has no converging harmonic tau (the smallest real tau of a truncation
    grows with N: 24, 133, 268 at N = 10, 20, 40); its subharmonic tau_min is 1.91867... .
    ``--tau-max 0.5`` asks for the physical range only and succeeds; without it the
    non-convergence message points to that flag. Oracle: QZ of the real-form pencil at N = 40."""
    from spectralshell.discretise.hill import assemble
    from spectralshell.models.sphere import hill_system
    from spectralshell.solvers.marginal import dense_taus

    params = ["--m", "3", "--kappa", "0.02", "--nu", "0.006", "--component", "toroidal"]
    system = hill_system(m=3, kappa=0.02, nu=0.006, component="toroidal")
    qz = {kind: dense_taus(assemble(system, kind, 40, "real")) for kind in ("harmonic", "subharmonic")}
    assert not np.any((qz["harmonic"] > 0) & (qz["harmonic"] <= 0.5))
    code, out, _ = run_cli(capsys, "floquet", "sphere", *params, "--tau-max", "0.5", "--json")
    data = json.loads(out)
    assert code == 0 and data["provenance"]["options"]["tau_max"] == 0.5
    assert data["harmonic"]["tau_min"] is None and data["subharmonic"]["tau_min"] is None
    code, out, _ = run_cli(capsys, "floquet", "sphere", *params, "--tau-max", "0.5")
    assert code == 0 and out.count("no marginal tau <= 0.5") == 2
    code, out, _ = run_cli(capsys, "floquet", "sphere", *params, "--tau-max", "5", "--kind",
                           "subharmonic", "--json")
    expected = min(t for t in qz["subharmonic"] if t > 0)
    assert code == 0 and json.loads(out)["subharmonic"]["tau_min"] == pytest.approx(expected, rel=1e-12)
    code, _, err = run_cli(capsys, "floquet", "sphere", *params, "--kind", "harmonic")
    assert code == 1 and "--tau-max 0.5" in err and "tau_max=" not in err
    with pytest.raises(ss.ConvergenceError) as api_err:  # the API names its keywords
        ss.floquet("sphere", m=3, kappa=0.02, nu=0.006, component="toroidal", kind="harmonic")
    assert "tau_max=0.5" in str(api_err.value) and "--" not in str(api_err.value)
    assert run_cli(capsys, "floquet", "sphere", *params, "--tau-max", "-1")[0] == 2


def test_cli_names_its_flags_where_the_library_names_keywords():
    """Library messages name API keywords ``name=``; the CLI shows the flag of each keyword
    that is one of its options, and leaves other text alone."""
    from spectralshell.cli import _as_flags, _option_flags, build_parser

    parser = build_parser()
    flags = _option_flags(parser)
    assert flags["tau_max"] == "--tau-max" and flags["max_points"] == "--max-points"
    message = ("converge to tol=1e-10 by n_temporal=40; give tau_max= at most 3, raise it with "
               "max_points= or SPECTRALSHELL_MAX_POINTS=...; complete_to=2 (a==b)")
    assert _as_flags(message, None) == message  # no parser built: the library's words
    assert _as_flags(message, parser) == (
        "converge to --tol 1e-10 by --n-temporal 40; give --tau-max at most 3, raise it with "
        "--max-points or SPECTRALSHELL_MAX_POINTS=...; complete_to=2 (a==b)")


def test_tongues_tau_max_flag(capsys):
    """``tongues --tau-max 0.5`` lists only tau <= 1/2 at every kappa: the same values as the
    unbounded diagram's below 1/2 (Mathieu, whose diagram tests check against scipy's Mathieu
    characteristic values), and records the bound in the provenance."""
    args = ["tongues", "mathieu", "--nu", "0.1", "--kappa", "0:3:13", "--no-tips", "--json"]
    code, out, _ = run_cli(capsys, *args)
    full = json.loads(out)
    code_b, out_b, _ = run_cli(capsys, *args, "--tau-max", "0.5")
    bounded = json.loads(out_b)
    assert code == code_b == 0 and bounded["provenance"]["options"]["tau_max"] == 0.5
    for kind in ("harmonic", "subharmonic"):
        for every, below in zip(full[kind]["tau"], bounded[kind]["tau"]):
            assert below == pytest.approx([t for t in every if t <= 0.5], abs=1e-9)
    assert any(bounded["subharmonic"]["tau"]) and len(bounded["subharmonic"]["tau"]) == 13


def test_tongues_no_boundaries_flag(capsys):
    """``--no-boundaries`` skips the tracing: the JSON has no boundary curves and records the
    choice, and the grid's tau are those of the traced run (Mathieu, nu = 0.1)."""
    args = ["tongues", "mathieu", "--nu", "0.1", "--kappa", "0.1:1.5:8", "--no-tips", "--json"]
    code, out, _ = run_cli(capsys, *args)
    code_b, out_b, _ = run_cli(capsys, *args, "--no-boundaries")
    traced, bare = json.loads(out), json.loads(out_b)
    assert code == code_b == 0 and traced["boundaries"] and not bare["boundaries"]
    assert traced["provenance"]["options"]["boundaries"] is True
    assert bare["provenance"]["options"]["boundaries"] is False
    assert bare["subharmonic"]["tau"] == traced["subharmonic"]["tau"]


def test_modes_text_labels_a_practically_real_mode():
    """m = 2, zeta = 5: the least damped mode has Im gamma = 3.366e-13 (a 30-digit polish agrees,
    so the mode is off the real axis), but |Re gamma| is 1.4e11 times larger: the text calls it
    overdamped in practice and gives the ratio; an inviscid mode is oscillatory."""
    res = ss.natural_modes("sphere", m=2, zeta=5.0, count=1, precision=30)
    assert res.gamma_digits[0][1].startswith("3.3659263")
    g = complex(res.gamma[0])
    assert mode_kind(g, float(res.error_estimate[0])) == "overdamped in practice: Im/|Re| = 7.4e-12"
    assert mode_kind(g, 1e-12) == "overdamped"  # real to within a larger error
    assert mode_kind(2.19j, 1e-15) == "oscillatory"
    assert mode_kind(-1.09 + 1.58j, 1e-14) == "oscillatory"


def test_help_lists_each_models_parameters_with_meaning_and_default():
    """``help(ss.floquet)`` and the other entry points taking ``**params`` list, per model,
    each parameter's meaning and default (from the parameter metadata)."""
    for function in (ss.floquet, ss.tongues, ss.tau_map, ss.exponents, ss.stability,
                     ss.natural_modes, ss.response):
        doc = function.__doc__
        for model in ("mathieu", "sphere", "fibre", "cochlea"):
            assert f"\n        {model}: " in doc, (function.__name__, model)
        assert "nu : damping nu (dimensionless, >= 0; 0 = undamped); required" in doc
        assert "m : spherical-harmonic degree m >= 2; required" in doc


@pytest.mark.parametrize("suffix,magic", [(".png", b"\x89PNG"), (".svg", b"<?xml"),
                                          (".pdf", b"%PDF")])
def test_figures_are_written_in_the_format_of_their_suffix(suffix, magic, tmp_path, capsys):
    out = tmp_path / f"tongues{suffix}"
    assert main(["tongues", "mathieu", "--kappa", "0.1:1:5", "--nu", "0.1", "--png",
                 str(out)]) == 0
    assert out.read_bytes().startswith(magic)
    base = tmp_path / f"modes{suffix}"
    assert main(["simulate", "sphere", "--m", "2", "--kappa", "0.06", "--nu", "0.002",
                 "--t-end", "1", "--png", str(base)]) == 0
    shape = tmp_path / f"modes_shape{suffix}"
    assert base.read_bytes().startswith(magic) and shape.read_bytes().startswith(magic)
    capsys.readouterr()


@pytest.mark.parametrize("model, given", [("mathieu", {"kappa": 0.3}),
                                          ("sphere", {"m": 2, "kappa": 0.02}),
                                          ("fibre", {"m": 2, "kappa": 0.02}),
                                          ("cochlea", {"kappa": 1.0, "alpha": 0.0})])
def test_missing_nu_is_refused_alike_for_every_model(model, given, capsys):
    """No model silently makes a missing viscosity 0 (inviscid): the API and the CLI refuse it,
    naming nu and its range; nu = 0 given explicitly is the inviscid model."""
    with pytest.raises(ss.ParameterError, match=r"^nu is missing: model '\w+' has no default "
                                                r"for it \(.*nu \(dimensionless, >= 0"):
        ss.floquet(model, kind="subharmonic", **given)
    flags = [x for k, v in given.items() for x in (f"--{k}", str(v))]
    code, out, err = run_cli(capsys, "floquet", model, *flags)
    assert code == 2 and out == "" and err.count("\n") == 1 and "nu is missing" in err
    res = ss.floquet(model, kind="subharmonic", nu=0.0, tau_max=0.5, n_temporal=4,
                     **({"spatial_mode": 1} if model == "cochlea" else {}), **given)
    assert res.params["nu"] == 0.0
