"""CLI fuzzing: every malformed command line or scene gives one line on stderr and exit status 2,
no traceback and no file left behind; an interrupted sweep (SIGINT) keeps complete finished chunks.

Runs ``spectralshell.cli.main`` in-process (fast); only the interrupt test starts a subprocess.
(tests/test_sweep.py covers an in-process KeyboardInterrupt and resume; this adds a real SIGINT
to the CLI's process group, as Ctrl-C sends it.)
"""

from __future__ import annotations

import os
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from spectralshell.cli import main
import spectralshell as ss
from spectralshell.runner import open_sweep

SPHERE = ["--m", "3", "--kappa", "0.02", "--nu", "0.006"]

# (id, argv) with {tmp} replaced by the test's directory; each must exit 2 with one line
BAD_ARGV = [
    # malformed numbers
    ("kappa-text", ["floquet", "mathieu", "--kappa", "abc"]),
    ("kappa-inf", ["floquet", "mathieu", "--kappa", "1e999"]),
    ("kappa-nan", ["floquet", "mathieu", "--kappa", "nan"]),
    ("nu-comma", ["floquet", "mathieu", "--kappa", "0.25", "--nu", "0,1"]),
    ("tol-text", ["floquet", "mathieu", "--kappa", "0.25", "--tol", "small"]),
    ("n-temporal-float", ["floquet", "mathieu", "--kappa", "0.25", "--n-temporal", "2.5"]),
    ("m-text", ["floquet", "sphere", "--m", "two", "--kappa", "0.02"]),
    ("m-float", ["floquet", "sphere", "--m", "2.5", "--kappa", "0.02"]),
    ("tau-text", ["exponents", "mathieu", "--kappa", "1", "--tau", "x"]),
    ("tau-nan", ["stability", "sphere", "--kappa", "0.02", "--tau", "nan", "--m", "2:4"]),
    ("count-text", ["modes", "sphere", "--m", "2", "--zeta", "0.1", "--count", "one"]),
    ("precision-text", ["modes", "sphere", "--m", "2", "--zeta", "0.1", "--precision", "lots"]),
    ("lp-m-text", ["lp", "--m", "x"]),
    ("workers-text", ["tongues", "mathieu", "--kappa", "0:1:5", "--workers", "two"]),
    ("validate-workers-text", ["validate", "--quick", "--out", "{tmp}/v", "--workers", "two"]),
    # missing options or arguments
    ("no-command", []),
    ("no-model", ["floquet"]),
    ("kappa-missing", ["floquet", "mathieu"]),
    ("sphere-m-missing", ["floquet", "sphere", "--kappa", "0.02"]),
    ("tongues-kappa-missing", ["tongues", "mathieu", "--nu", "0.1"]),
    ("exponents-tau-missing", ["exponents", "mathieu", "--kappa", "1"]),
    ("stability-m-missing", ["stability", "sphere", "--kappa", "0.02", "--tau", "0.4"]),
    ("lp-m-missing", ["lp"]),
    ("sweep-out-missing", ["sweep", "{tmp}/scene.toml"]),
    ("plot-png-missing", ["plot", "{tmp}/x.zarr"]),
    ("option-without-value", ["floquet", "mathieu", "--kappa"]),
    # unknown commands, models, options and choices
    ("unknown-command", ["frobnicate"]),
    ("unknown-model", ["floquet", "banana", "--kappa", "1"]),
    ("unknown-option", ["floquet", "mathieu", "--kappa", "1", "--bogus", "3"]),
    ("foreign-parameter", ["floquet", "mathieu", "--kappa", "1", "--m", "3"]),
    ("unknown-kind", ["floquet", "mathieu", "--kappa", "1", "--kind", "sideways"]),
    ("unknown-volume", ["lp", "--m", "2", "--volume", "huge"]),
    ("unknown-figure", ["figure", "fig-99.9", "--out", "{tmp}/f"]),
    ("unknown-component", ["floquet", "sphere", *SPHERE, "--component", "spiral"]),
    ("tol-and-n-temporal", ["floquet", "mathieu", "--kappa", "1", "--tol", "1e-8", "--n-temporal", "9"]),
    # out-of-range values
    ("kappa-negative", ["floquet", "mathieu", "--kappa", "-1"]),
    ("nu-negative", ["floquet", "sphere", "--m", "3", "--kappa", "0.02", "--nu", "-0.1"]),
    ("m-rigid", ["floquet", "sphere", "--m", "1", "--kappa", "0.02"]),
    ("m-too-large", ["floquet", "fibre", "--m", "100000", "--kappa", "0.02"]),
    ("tol-negative", ["floquet", "mathieu", "--kappa", "1", "--tol", "-1e-8"]),
    ("n-temporal-zero", ["floquet", "mathieu", "--kappa", "1", "--n-temporal", "0"]),
    ("n-temporal-huge", ["floquet", "mathieu", "--kappa", "1", "--n-temporal", "100000"]),
    ("exponents-count-zero", ["exponents", "sphere", *SPHERE, "--tau", "0.3", "--count", "0"]),
    ("zeta-out-of-domain", ["modes", "sphere", "--m", "2", "--zeta", "1e-20"]),
    ("count-zero", ["modes", "sphere", "--m", "2", "--zeta", "0.1", "--count", "0"]),
    ("lp-m-too-large", ["lp", "--m", "9"]),
    ("lp-not-normal-mode", ["lp", "--m", "3", "--k", "1"]),
    ("lp-k-too-large", ["lp", "--m", "2", "--k", "5"]),
    ("validate-workers-zero", ["validate", "--quick", "--out", "{tmp}/v", "--workers", "0"]),
    # empty or reversed ranges
    ("kappa-range-reversed", ["tongues", "mathieu", "--nu", "0.1", "--kappa", "1:0:10"]),
    ("kappa-range-empty", ["tongues", "mathieu", "--nu", "0.1", "--kappa", "0:1:0"]),
    ("kappa-range-blank", ["tongues", "mathieu", "--nu", "0.1", "--kappa", ""]),
    ("kappa-range-malformed", ["tongues", "mathieu", "--nu", "0.1", "--kappa", "0:1"]),
    ("m-range-reversed", ["stability", "sphere", "--kappa", "0.02", "--tau", "0.4", "--m", "6:2"]),
    ("m-range-blank", ["stability", "sphere", "--kappa", "0.02", "--tau", "0.4", "--m", ""]),
    # unwritable or wrong output paths
    ("png-no-directory", ["tongues", "mathieu", "--nu", "0.1", "--kappa", "0:1:5", "--png",
                          "{tmp}/no/such/dir/x.png"]),
    ("csv-under-a-file", ["tongues", "mathieu", "--nu", "0.1", "--kappa", "0:1:5", "--csv",
                          "{tmp}/a_file/x.csv"]),
    ("figure-out-is-a-file", ["figure", "fig-2.2", "--out", "{tmp}/a_file"]),
    ("figure-out-under-a-file", ["figure", "fig-2.2", "--out", "{tmp}/a_file/sub"]),
    ("validate-out-is-a-file", ["validate", "--quick", "--out", "{tmp}/a_file"]),
    ("demo-out-is-a-file", ["demo", "--out", "{tmp}/a_file"]),
    ("run-out-is-a-file", ["run", "{tmp}/scene.toml", "--out", "{tmp}/a_file"]),
    ("sweep-out-suffix", ["sweep", "{tmp}/grid.toml", "--out", "{tmp}/map.txt"]),
    ("sweep-out-no-directory", ["sweep", "{tmp}/grid.toml", "--out", "{tmp}/no/dir/map.zarr"]),
    ("sweep-out-is-a-file", ["sweep", "{tmp}/grid.toml", "--out", "{tmp}/file.zarr"]),
    ("plot-missing-store", ["plot", "{tmp}/missing.zarr", "--png", "{tmp}/x.png"]),
    ("plot-png-no-directory", ["plot", "{tmp}/missing.zarr", "--png", "{tmp}/no/dir/x.png"]),
    ("run-missing-scene", ["run", "{tmp}/missing.toml"]),
]

