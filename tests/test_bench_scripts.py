"""Smoke checks of the benchmark scripts in validation/ (the full runs are `make bench`)."""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

import pytest

VALIDATION = Path(__file__).resolve().parents[1] / "validation"


@pytest.fixture(scope="module")
def work_precision():
    """validation/bench_work_precision.py as a module (it imports _bench and bench_floquet from
    its own directory, as when it runs)."""
    sys.path.insert(0, str(VALIDATION))
    try:
        return importlib.import_module("bench_work_precision")
    finally:
        sys.path.remove(str(VALIDATION))


def test_work_precision_mathieu_point(work_precision, tmp_path):
    """The Mathieu point at two tolerances: the reference agrees with the mpmath Hill
    determinant, the package meets tol, the monodromy error falls with tol and stays within
    10 tol, QZ improves with N; the chart is drawn."""
    wp = work_precision
    point = wp.POINTS[0]
    system = point.system()
    ref = wp.reference(point, system)
    assert ref.mp_check < 1e-18 and ref.change < 1e-18
    tols = (1e-4, 1e-8)
    pkg = wp.package_series(system, ref, tols)
    assert all(p.error <= p.setting for p in pkg)
    mono = wp.monodromy_series(point.monodromy, ref, tols)
    assert mono[1].error < mono[0].error
    assert all(m.error < 10 * m.setting for m in mono)
    dense = wp.dense_series(system, ref, (1, 3))
    assert dense[1].error < dense[0].error < 1e-5
    assert wp.matched(dense, 1e-8) is dense[1]
    path = wp.plot([(point, ref, pkg, dense, mono)], tmp_path / "wp.png")
    assert path.stat().st_size > 0


def test_sweep_bench_writes_chunks_through_the_store():
    """validation/bench_sweep.py times Zarr chunk writes through the store's own API (it once
    passed a region where the store takes a Chunk, and `make bench` failed there): eight chunks
    of a cheap Mathieu scene are written, at a finite positive cost each."""
    sys.path.insert(0, str(VALIDATION))
    try:
        bench = importlib.import_module("bench_sweep")
    finally:
        sys.path.remove(str(VALIDATION))
    seconds = bench.write_per_chunk(16)
    assert 0 < seconds < 5


@pytest.mark.slow
def test_sweep_bench_end_to_end_measures_every_executor(capsys):
    """The end-to-end rows of validation/bench_sweep.py run through (their errors are caught and
    printed as 'not measured', so `make bench` once went on with none of them: the store was
    passed a region again; the serial one now raises): serial and process pools each give an
    overhead (28 s: slow)."""
    sys.path.insert(0, str(VALIDATION))
    try:
        bench = importlib.import_module("bench_sweep")
    finally:
        sys.path.remove(str(VALIDATION))
    out = bench.end_to_end(dask=False)
    assert "not measured" not in capsys.readouterr().out
    assert set(out) == {"serial", "processes"}


@pytest.fixture()
def bench_table():
    """validation/bench_table.py and validation/_bench.py as modules."""
    sys.path.insert(0, str(VALIDATION))
    try:
        return importlib.import_module("bench_table"), importlib.import_module("_bench")
    finally:
        sys.path.remove(str(VALIDATION))


def _records(bench, capsys, monkeypatch, emit, quick=False):
    """The records ``emit()`` prints through the row protocol, as bench_table reads them."""
    argv = ["bench_x.py", bench.FLAG] + [bench.QUICK] * quick
    monkeypatch.setattr(sys, "argv", argv)
    capsys.readouterr()
    emit()
    out = capsys.readouterr().out.splitlines()
    assert all(line.startswith(bench.PREFIX) for line in out)
    return [{**json.loads(line[len(bench.PREFIX):]), "script": "bench_x.py"} for line in out]


def test_table_lists_every_goal_with_its_baseline(bench_table, capsys, monkeypatch):
    """The writer puts each goal first with the row of the run that measures it, that row's
    baseline and time and whether it is met; a goal no row named says 'not measured'; a plain
    row, a growth series and a failed script appear in their sections; '|' in a task is
    escaped so the Markdown table keeps its columns."""
    table, bench = bench_table

    def emit():
        bench.row(task="fibre one truncation | N = 40", package_s=0.002, baseline="dense QZ",
                  baseline_s=0.08, error=1e-14, note="each N and kind", goal="fibre-truncation",
                  met=True)
        bench.row(task="Fig 6.13 map 200 x 200", package_s=75.0, baseline="dense path, projected",
                  baseline_s=600.0, error=2e-15, goal="fig-6.13", met=False)
        bench.row(task="plain row", package_s=1.0, baseline="other", baseline_s=None, error=None)
        bench.growth(label="series", parameter="N", values=[10, 20, 40], seconds=[1, 2, 4])

    records = _records(bench, capsys, monkeypatch, emit)
    status = {"bench_x.py": (0, 12.0, 4, 20.0), "bench_y.py": (1, 3.0, 0, 3.0)}
    text = table.markdown(records, status)
    goals = text[text.index("## Issue 25's goals"):text.index("## All rows")]
    assert all(goal in goals for goal in bench.GOALS.values())
    lines = goals.splitlines()
    line = next(x for x in lines if x.startswith("| " + bench.GOALS["fibre-truncation"]))
    cells = [c.strip() for c in line.strip("|").split(" | ")]
    assert cells[1:6] == ["yes", "0.002", "dense QZ", "0.08", "40"]
    assert "fibre one truncation \\| N = 40 (each N and kind)" in cells[6]
    line = next(x for x in lines if x.startswith("| " + bench.GOALS["fig-6.13"]))
    assert "| **no** | 75 | dense path, projected | 600 | 8 |" in line
    missing = [x for x in lines if "**not measured**" in x]
    assert len(missing) == len(bench.GOALS) - 2
    rows = text[text.index("## All rows"):text.index("## Cost growth")]
    assert "**goal fig-6.13**: Fig 6.13 map 200 x 200" in rows
    assert "| plain row | 1 | other | - |" in rows
    assert "| series | N | 10-40 | 1.00 |" in text
    assert "| `bench_y.py` | **failed (1)** | 0 | 3 | 3 |" in text
    assert "Quick smoke run" not in text


