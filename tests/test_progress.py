"""Progress of long work: a bar with ETA on a terminal, a line every few seconds on a piped
stderr, nothing with --quiet (anywhere on the command line) or --json."""

import io
import re
import sys

import pytest

from spectralshell import cli
from spectralshell.runner import progress, run_sweep

SCENE = ('model = "mathieu"\nask = ["tau_min"]\n[params]\nnu = 0.1\n[grid]\n'
         'kappa = {start = 0.1, stop = 1.2, num = 12}\n[tau_min]\ntau_max = 2.0\n'
         '[sweep]\nchunk = 3\n')
LINE = re.compile(r"sweep \[serial\]: (\d+)/24 pt \((\d+)%\), [0-9.e+]+ pt/s, \d+s elapsed(, ETA \S+)?")


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(SCENE)
    return path


def test_a_line_says_done_total_share_rate_elapsed_and_eta():
    """120 of 960 points in 35 s: 3.43 pt/s, the other 840 in 245 s."""
    with progress.LineProgress(960, "sweep", "pt") as bar:
        bar.update(120)
        assert bar.line(35.0) == "sweep: 120/960 pt (12%), 3.43 pt/s, 35s elapsed, ETA 4m05s"
        bar.update(840)
        assert bar.line(7300.0).endswith("2h01m elapsed, ETA 0s")


def test_a_piped_sweep_writes_progress_lines(scene, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(progress, "PIPE_SECONDS", 0.0)  # a line at every chunk
    assert cli.main(["sweep", str(scene), "--out", str(tmp_path / "m.zarr"),
                     "--executor", "serial"]) == 0
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 4 and all(LINE.fullmatch(line) for line in lines), lines
    done = [int(LINE.fullmatch(line).group(1)) for line in lines]
    assert done == [6, 12, 18, 24] and lines[-1].startswith("sweep [serial]: 24/24 pt (100%)")
    assert captured.out.startswith("sweep: 24 points (24 computed")


@pytest.mark.parametrize("where", ["before", "after"])
def test_quiet_silences_progress_wherever_it_is_given(where, scene, tmp_path, monkeypatch,
                                                      capsys):
    monkeypatch.setattr(progress, "PIPE_SECONDS", 0.0)
    argv = ["sweep", str(scene), "--out", str(tmp_path / "m.zarr"), "--executor", "serial"]
    argv = ["--quiet", *argv] if where == "before" else [*argv, "-q"]
    assert cli.main(argv) == 0
    captured = capsys.readouterr()
    assert captured.err == "" and "24 computed" in captured.out


def test_json_output_has_no_progress(scene, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(progress, "PIPE_SECONDS", 0.0)
    assert cli.main(["sweep", str(scene), "--out", str(tmp_path / "m.zarr"),
                     "--executor", "serial", "--json"]) == 0
    assert capsys.readouterr().err == ""


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_terminal_gets_a_bar_with_eta(scene, monkeypatch):
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    run_sweep(str(scene), executor="serial", progress=True)
    text = terminal.getvalue()
    assert "sweep [serial]: 100%" in text and "24/24" in text and "pt/s" in text
    assert re.search(r"\[\d\d:\d\d<\d\d:\d\d", text)  # elapsed<remaining: the ETA


def test_short_piped_work_prints_nothing(scene, capsys):
    """Below PIPE_SECONDS a piped run stays silent (no bar, no line)."""
    run_sweep(str(scene), executor="serial", progress=True)
    assert capsys.readouterr().err == ""


def test_a_figure_says_what_it_computes_and_reports_progress(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(progress, "PIPE_SECONDS", 0.0)
    assert cli.main(["figure", "fig-6.6", "--out", str(tmp_path), "--workers", "1"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("fig-6.6: computing ")
    assert any(re.fullmatch(r"fig-6\.6 case \S+: 7/7 m \(100%\), .*", line) for line in err), err
    assert cli.main(["figure", "fig-6.6", "--out", str(tmp_path), "--workers", "1",
                     "--quiet"]) == 0
    assert capsys.readouterr().err == ""


def test_a_piped_spatial_refinement_reports_the_m_it_solves(monkeypatch, capsys):
    """floquet cochlea refines M with a bar; piped, its lines name the M being solved."""
    monkeypatch.setattr(progress, "PIPE_SECONDS", 0.0)
    assert cli.main(["floquet", "cochlea", "--omega", "1000", "--kind", "subharmonic",
                     "--n-temporal", "6", "--tau-max", "0.5"]) == 0
    lines = [x for x in capsys.readouterr().err.splitlines() if x.startswith("cochlea")]
    shape = re.compile(r"cochlea .*: \d+/\d+ M \(\d+%\), .* elapsed.*\(M = \d+\)")
    assert lines and all(shape.fullmatch(x) for x in lines), lines


def test_piped_work_busy_on_one_item_still_writes_lines(monkeypatch, capsys):
    """A long item (one large truncation) is not silent: the clock writes a line every
    PIPE_SECONDS without any update, and nothing after close."""
    import time

    monkeypatch.setattr(progress, "PIPE_SECONDS", 0.05)
    with progress.LineProgress(3, "cochlea", "M") as bar:
        bar.set_postfix_str("M = 64")
        time.sleep(0.3)
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) >= 2, lines
    assert all(line.startswith("cochlea: 0/3 M (0%)") and line.endswith("(M = 64)")
               for line in lines), lines
    time.sleep(0.15)
    assert capsys.readouterr().err == ""