# (id, TOML text) of scenes with wrong types or values; each run with `spectralshell run`
BAD_SCENES = [
    ("not-toml", 'model = "mathieu"\nask = [floquet\n'),
    ("model-number", "model = 3\n"),
    ("model-unknown", 'model = "banana"\n[params]\nkappa = 1.0\n'),
    ("model-missing", "[params]\nkappa = 1.0\n"),
    ("kappa-string", 'model = "mathieu"\n[params]\nkappa = "abc"\n'),
    ("kappa-list", 'model = "mathieu"\n[params]\nkappa = [1, 2]\n'),
    ("kappa-bool", 'model = "mathieu"\n[params]\nkappa = true\n'),
    ("nu-table", 'model = "mathieu"\n[params]\nkappa = 1.0\nnu = {x = 1}\n'),
    ("m-float", 'model = "sphere"\n[params]\nm = 2.5\nkappa = 0.02\n'),
    ("m-string", 'model = "sphere"\n[params]\nm = "three"\nkappa = 0.02\n'),
    ("params-not-table", 'model = "mathieu"\nparams = 3\n'),
    ("unknown-param", 'model = "mathieu"\n[params]\nkappa = 1.0\ngravity = 9.8\n'),
    ("unknown-key", 'model = "mathieu"\ncolour = "red"\n[params]\nkappa = 1.0\n'),
    ("ask-number", 'model = "mathieu"\nask = 3\n[params]\nkappa = 1.0\n'),
    ("ask-unknown", 'model = "mathieu"\nask = ["dance"]\n[params]\nkappa = 1.0\n'),
    ("ask-empty", 'model = "mathieu"\nask = []\n[params]\nkappa = 1.0\n'),
    ("tol-string", 'model = "mathieu"\n[params]\nkappa = 1.0\n[floquet]\ntol = "small"\n'),
    ("n-temporal-float", 'model = "mathieu"\n[params]\nkappa = 1.0\n[floquet]\nn_temporal = 2.5\n'),
    ("kind-number", 'model = "mathieu"\n[params]\nkappa = 1.0\n[floquet]\nkind = 2\n'),
    ("floquet-not-table", 'model = "mathieu"\nfloquet = 1\n[params]\nkappa = 1.0\n'),
    ("tongues-kappa-string", 'model = "mathieu"\nask = ["tongues"]\n[params]\nnu = 0.1\n[tongues]\n'
                             'kappa = "lots"\n'),
    ("tongues-kappa-table-types", 'model = "mathieu"\nask = ["tongues"]\n[params]\nnu = 0.1\n'
                                  '[tongues]\nkappa = {start = "a", stop = 1, num = 3}\n'),
    ("tongues-tips-string", 'model = "mathieu"\nask = ["tongues"]\n[params]\nnu = 0.1\n[tongues]\n'
                            'kappa = "0:1:3"\ntips = "yes"\n'),
    ("exponents-tau-missing", 'model = "mathieu"\nask = ["exponents"]\n[params]\nkappa = 1.0\n'),
    ("exponents-tau-bool", 'model = "mathieu"\nask = ["exponents"]\n[params]\nkappa = 1.0\n'
                           '[exponents]\ntau = true\n'),
    ("output-dir-number", 'model = "mathieu"\n[params]\nkappa = 1.0\n[output]\ndir = 5\n'),
    ("grid-values-string", 'model = "mathieu"\nask = ["tau_min"]\n[params]\nnu = 0.1\n[grid]\n'
                           'kappa = "many"\n'),
    ("grid-num-float", 'model = "mathieu"\nask = ["tau_min"]\n[params]\nnu = 0.1\n[grid]\n'
                       'kappa = {start = 0.1, stop = 1, num = 2.5}\n'),
    ("grid-empty-list", 'model = "mathieu"\nask = ["tau_min"]\n[params]\nnu = 0.1\n[grid]\nkappa = []\n'),
    ("grid-m-float", 'model = "sphere"\nask = ["tau_min"]\n[params]\nkappa = 0.02\n[grid]\nm = [2.5]\n'),
    ("grid-tau-max-string", 'model = "mathieu"\nask = ["tau_min"]\n[params]\nnu = 0.1\n[grid]\n'
                            'kappa = [0.2, 0.3]\n[tau_min]\ntau_max = "half"\n'),
]

