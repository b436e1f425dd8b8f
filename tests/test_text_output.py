"""The CLI's text summaries: an error estimate above tol says why, options not used (None) are
not shown, the response's peak position reads in plain units."""

import re

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main

COCHLEA = ["floquet", "cochlea", "--omega", "1000", "--kind", "subharmonic", "--n-temporal", "8"]


def run(capsys, *argv):
    assert main([*argv, "--quiet"]) == 0
    return capsys.readouterr()


def test_a_fixed_n_spatial_says_its_spatial_change_is_the_error(capsys):
    """The note's change is |tau_min(M = 16) - tau_min(M = 8)|, each from its own solve."""
    text = run(capsys, *COCHLEA, "--n-spatial", "16").out
    fine = ss.floquet("cochlea", omega=1000.0, kind="subharmonic", n_temporal=8,
                      n_spatial=16).subharmonic.tau_min
    coarse = ss.floquet("cochlea", omega=1000.0, kind="subharmonic", n_temporal=8,
                        n_spatial=8).subharmonic.tau_min
    note = re.search(r"error above tol = 1e-10: the spatial truncation: tau_min changes by "
                     r"(\S+) between M = 8 and M = 16 spatial modes \(n_spatial is fixed\)", text)
    assert note, text
    assert float(note.group(1)) == pytest.approx(abs(fine - coarse), rel=0.05)
    assert "None" not in text and "n_spatial = 16" in text


def test_a_refined_n_spatial_names_tol_spatial(capsys):
    text = run(capsys, *COCHLEA).out
    assert re.search(r"between M = (\d+) and M = (\d+) spatial modes \(M is refined only until "
                     r"this change is <= tol_spatial = 0\.001\)", text), text
    assert "None" not in text


def test_a_fixed_temporal_truncation_is_named_and_a_converged_one_needs_no_note(capsys):
    fixed = run(capsys, "floquet", "mathieu", "--kappa", "0.25", "--nu", "0.1",
                "--n-temporal", "3").out
    assert "error above tol = 1e-10: N is fixed (n_temporal = 3)" in fixed
    converged = run(capsys, "floquet", "mathieu", "--kappa", "0.25", "--nu", "0.1").out
    assert "error above tol" not in converged


def test_unused_options_are_not_shown(capsys):
    text = run(capsys, "floquet", "cochlea", "--omega", "1000", "--alpha", "0",
               "--spatial-mode", "3", "--tau-max", "0.5").out
    assert "spatial_mode = 3" in text and "None" not in text


def test_the_response_peak_reads_in_plain_units(capsys):
    argv = ["response", "cochlea", "--omega", "1000", "--n-temporal", "8"]
    text = run(capsys, *argv).out
    data = ss.response("cochlea", omega=1000.0, n_temporal=8).to_dict()
    assert "of pi" not in text and "None" not in text
    found = re.search(r"envelope peak at x = (\S+) ± (\S+) \((\S+) % of the way from the base, "
                      r"x = 0, to the apex, x = π\) = (\S+) ± (\S+) cm", text)
    assert found, text
    x, dx, share, cm, dcm = map(float, found.groups())
    assert x == pytest.approx(data["peak_x"], rel=1e-5) and dx == pytest.approx(
        data["peak_error"], rel=0.05)
    assert share == pytest.approx(100 * data["peak_x"] / np.pi, rel=1e-2)
    assert cm == pytest.approx(data["peak_cm"], rel=1e-3)
    assert dcm == pytest.approx(data["peak_error_cm"], rel=0.5)  # one significant digit
