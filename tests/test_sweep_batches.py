"""Chunks batched into tasks: sizes from the measured cost, same numbers, finished chunks kept."""

import importlib

import numpy as np
import pytest

from spectralshell.errors import ConvergenceError
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.runner import open_sweep, run_sweep, solve
from spectralshell.runner.engine import PartialFailure, run_tasks
from spectralshell.runner.executors import SerialExecutor
from spectralshell.runner.layout import chunks

CHUNK = 2
SCENE = {"model": "mathieu", "ask": ["tau_min"],
         "grid": {"nu": [0.0, 0.1], "kappa": {"start": 0.05, "stop": 1.5, "num": 24}},
         "tau_min": {"tau_max": 2.0}, "sweep": {"chunk": CHUNK}}
N_CHUNKS = 24  # 2 lines of 24 points in chunks of 2
sweep = importlib.import_module("spectralshell.runner.sweep")  # the package exports a function sweep


def sizes(cost, n=40, slots=2):
    return [len(b) for b in sweep.batches(list(range(n)), lambda: cost, slots)]


def test_batches_cover_the_chunks_in_order():
    costs = iter([None, None, 0.5, 0.5, 0.01, 10.0] + [0.25] * 40)
    got = [c for b in sweep.batches(list(range(40)), lambda: next(costs), 2) for c in b]
    assert got == list(range(40))


def test_batch_size_fills_task_seconds_and_keeps_the_tail_short():
    assert sizes(None) == [1] * 40  # nothing measured yet: one chunk per task
    assert sizes(sweep.TASK_SECONDS + 1) == [1] * 40  # dear chunks: one per task
    # cheap chunks: ceil(TASK_SECONDS / cost) per task, at most remaining / (2 per slot x slots)
    cheap = sizes(sweep.TASK_SECONDS / 3, n=400, slots=2)
    assert cheap[:3] == [3, 3, 3] and sum(cheap) == 400
    tiny = sizes(1e-6, n=40, slots=2)
    assert tiny[0] == 40 // 4 and tiny[-4:] == [1, 1, 1, 1] and sum(tiny) == 40
    left = 40
    for size in tiny:  # every task leaves at least 4 tasks' worth for the 2 slots, or is single
        assert size == 1 or size <= left // 4
        left -= size


def test_partial_failure_delivers_its_finished_part_then_raises():
    seen = []

    def task(x):
        if x == 2:
            raise PartialFailure(["a", "b"], ValueError("chunk c failed"))
        return [x]

    with pytest.raises(ValueError, match="chunk c failed"):
        run_tasks(SerialExecutor(), task, [(1,), (2,), (3,)], in_flight=1,
                  on_result=lambda t, r: seen.append(r))
    assert seen == [[1], ["a", "b"]]  # nothing submitted after the failure


def _fail_at_chunk(monkeypatch, index):
    spec = sweep_spec(SCENE)
    kappa_bad = spec.axis("kappa").values[index * CHUNK + 1]  # second point of chunk ``index``
    real = solve.solve_kind

    def patched(system, kind, options, *hints):
        if abs(system.forcing[0, 0] - kappa_bad) < 1e-12:
            raise ConvergenceError("tau_min did not converge (test)")
        return real(system, kind, options, *hints)

    monkeypatch.setattr(solve, "solve_kind", patched)
    return kappa_bad


def test_a_failing_chunk_keeps_the_chunks_its_batch_finished_before_it(monkeypatch, tmp_path):
    # serial: task 1 is chunk 0 alone (no cost known yet), task 2 chunks 1..11 (TASK_SECONDS
    # huge, so the tail cap 23 // 2 decides); chunk 7 fails inside it
    monkeypatch.setattr(sweep, "TASK_SECONDS", 1e9)
    kappa_bad = _fail_at_chunk(monkeypatch, 7)
    out = tmp_path / "map.zarr"
    with pytest.raises(ConvergenceError, match=f"kappa = {kappa_bad!r}"):
        run_sweep(SCENE, executor="serial", out=out)
    computed = open_sweep(out)["computed"].values.all(axis=-1)  # (nu, kappa)
    assert computed[0, :7 * CHUNK].all() and not computed[0, 7 * CHUNK:].any()
    assert not computed[1].any()


def test_batched_processes_equal_serial(monkeypatch):
    serial = run_sweep(SCENE, executor="serial").dataset
    made = []
    real = sweep.batches

    def recorded(*args):
        for batch in real(*args):
            made.append(len(batch))
            yield batch

    monkeypatch.setattr(sweep, "batches", recorded)
    monkeypatch.setattr(sweep, "TASK_SECONDS", 1e9)
    run = run_sweep(SCENE, executor="processes", workers=2)
    assert max(made) > 1 and sum(made) == N_CHUNKS == len(chunks(sweep_spec(SCENE)))
    assert run.chunks == N_CHUNKS
    for name in serial.data_vars:
        np.testing.assert_array_equal(run.dataset[name].values, serial[name].values, err_msg=name)