GOOD_SCENE = 'model = "mathieu"\n[params]\nkappa = 0.25\nnu = 0.1\n'
GRID_SCENE = ('model = "mathieu"\nask = ["tau_min"]\n[params]\nnu = 0.1\n[grid]\n'
              'kappa = {start = 0.2, stop = 0.3, num = 3}\n')


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """A directory with a valid scene, a grid scene, a plain file and a file named like a store;
    the current directory is moved there so that default output paths also land in it."""
    (tmp_path / "scene.toml").write_text(GOOD_SCENE)
    (tmp_path / "grid.toml").write_text(GRID_SCENE)
    (tmp_path / "a_file").write_text("not a directory")
    (tmp_path / "file.zarr").write_text("not a store")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _listing(root: Path) -> dict[str, int]:
    return {str(p.relative_to(root)): p.stat().st_size for p in root.rglob("*")}


def _assert_one_line_exit_2(argv, capsys, root: Path) -> str:
    before = _listing(root)
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2, (argv, code, out, err)
    assert err.endswith("\n") and err.count("\n") == 1, err
    assert err.startswith("spectralshell: error: ") and "Traceback" not in err
    assert out == ""
    assert _listing(root) == before, "a file was left behind"
    return err


@pytest.mark.parametrize("argv", [a for _, a in BAD_ARGV], ids=[i for i, _ in BAD_ARGV])
def test_bad_command_line(argv, capsys, workdir):
    _assert_one_line_exit_2([a.replace("{tmp}", str(workdir)) for a in argv], capsys, workdir)