def test_table_marks_a_quick_run(bench_table, capsys, monkeypatch):
    """In a --quick run the goal rows measure nothing and the table says so, above all."""
    table, bench = bench_table
    records = _records(bench, capsys, monkeypatch, lambda: bench.row(
        task="small map", package_s=0.5, baseline="dense", baseline_s=1.0, error=0.0,
        goal="fig-6.13", met=True), quick=True)
    text = table.markdown(records, {"bench_x.py": (0, 1.0, 1, 1.0)}, quick=True)
    assert text.index("Quick smoke run") < text.index("## Issue 25's goals")
    assert "| quick run: measures nothing |" in text and "| yes |" not in text


def test_row_refuses_an_unknown_goal_or_a_goal_without_verdict(bench_table):
    _, bench = bench_table
    with pytest.raises(ValueError, match="goal = 'fig-9.99' is not one of"):
        bench.row(task="t", package_s=1.0, baseline="b", baseline_s=1.0, error=None,
                  goal="fig-9.99", met=True)
    with pytest.raises(ValueError, match="goal and met go together"):
        bench.row(task="t", package_s=1.0, baseline="b", baseline_s=1.0, error=None,
                  goal="fig-6.13")


def test_sweep_bench_map_sample_is_not_refused_by_the_pricing():
    """The Fig 5.18 sample of validation/bench_sweep.py (100 seeded points) is solved with the
    scenes' --max-seconds: the sweep's pricing refuses some of its points at the default
    600 s limit (make bench once failed there), none at the limit the script passes."""
    from spectralshell.params.limits import SECONDS
    from spectralshell.params.sweep_grid import sweep_spec
    from spectralshell.runner.sweep import sweep_cost

    sys.path.insert(0, str(VALIDATION))
    try:
        bench = importlib.import_module("bench_sweep")
    finally:
        sys.path.remove(str(VALIDATION))
    points = bench.sample_points()
    assert len(points) >= bench.GOAL_CELLS
    prices = [sweep_cost(sweep_spec(point), 1)[0] for _, point in points]
    assert max(prices) <= bench.MAP_MAX_SECONDS
    assert max(prices) > SECONDS.value(None)  # what the sweep refuses by default


def test_table_main_runs_scripts_end_to_end(bench_table, tmp_path, monkeypatch):
    """bench_table.main runs each script with --json-rows (and --quick when asked), collects
    its rows and growth series, writes BENCHMARKS.md and the growth plot into --out, and exits
    1 when a script fails (its failure listed, the other's rows kept)."""
    table, _ = bench_table
    good = tmp_path / "bench_good.py"
    good.write_text("import sys\nfrom _bench import growth, quick, row\n"
                    "assert quick() == ('--quick' in sys.argv)\n"
                    "row(task='cochlea point', package_s=0.1, baseline='dense W', baseline_s=1.5,"
                    " error=0.0, goal='cochlea-point', met=True)\n"
                    "growth(label='s', parameter='N', values=[10, 20], seconds=[1.0, 2.0])\n")
    bad = tmp_path / "bench_bad.py"
    bad.write_text("raise SystemExit(3)\n")
    monkeypatch.setattr(table, "scripts", lambda only: [good, bad])
    out = tmp_path / "out"
    assert table.main(["--out", str(out), "--quick"]) == 1
    text = (out / "BENCHMARKS.md").read_text()
    assert (out / "cost_growth.png").stat().st_size > 0
    assert "Quick smoke run" in text
    assert "| quick run: measures nothing | 0.1 | dense W | 1.5 |" in text
    assert "| `bench_good.py` | ok | 2 |" in text
    assert "| `bench_bad.py` | **failed (3)** | 0 |" in text


def test_modal_reduction_with_every_mode_is_the_cosine_system():
    """validation/explore_modal_reduction.py's projection onto the natural modes: with all M of
    them it is a congruence of the cosine-mode system, so the marginal tau are the package's
    (a check of the projected D(s) and G); with fewer, tau_min approaches the package's as m
    grows (kappa = 1, alpha = 1, M = 16, subharmonic: off by 3e-2, 1e-5, 6e-7 at m = 4, 8, 12)."""
    sys.path.insert(0, str(VALIDATION))
    try:
        explore = importlib.import_module("explore_modal_reduction")
    finally:
        sys.path.remove(str(VALIDATION))
    from spectralshell.models.cochlea import hill_system
    from spectralshell.solvers.marginal import marginal_tau

    options = {"n_temporal": 8, "tau_max": 0.5}
    full = hill_system(kappa=0.5, nu=1e-3, alpha=1.0, n_spatial=16)
    for kind in ("harmonic", "subharmonic"):
        cosine = marginal_tau(full, kind, **options).tau_min
        every = explore.reduced_system(full, 1e-3, 16)[0]
        assert marginal_tau(every, kind, **options).tau_min == pytest.approx(cosine, rel=1e-12)
    full = hill_system(kappa=1.0, nu=1e-3, alpha=1.0, n_spatial=16)
    cosine = marginal_tau(full, "subharmonic", **options).tau_min
    errors = [abs(marginal_tau(explore.reduced_system(full, 1e-3, m)[0], "subharmonic",
                               **options).tau_min - cosine) for m in (4, 8, 12)]
    assert errors[0] > 10 * errors[1] > 100 * errors[2] > 0
