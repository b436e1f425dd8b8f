"""cochlea-tone (issue 29): the pure-tone envelope of the 2D box cochlea and its peak position
against a finer truncation and a finer evaluation of the same physics, score on synthetic
envelopes with known perturbations, bit-identical writing through the CLI, bad input."""

import json
import math

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.models.cochlea import tone_response
from spectralshell.runner.benchmark import score

from benchmark_cases import cli_writes, reference_params, timed_benchmark, user_csv


@pytest.fixture(scope="module")
def reference():
    return timed_benchmark("cochlea-tone")


def test_reference_is_normalised_bounded_and_fast(reference):
    """The envelope has maximum 1 on x in [0, L] cm; its bounds and the peak's are small; the
    peak lies inside the membrane past the load; written in under a minute (measured ~4 s)."""
    p = reference_params(reference)
    x = reference["x"].values
    assert x[0] == 0.0 and x[-1] == pytest.approx(p["length"], rel=1e-15)
    assert np.max(reference["envelope"].values) == 1.0
    assert np.max(reference["envelope_error"].values) < 5e-3
    assert reference.attrs["tone_start_cm"] < reference.attrs["peak_x_cm"] < x[-1]
    assert reference.attrs["peak_error_cm"] < 1e-3
    assert reference.attrs["seconds"] < 60


def _fine_envelope(p, modes, x_cm):
    """|H(x)| of the tone, summed directly from its cosine amplitudes at ``modes`` on x (cm)."""
    h = tone_response(kappa=p["kappa"], nu=p["nu"], alpha=p["alpha"], n_spatial=modes)
    xi = np.asarray(x_cm) * math.pi / p["length"]
    return np.abs(np.cos(np.outer(xi, np.arange(1, modes + 1))) @ h)


def test_peak_is_the_maximum_on_a_finer_grid_and_truncation(reference):
    """The envelope of twice the reference's modes (1024), summed directly on a grid 100 times
    finer than the reference's around the peak, is largest within the stated error bound of
    the reported peak, and its refined maximum is a local maximum there."""
    p = reference_params(reference)
    peak, bound = reference.attrs["peak_x_cm"], reference.attrs["peak_error_cm"]
    dx = p["length"] / 2000 / 100
    x = peak + dx * np.arange(-2000, 2001)
    env = _fine_envelope(p, 2 * p["n_spatial"], x)
    i = int(np.argmax(env))
    assert 0 < i < x.size - 1
    assert abs(x[i] - peak) < bound


def test_reported_envelope_matches_the_finer_truncation(reference):
    """The envelope at 1024 modes, normalised alike, differs from the reference by no more than
    its per-sample bound (plus 1e-12) everywhere past the load."""
    p = reference_params(reference)
    x = reference["x"].values
    fine = _fine_envelope(p, 2 * p["n_spatial"], x)
    fine /= fine.max()
    past = x >= reference.attrs["tone_start_cm"]
    diff = np.abs(fine - reference["envelope"].values)[past]
    assert np.all(diff <= reference["envelope_error"].values[past] + 1e-12)


def _scored(reference, tmp_path, label, x, env):
    res, _, _ = score("cochlea-tone", user_csv(tmp_path / f"{label}.csv", x, {"envelope": env}, "x"),
                      reference=reference)
    return res


def test_score_reports_synthetic_perturbations(reference, tmp_path):
    """The reference itself: zero error, the peak within 1e-4 cm; scaled by 3: scale 3, still
    zero error; shifted by 0.05 cm: the peak moves by 0.05 cm; noise of 1e-4: relative L2 about
    ||noise|| / ||env||; resampled every 4th point: an interpolation error below the reference's
    own bound, the peak within 10 of its bounds."""
    x = reference["x"].values
    env = reference["envelope"].values
    peak = reference.attrs["peak_x_cm"]
    same = _scored(reference, tmp_path, "same", x, env)
    assert same.relative_l2 == 0.0 and same.max_error == 0.0 and same.scale == 1.0
    assert abs(same.peak_x - peak) < 1e-4
    scaled = _scored(reference, tmp_path, "scaled", x, 3.0 * env)
    assert scaled.scale == pytest.approx(3.0, rel=1e-12)
    assert scaled.relative_l2 < 1e-15
    shifted = _scored(reference, tmp_path, "shifted", x + 0.05, env)
    assert shifted.peak_x - same.peak_x == pytest.approx(0.05, abs=1e-9)
    assert shifted.relative_l2 > 1e-2
    rng = np.random.default_rng(29)
    noise = 1e-4 * rng.standard_normal(x.size)
    noisy = _scored(reference, tmp_path, "noisy", x, env + noise)
    assert noisy.relative_l2 == pytest.approx(np.linalg.norm(noise) / np.linalg.norm(env),
                                              rel=0.05)
    coarse = _scored(reference, tmp_path, "coarse", x[::4], env[::4])
    assert coarse.samples == x.size
    assert 0.0 < coarse.max_error < coarse.reference_error
    assert abs(coarse.peak_x - peak) < 10 * reference.attrs["peak_error_cm"]


def test_cli_writes_the_python_bytes_and_scores(reference, tmp_path, capsys):
    """`benchmark write cochlea-tone` writes byte for byte the Python reference; score prints
    the JSON of the peak; list and show name the problem."""
    written = reference.copy()
    del written.attrs["seconds"]    # the fixture's timing, not part of the reference
    out = json.loads(cli_writes("cochlea-tone", written, tmp_path, capsys))
    assert out["samples"] == reference.sizes["x"]
    assert out["peak_x_cm"] == reference.attrs["peak_x_cm"]
    csv = tmp_path / "cli" / "cochlea-tone.csv"
    assert main(["benchmark", "score", "cochlea-tone", str(csv), "--json",
                 "--png", str(tmp_path / "score.png")]) == 0
    scored = json.loads(capsys.readouterr().out)
    assert scored["quantities"]["envelope"]["relative_l2"] == 0.0
    assert (tmp_path / "score.png").stat().st_size > 0
    assert main(["benchmark", "list"]) == 0
    assert "cochlea-tone" in capsys.readouterr().out
    assert main(["benchmark", "show", "cochlea-tone", "--omega", "800"]) == 0
    assert "omega = 800 rad/s" in capsys.readouterr().out


def test_bad_input(tmp_path, capsys):
    """omega outside Table 5.1's range, a negative length, an unknown parameter: ParameterError
    naming it (API) and exit 2 with one line (CLI); a user file with a time column is refused."""
    for bad in ({"omega": 5000.0}, {"length": -1.0}, {"radius": 1.0}):
        with pytest.raises(ParameterError, match=next(iter(bad))):
            ss.benchmark("cochlea-tone", **bad)
    assert main(["benchmark", "write", "cochlea-tone", "--out", str(tmp_path),
                 "--omega", "5000"]) == 2
    err = capsys.readouterr().err.strip()
    assert "omega" in err and len(err.splitlines()) == 1
    path = user_csv(tmp_path / "t.csv", np.arange(5.0), {"envelope": np.ones(5)})
    with pytest.raises(ParameterError, match="header"):
        score("cochlea-tone", path)
