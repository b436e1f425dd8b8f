"""Smoke checks of the benchmark scripts in validation/ (the full runs are `make bench`)."""

from __future__ import annotations

import importlib
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
