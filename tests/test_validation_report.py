"""`spectralshell validate`: the quick report in the fast suite, the full report (every case, every
reproduced figure) in the slow one, and the runner's pass/fail logic on deliberately wrong cases.

The full report is written to $SPECTRALSHELL_REPORT_DIR when set (``make test-all`` sets it to
``validation-report``), else to a temporary directory.
"""

from __future__ import annotations

import base64
import json
import re
import os
from pathlib import Path

import pytest
import scipy

from spectralshell.cli import main
from spectralshell.reports import validation
from spectralshell.reports.figures import FIGURES
from spectralshell.reports.thesis_errata import FINDINGS, KINDS

HEADER = "| case | quantity | source | expected | computed | error | tolerance | result |"


def _check_report(out: Path, cases: list) -> dict:
    text = (out / "report.md").read_text()
    data = json.loads((out / "report.json").read_text())
    assert HEADER in text and f"**{len(cases)} of {len(cases)} cases pass**" in text
    assert [c["name"] for c in data["cases"]] == [c.name for c in cases]
    assert all(c["passed"] for c in data["cases"]) and data["passed"]
    assert data["libraries"]["scipy"] == scipy.__version__ and f"scipy {scipy.__version__}" in text
    for case in cases:
        assert f"`{case.name}`" in text
    assert "## Where the thesis is wrong" in text and "### Confirmed misprints" in text
    assert "### Thesis claims that do not hold at converged truncation" in text
    assert text.count("\n- **") == len(FINDINGS)  # every finding, each with its evidence
    assert text.count("  - Evidence: ") == len(FINDINGS)
    assert (out / "errors.png").stat().st_size > 10_000
    _check_html(out, text)
    return data


def _check_html(out: Path, text: str) -> None:
    """report.html is report.md as one page with every figure embedded: as many images as the
    Markdown shows, each the bytes of its PNG, no reference to another file."""
    page = (out / "report.html").read_text()
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    shown = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    embedded = re.findall(r'<img src="data:image/png;base64,([^"]+)"', page)
    assert shown and len(embedded) == len(shown) == page.count("<img ")
    for path, data in zip(shown, embedded):
        assert base64.b64decode(data) == (out / path).read_bytes(), path
    assert not re.search(r'(src|href)="(?!data:|#|https?:)', page)
    assert page.count("<tr>") == text.count("\n| ")  # every table row, headers included


def test_quick_report(tmp_path, capsys):
    out = tmp_path / "report"
    assert main(["validate", "--quick", "--out", str(out)]) == 0
    stdout, stderr = capsys.readouterr()
    quick = validation.all_cases(quick=True)
    assert stdout.startswith(f"validation (quick): {len(quick)} of {len(quick)} cases pass")
    assert stderr.count("\npass  ") + stderr.startswith("pass  ") == len(quick)
    data = _check_report(out, quick)
    assert data["quick"] and not data["figures"]
    text = (out / "report.md").read_text()
    # a live recomputation: the Table 7.3 nonlinear column with the printed and the exact c_2
    assert "with the printed c_2 = -0.7167: 44.15 1/s" in text and "-0.2112: 45.07 1/s" in text


def test_registry_is_consistent():
    cases = validation.all_cases()
    names = {c.name for c in cases}
    assert len(names) == len(cases)
    assert {c.name for c in validation.all_cases(quick=True)} <= names
    for f in FINDINGS:
        assert f.kind in KINDS and f.where and f.thesis and f.holds and f.evidence
        assert set(f.cases) <= names, f"finding {f.where!r} names unknown cases {set(f.cases) - names}"
    for c in cases:
        assert c.tolerance >= 0 and c.quantity and c.source
    for kind in validation.SOURCE_KINDS:  # every kind of evidence is represented
        assert any(c.source_kind == kind for c in cases), kind


def _wrong(name: str, compute) -> validation.Case:
    return validation.Case(name=name, section="runner", quantity="q", source="a closed form",
                           source_kind="closed form", expected=2.0, compute=compute, tolerance=1e-12)


def test_failing_cases_fail_the_report_and_the_exit_status(tmp_path, capsys, monkeypatch):
    """A wrong value and a raising case both fail, with their message, and validate exits 1."""
    def boom(ctx):
        raise RuntimeError("no convergence here")

    cases = [_wrong("wrong.value", lambda ctx: 2.5), _wrong("raises", boom),
             _wrong("right.value", lambda ctx: validation.Measured(2.0, "exact"))]
    monkeypatch.setattr(validation, "all_cases", lambda quick=False: cases)
    assert main(["validate", "--quick", "--out", str(tmp_path)]) == 1
    assert capsys.readouterr().out.startswith("validation (quick): 1 of 3 cases pass")
    text = (tmp_path / "report.md").read_text()
    assert "**1 of 3 cases pass**, **2 fail**." in text
    assert "- `raises`: RuntimeError: no convergence here" in text
    assert "| 2.5 | 5.0e-01 | 1e-12 | **FAIL** |" in text
    assert "| 2 (exact) | 0.0e+00 | 1e-12 | pass |" in text
    assert "<td><strong>FAIL</strong></td>" in (tmp_path / "report.html").read_text()
    assert main(["validate", "--quick", "--quiet", "--out", str(tmp_path)]) == 1
    assert [line.split()[:2] for line in capsys.readouterr().err.splitlines()] == [
        ["FAIL", "wrong.value"], ["FAIL", "raises"]]  # --quiet: the failures only


def test_the_stepper_agrees_with_floquet_in_the_quick_set():
    """The quick set holds the time-stepper cross-check: at, below and above tau_min."""
    quick = {c.name for c in validation.all_cases(quick=True)}
    assert {f"stepper.m2.k0.06.nu0.002.quick.{s}" for s in ("at_tau_min", "below", "above")} <= quick
    full = {c.name for c in validation.all_cases()} - quick
    assert {c for c in full if c.startswith("stepper.")}  # longer runs, a second degree


@pytest.mark.slow
def test_full_report(tmp_path, capsys):
    """Every case passes and every figure of the registry is reproduced and checked by a case."""
    out = Path(os.environ.get("SPECTRALSHELL_REPORT_DIR") or tmp_path / "report")
    assert main(["validate", "--out", str(out)]) == 0
    data = _check_report(out, validation.all_cases())
    assert set(data["figures"]) == set(FIGURES) and not data["figure_errors"]
    unchecked = [name for name, checks in data["figures"].items() if not checks]
    assert not unchecked, f"figures without a validation case: {unchecked}"
    for name in FIGURES:
        assert (out / "figures" / f"{name}.png").stat().st_size > 10_000
