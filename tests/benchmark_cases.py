"""Helpers shared by the benchmark tests (tests/test_benchmark*.py): a reference timed, its
parameters, a user's run written as
score's CSV and scored, the checks of the reference's own score and of two perturbations, and
the check that the CLI writes the bytes of a computation made in Python."""

import json
import time

import numpy as np
import pytest

import spectralshell as ss

from spectralshell.cli import main
from spectralshell.results.benchmark import write_csv, write_netcdf
from spectralshell.runner.benchmark import score


def timed_benchmark(name):
    """The default reference of problem ``name``, with the seconds it took in attrs['seconds']
    (remove it before comparing written bytes)."""
    start = time.perf_counter()
    ds = ss.benchmark(name)
    ds.attrs["seconds"] = time.perf_counter() - start
    return ds


def reference_params(ds):
    """The parameters (JSON attribute) of a reference Dataset."""
    return json.loads(ds.attrs["params"])


def user_csv(path, t, columns, first="t"):
    """``columns`` ({name: values} at times t, or the positions of the first column named
    ``first``) as a user's CSV at ``path`` (with a comment)."""
    names = list(columns)
    rows = np.column_stack([t] + [columns[n] for n in names])
    path.write_text("# my IB run\n" + ",".join([first, *names]) + "\n"
                    + "\n".join(",".join(repr(float(v)) for v in r) for r in rows) + "\n")
    return path


def cli_writes(name, reference, tmp_path, capsys) -> str:
    """`benchmark write NAME --json` into tmp_path/cli, checked to be byte for byte the NetCDF
    and CSV of ``reference`` (the same computation from Python); its JSON output."""
    assert main(["benchmark", "write", name, "--out", str(tmp_path / "cli"), "--json"]) == 0
    out = capsys.readouterr().out
    write_netcdf(reference, tmp_path / "py.nc")
    write_csv(reference, tmp_path / "py.csv")
    for suffix in ("nc", "csv"):
        assert ((tmp_path / "cli" / f"{name}.{suffix}").read_bytes()
                == (tmp_path / f"py.{suffix}").read_bytes())
    return out


def refused_in_one_line(argvs, capsys):
    """Each CLI call of ``argvs`` exits 2 with a one-line error on stderr."""
    for argv in argvs:
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "error" in err


def amplitude_scorer(name, reference, tmp_path):
    """(label, t, values) -> the QuantityScore of a user's run with the one column
    ``amplitude`` scored against ``reference`` of problem ``name``."""
    def run(label, t, values):
        res, _, _ = score(name, user_csv(tmp_path / f"{label}.csv", t, {"amplitude": values}),
                          reference=reference)
        (q,) = res.quantities
        return q
    return run


def check_self_score(q, guess):
    """The reference scored against itself: zero error, and its fitted rate and frequency within
    1e-4 of the exact mode ``guess`` (complex: rate + i frequency)."""
    assert q.relative_l2 == 0.0 and q.max_error == 0.0
    assert q.growth_rate == q.reference_growth_rate
    assert abs(q.reference_growth_rate - guess.real) < 1e-4 * abs(guess.real)
    assert abs(q.reference_frequency - guess.imag) < 1e-4 * guess.imag


def check_rate_and_noise(run, t0, t, a, same, guess, rng):
    """Two perturbations of the reference amplitude ``a`` scored by ``run``
    (:func:`amplitude_scorer`; ``same``: the reference's own score): a decay rate wrong by
    delta = 10 % from t0 (the fitted rate moves by delta, the frequency stays), and noise of
    1e-5 of max |a| (L2 error = ||noise|| / ||a||, the rate within 5 standard errors, a
    larger standard error)."""
    delta = 0.1 * guess.real
    wrong = run("rate", t, a * np.exp(delta * (t - t0)))
    assert wrong.growth_rate - same.growth_rate == pytest.approx(delta, rel=1e-3)
    assert abs(wrong.frequency - same.frequency) < 1e-3 * guess.imag
    noise = 1e-5 * np.max(np.abs(a)) * rng.standard_normal(t.size)
    noisy = run("noise", t, a + noise)
    assert noisy.relative_l2 == pytest.approx(np.linalg.norm(noise) / np.linalg.norm(a),
                                              rel=1e-9)
    assert abs(noisy.growth_rate - same.growth_rate) < 5 * noisy.fit_error
    assert noisy.fit_error > same.fit_error