@pytest.mark.parametrize("text", [t for _, t in BAD_SCENES], ids=[i for i, _ in BAD_SCENES])
def test_bad_scene(text, capsys, workdir):
    path = workdir / "bad.toml"
    path.write_text(text)
    err = _assert_one_line_exit_2(["run", str(path), "--out", str(workdir / "out")], capsys, workdir)
    assert "scene" in err or "=" in err or "is" in err  # names what is wrong
    if "[grid]" in text:  # the sweep command reads the same scenes
        _assert_one_line_exit_2(["sweep", str(path), "--out", str(workdir / "m.zarr")], capsys, workdir)


def test_messages_name_parameter_and_range(capsys, workdir):
    _assert_one_line_exit_2(["floquet", "mathieu", "--kappa", "-1", "--nu", "0"], capsys, workdir)
    main(["floquet", "mathieu", "--kappa", "-1", "--nu", "0"])
    err = capsys.readouterr().err
    assert "kappa = -1" in err and "must be" in err


@pytest.mark.parametrize("text, shown", [("1", "1"), ("2.5", "2.5"), ("two", "'two'")])
def test_integer_messages_repeat_what_was_typed(text, shown, capsys, workdir):
    """An integer parameter's message shows the typed value (not 1.0) and the integer range."""
    err = _assert_one_line_exit_2(["floquet", "sphere", "--m", text, "--kappa", "0.02", "--nu", "0"], capsys,
                                  workdir)
    assert err.startswith(f"spectralshell: error: m = {shown} is invalid: must be an integer in [2, 200]")


# ----------------------------------------------------------------- interrupted sweep (SIGINT)

LONG_SCENE = ('model = "sphere"\nask = ["tau_min"]\n[params]\nnu = 0.002\n[grid]\n'
              'm = [2, 3, 4, 5]\nkappa = {start = 0.01, stop = 0.2, num = 60}\n'
              '[tau_min]\ntau_max = 0.5\ncontinuation = false\n[sweep]\nchunk = 5\n')


def _chunks_on_disk(store: Path) -> int:
    """Finished chunks: the 'computed' flags are written last, one Zarr chunk file per chunk."""
    flags = store / "computed"
    return sum(1 for p in flags.iterdir() if not p.name.startswith(".")) if flags.is_dir() else 0


@pytest.mark.parametrize("executor", ["serial", "processes"])
def test_sigint_keeps_complete_finished_chunks(tmp_path, executor):
    """Ctrl-C (SIGINT to the process group) during `spectralshell sweep`: exit 130 with one line,
    the store opens, every point flagged computed equals an independent ss.floquet solve, and no
    partial file remains."""
    scene = tmp_path / "long.toml"
    scene.write_text(LONG_SCENE)
    store = tmp_path / "long.zarr"
    argv = [sys.executable, "-m", "spectralshell", "sweep", str(scene), "--out", str(store),
            "--executor", executor] + (["--workers", "2"] if executor == "processes" else [])
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "OMP_NUM_THREADS": "1"}, start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        while _chunks_on_disk(store) < 2 and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.05)
        assert proc.poll() is None, "the sweep finished before it could be interrupted"
        os.killpg(proc.pid, signal.SIGINT)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    assert proc.returncode == 130, (proc.returncode, err)
    assert "Traceback" not in err and "\n" not in err.strip(), err
    assert not [p for p in tmp_path.rglob("*") if p.name.startswith(".partial-")]
    ds = open_sweep(store)
    done = ds["computed"].values
    assert 0 < done.sum() < done.size
    assert err.strip() == (f"spectralshell: interrupted: {int(done.sum())} of {done.size} points are "
                           f"stored in {store}; resume with: {shlex.join(['spectralshell', *argv[3:]])}")
    assert np.isnan(ds["tau_min"].values[~ds["has_tau"].values]).all()
    for idx in zip(*np.nonzero(done)):
        point = ds.isel({dim: int(i) for dim, i in zip(ds["computed"].dims, idx)})
        kind = str(point["kind"].values)
        ref = getattr(ss.floquet("sphere", kind=kind, m=int(point["m"]), kappa=float(point["kappa"]),
                                 nu=0.002, tau_max=0.5), kind)
        assert bool(point["has_tau"]) == (ref.tau_min is not None)
        if ref.tau_min is not None:
            assert abs(float(point["tau_min"]) - ref.tau_min) <= 1e-10
