"""Parameter sweeps: same numbers on every executor, resumable Zarr stores, continuation, errors."""

import json
import os
import re
import shlex
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import spectralshell as ss
from spectralshell import cli
from spectralshell.errors import (BackendUnavailable, ConvergenceError, ParameterError,
                                  SweepInterrupted)
from spectralshell.params.sweep_grid import DEFAULT_CHUNK, sweep_spec
from spectralshell.runner import SweepError, executors, map_points, open_sweep, run_sweep, solve
from spectralshell.results.maps import map_dict, minimum_map, write_npz
from spectralshell.runner.layout import chunks, region

CHUNK = 6
SCENE = {"model": "mathieu", "ask": ["tau_min"],
         "grid": {"nu": [0.0, 0.1], "kappa": {"start": 0.05, "stop": 1.5, "num": 24}},
         "tau_min": {"tau_max": 2.0}, "sweep": {"chunk": CHUNK}}
POINTS_PER_CHUNK = CHUNK * 2  # two kinds


def assert_same(a, b, atol=1e-14):
    """Equal datasets: integer/bool variables exactly, reals to ``atol``; same coordinates."""
    assert list(a.data_vars) == list(b.data_vars)
    for name in a.coords:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    for name in a.data_vars:
        x, y = a[name].values, b[name].values
        if x.dtype.kind == "f":
            np.testing.assert_allclose(x, y, rtol=0, atol=atol, err_msg=name)
        else:
            assert np.array_equal(x, y), name


@pytest.fixture(scope="module")
def serial():
    return run_sweep(SCENE, executor="serial")


def test_dataset_is_labelled_and_complete_nan_where_no_instability(serial):
    ds = serial.dataset
    assert ds["tau_min"].dims == ("nu", "kappa", "kind")
    assert ds["kappa"].attrs["units"] == "1" and ds["kind"].values.tolist() == ["harmonic", "subharmonic"]
    assert ds.attrs["version"] == ss.__version__ and ds.attrs["scene_hash"] == sweep_spec(SCENE).digest
    assert json.loads(ds.attrs["solver_options"])["tau_max"] == 2.0
    assert json.loads(ds.attrs["libraries"])["numpy"] == np.__version__
    assert bool(ds["computed"].all()) and bool(ds["has_tau"].any()) and not bool(ds["has_tau"].all())
    none = ~ds["has_tau"].values
    assert np.isfinite(ds["tau_min"].values[~none]).all()
    assert np.isnan(ds["tau_min"].values[none]).all()
    assert np.isfinite(ds["error_estimate"].values).all()
    assert (ds["error_estimate"].values[none] == 0).all()
    assert serial.summary() == {"points": 96, "computed": 96, "skipped": 0, "damaged": 0,
                                "outdated": 0, "uncertified": 0, "out": None,
                                "seconds": serial.summary()["seconds"]}


def test_matches_the_floquet_api_pointwise(serial):
    ds = serial.dataset
    for nu, kappa in ((0.1, float(ds.kappa[10])), (0.0, float(ds.kappa[3]))):
        ref = ss.floquet("mathieu", kappa=kappa, nu=nu, tau_max=2.0)
        for kind in ("harmonic", "subharmonic"):
            point = ds.sel(nu=nu, kappa=kappa, kind=kind)
            expected = getattr(ref, kind).tau_min
            assert bool(point.has_tau) == (expected is not None)
            if expected is not None:
                assert abs(float(point.tau_min) - expected) <= 1e-10


def test_processes_equal_serial(serial):
    run = run_sweep(SCENE, executor="processes", workers=2)
    assert_same(run.dataset, serial.dataset)


def test_interrupt_then_resume_equals_fresh_and_rerun_computes_nothing(serial, tmp_path):
    out = tmp_path / "map.zarr"
    stop_after = 3

    def hook(n, result):
        if n == stop_after:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(SCENE, executor="serial", out=out, on_chunk=hook)
    partial = open_sweep(out)  # finished chunks are readable, the rest is flagged
    assert int(partial["computed"].sum()) == stop_after * POINTS_PER_CHUNK
    done = partial["computed"].values
    for name in ("tau_min", "has_tau", "n_temporal"):
        np.testing.assert_array_equal(partial[name].values[done],
                                      serial.dataset[name].values[done], err_msg=name)
    assert np.isnan(partial["tau_min"].values[~done]).all()
    assert not partial["has_tau"].values[~done].any()

    seen = []
    resumed = run_sweep(SCENE, executor="processes", workers=2, out=out,
                        on_chunk=lambda n, r: seen.append(r.index))
    assert len(seen) == len(set(seen)) == len(chunks(sweep_spec(SCENE))) - stop_after
    assert resumed.summary()["computed"] == 96 - stop_after * POINTS_PER_CHUNK
    assert resumed.summary()["skipped"] == stop_after * POINTS_PER_CHUNK
    assert_same(resumed.dataset, serial.dataset)
    assert_same(open_sweep(out), serial.dataset)

    again = run_sweep(SCENE, executor="serial", out=out,
                      on_chunk=lambda n, r: pytest.fail("a finished sweep computed a chunk"))
    assert again.computed == 0 and again.skipped == 96


def test_different_scene_is_refused_and_store_untouched(tmp_path):
    out = tmp_path / "map.zarr"
    small = {**SCENE, "params": {"nu": 0.1}, "grid": {"kappa": {"start": 0.2, "stop": 0.3, "num": 3}}}
    run_sweep(small, executor="serial", out=out)
    before = open_sweep(out)
    other = {**small, "tau_min": {"tau_max": 1.0}}
    with pytest.raises(ParameterError, match="holds a different sweep.*never mixed"):
        run_sweep(other, executor="serial", out=out)
    assert_same(open_sweep(out), before)


def test_netcdf_written_at_the_end_and_reread(serial, tmp_path):
    out = tmp_path / "map.nc"
    run = run_sweep(SCENE, executor="serial", out=out)
    assert run.out == str(out) and out.is_file()
    back = open_sweep(out)
    assert back.attrs["scene_hash"] == serial.dataset.attrs["scene_hash"]
    for name in serial.dataset.data_vars:
        np.testing.assert_array_equal(back[name].values, serial.dataset[name].values, err_msg=name)
    assert run_sweep(SCENE, executor="serial", out=out).computed == 0


def _fail_at(monkeypatch, kappa_bad, action):
    real = solve.solve_kind

    def patched(system, kind, options, *hints):
        if abs(system.forcing[0, 0] - kappa_bad) < 1e-12:
            action()
        return real(system, kind, options, *hints)

    monkeypatch.setattr(solve, "solve_kind", patched)


def test_failing_point_names_point_and_parameters_and_keeps_finished_chunks(monkeypatch, tmp_path):
    spec = sweep_spec(SCENE)
    kappa_bad = spec.axis("kappa").values[2 * CHUNK + 1]  # third chunk of the first line

    def boom():
        raise ConvergenceError("tau_min did not converge (test)")

    _fail_at(monkeypatch, kappa_bad, boom)
    out = tmp_path / "map.zarr"
    with pytest.raises(ConvergenceError) as info:
        run_sweep(SCENE, executor="serial", out=out)
    message = str(info.value)
    assert "\n" not in message and f"kappa = {kappa_bad!r}" in message and "nu = 0.0" in message
    assert "parameters:" in message and "did not converge (test)" in message
    assert int(open_sweep(out)["computed"].sum()) == 2 * POINTS_PER_CHUNK


def test_killed_worker_is_reported_and_finished_chunks_stay_readable(monkeypatch, tmp_path):
    kappa_bad = sweep_spec(SCENE).axis("kappa").values[-1]
    _fail_at(monkeypatch, kappa_bad, lambda: os._exit(3))
    out = tmp_path / "map.zarr"
    with pytest.raises(SweepError, match="worker process died.*rerun"):
        run_sweep(SCENE, executor="processes", workers=2, out=out)
    done = int(open_sweep(out)["computed"].sum())
    assert done % POINTS_PER_CHUNK == 0 and done < 96


def test_continuation_equals_independent_solves():
    scene = {"model": "sphere", "params": {"nu": 1e-3, "m": 3},
             "grid": {"kappa": {"start": 0.2, "stop": 0.26, "num": 5}},
             "tau_min": {"tau_max": 2.0, "tol": 1e-10}}
    independent = run_sweep({**scene, "tau_min": {**scene["tau_min"], "continuation": False}},
                            executor="serial")
    continued = run_sweep(scene, executor="serial")
    assert continued.continued > 0 and independent.continued == 0
    a, b = independent.dataset, continued.dataset
    assert np.array_equal(a.has_tau.values, b.has_tau.values)
    np.testing.assert_allclose(b.tau_min.values, a.tau_min.values, rtol=0, atol=1e-10)
    same_pair = a.n_temporal.values == b.n_temporal.values  # same truncations: bitwise equal
    assert same_pair.any()
    np.testing.assert_array_equal(a.tau_min.values[same_pair], b.tau_min.values[same_pair])


@pytest.mark.parametrize("model,params", [
    ("mathieu", {"kappa": 0.3, "nu": 0.1}), ("mathieu", {"kappa": 6.0, "nu": 0.01}),
    ("sphere", {"m": 2, "kappa": 0.05, "nu": 2.39e-4}), ("sphere", {"m": 3, "kappa": 0.25, "nu": 1e-3}),
])
def test_the_solver_walks_the_schedule_continuation_reads(model, params):
    """Continuation skips along TruncationSchedule: marginal_tau must stop at a pair of it."""
    from spectralshell.models.registry import hill_system
    from spectralshell.params.registry import make_params
    from spectralshell.solvers.marginal import TruncationSchedule, marginal_tau

    system = hill_system(make_params(model, params))
    seq = TruncationSchedule.of(system).sequence()
    for kind in ("harmonic", "subharmonic"):
        m = marginal_tau(system, kind, tol=1e-10, tau_max=2.0)
        i = seq.index(m.n_previous)
        assert seq[i + 1] == m.n_temporal


@pytest.mark.parametrize("change,fragment", [
    ({"grid": {"alpha": [1.0]}}, "grid parameter 'alpha' is unknown for model 'mathieu'"),
    ({"grid": {"m": [2, 3]}}, "grid parameter 'm' is unknown"),
    ({"grid": {"kappa": {"start": 1.0, "stop": 0.5, "num": 5}}}, "stop must be >= start"),
    ({"grid": {"kappa": {"start": 0.1, "stop": 0.5, "num": 0}}}, "grid kappa num = 0 is invalid"),
    ({"grid": {"kappa": []}}, "grid kappa = \\[\\] is invalid"),
    ({"grid": {"kappa": [0.1, 0.1]}}, "appears twice"),
    ({"grid": {"kappa": {"start": 0.0, "stop": 1.0, "num": 4, "spacing": "log"}}}, "must be > 0"),
    ({"grid": {"kappa": {"start": 0.1, "stop": 1.0, "num": 4, "spacing": "cubic"}}}, "spacing"),
    ({"params": {"kappa": 0.3}, "grid": {"kappa": [0.1, 0.2]}}, "kappa is both fixed in \\[params\\]"),
    ({"grid": {"kappa": [0.1], "kind": ["harmonic", "odd"]}}, "grid kind = 'odd' is invalid"),
    ({"params": {"nu": 0.0}, "grid": {"kappa": [-0.1, 0.2]}}, "kappa = -0.1 is invalid"),
    ({"grid": {}}, "at least one swept parameter"),
    ({"tau_min": {"tol": 0}}, "tau_min.tol = 0 is invalid"),
    ({"tau_min": {"kind": "both"}}, "tau_min.kind is unknown"),
    ({"ask": ["exponents"]}, "ask = 'exponents' is invalid"),
    ({"colour": "red"}, "scene key 'colour' is unknown"),
    ({"sweep": {"chunk": 0}}, "sweep.chunk = 0 is invalid"),
])
def test_bad_grids_are_refused_in_one_line(change, fragment):
    with pytest.raises(ParameterError, match=fragment) as info:
        run_sweep({**SCENE, **change}, executor="serial")
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("change,fragment", [
    ({"model": "sphere", "params": {"nu": 0.01, "kappa": 0.1}, "grid": {"m": [1, 2]}}, "m = 1 is invalid"),
    ({"model": "sphere", "params": {"rho": 1.0, "mu": 0.04}, "grid": {"sigma": [1e3], "bpm": [60.0]}},
     "radius is missing"),
    ({"model": "sphere", "params": {"rho": 1.0, "mu": 0.04, "radius": 2.0, "nu": 0.1, "m": 2},
      "grid": {"sigma": [1e3], "bpm": [60.0]}}, "nu is given together with physical"),
    ({"model": "mathieu", "grid": {"sigma": [1.0]}}, "grid parameter 'sigma' is unknown"),
])
def test_bad_sphere_grids_are_refused(change, fragment):
    with pytest.raises(ParameterError, match=fragment):
        sweep_spec({"ask": ["tau_min"], **change})


def test_unwritable_or_wrong_output_is_refused_before_computing(tmp_path):
    with pytest.raises(ParameterError, match="must end in .zarr"):
        run_sweep(SCENE, executor="serial", out=tmp_path / "map.csv")
    with pytest.raises(ParameterError, match="not writable"):
        run_sweep(SCENE, executor="serial", out=tmp_path / "missing" / "map.zarr")
    (tmp_path / "junk.zarr").mkdir()
    with pytest.raises(ParameterError, match="not a readable spectralshell sweep|no spectralshell sweep"):
        run_sweep(SCENE, executor="serial", out=tmp_path / "junk.zarr")


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux /proc")
@pytest.mark.parametrize("name", ["map.zarr", "map.nc"])
def test_a_directory_that_refuses_files_is_caught_before_computing(monkeypatch, name):
    """/proc passes os.access(W_OK) as root but refuses new files: the probe file catches it
    before any point is solved (a NetCDF is otherwise only written at the end)."""
    def never(*args, **kwargs):
        raise AssertionError("a point was solved")

    monkeypatch.setattr(solve, "solve_kind", never)
    with pytest.raises(ParameterError, match="refuses new files|not writable"):
        run_sweep(SCENE, executor="serial", out=Path("/proc") / name)


def test_scene_hash_is_stable_across_forms():
    toml = """
model = "mathieu"
ask = ["tau_min"]
[params]
nu = 1
[grid]
kappa = {start = 0.1, stop = 0.5, num = 5}
[tau_min]
tau_max = 2.0
"""
    as_dict = {"model": "mathieu", "params": {"nu": 1.0}, "tau_min": {"tau_max": 2},
               "grid": {"kappa": "0.1:0.5:5"}}
    assert sweep_spec(toml).digest == sweep_spec(as_dict).digest
    assert sweep_spec({**as_dict, "tau_min": {"tau_max": 2, "tol": 1e-9}}).digest != sweep_spec(as_dict).digest
    spec = sweep_spec(toml)
    assert spec.dims == ("kappa", "kind") and spec.chunk == DEFAULT_CHUNK


def test_log_grid_integer_and_physical_axes():
    spec = sweep_spec({"model": "sphere", "params": {"rho": 1.0, "mu": 0.04, "radius": 2.0},
                       "grid": {"sigma": {"start": 1e3, "stop": 2e4, "num": 3, "spacing": "log"},
                                "bpm": [60.0, 400.0], "m": "2:4", "kind": ["subharmonic"]}})
    assert spec.dims == ("sigma", "bpm", "m", "kind") and spec.axis("m").values == (2, 3, 4)
    assert spec.axis("sigma").values[1] == pytest.approx(np.sqrt(2e7)) and spec.line_axis == 1
    p = spec.params_at({"sigma": 1e3, "bpm": 60.0, "m": 2})
    omega = 2 * np.pi
    assert p["kappa"] == pytest.approx(1e3 / (1.0 * 8.0 * omega**2))
    assert p["nu"] == pytest.approx(0.04 / (4.0 * omega)) and p["m"] == 2


def test_dask_missing_gives_one_line_error_naming_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(BackendUnavailable, match=r"pip install spectralshell\[dask\]") as info:
        run_sweep(SCENE, executor="dask")
    assert "\n" not in str(info.value)


def test_executor_arguments_are_checked():
    with pytest.raises(ParameterError, match="executor = 'threads' is invalid"):
        run_sweep(SCENE, executor="threads")
    with pytest.raises(ParameterError, match="needs executor 'dask'"):
        run_sweep(SCENE, executor="processes", scheduler="local")
    with pytest.raises(ParameterError, match="must be 'local' or an address"):
        run_sweep(SCENE, executor="dask", scheduler="somewhere")


def test_unreachable_scheduler_fails_within_the_timeout(monkeypatch, tmp_path):
    pytest.importorskip("distributed")
    monkeypatch.setattr(executors, "CONNECT_TIMEOUT", 1.0)
    out = tmp_path / "map.zarr"
    t0 = time.perf_counter()
    with pytest.raises(ParameterError, match="unreachable: no Dask scheduler answered within 1 s"):
        run_sweep(SCENE, executor="dask", scheduler="tcp://127.0.0.1:9", out=out)
    assert time.perf_counter() - t0 < 10 and not out.exists()


def test_local_cluster_equals_serial(serial):
    pytest.importorskip("distributed")
    run = run_sweep(SCENE, executor="dask", scheduler="local", workers=2)
    assert "LocalCluster" in run.executor
    assert_same(run.dataset, serial.dataset)


def mathieu_system(nu, kappa):
    from spectralshell.models.mathieu import hill_system

    return hill_system(kappa=kappa, nu=nu)


def test_map_points_gives_the_rows_of_independent_solves():
    from functools import partial

    from spectralshell.solvers.marginal import marginal_tau

    factory = partial(mathieu_system, 0.1)
    grid = np.linspace(0.1, 1.2, 9)
    kinds = ("harmonic", "subharmonic")
    ref = [{k: marginal_tau(factory(kappa), k, tol=1e-10) for k in kinds} for kappa in grid]
    rows = map_points(factory, grid, kinds, executor="processes", workers=2, chunk=4, tol=1e-10)
    for r, s in zip(ref, rows):
        for k in kinds:
            assert np.array_equal(r[k].tau, s[k].tau) and r[k].n_temporal == s[k].n_temporal


def test_plots_of_stored_sweeps(serial, tmp_path):
    from spectralshell.plots import sweep_plot

    two_d = sweep_plot.save(serial.dataset, tmp_path / "map.png")
    one_d = sweep_plot.save(serial.dataset.isel(nu=[1]), tmp_path / "line.png")
    for path in (two_d, one_d):
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ParameterError, match="one or two real axes"):
        sweep_plot.save(serial.dataset.isel(nu=[0], kappa=[0]), tmp_path / "none.png")




def test_cli_sweep_json_then_plot(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text('model = "mathieu"\nask = ["tau_min"]\n[params]\nnu = 0.1\n[grid]\n'
                     'kappa = {start = 0.1, stop = 1.2, num = 12}\n[tau_min]\ntau_max = 2.0\n')
    out = tmp_path / "m.zarr"
    assert cli.main(["sweep", str(scene), "--out", str(out), "--executor", "serial", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) == {"points", "computed", "skipped", "damaged", "outdated", "uncertified",
                         "out", "seconds"}
    assert (data["points"], data["computed"], data["skipped"]) == (24, 24, 0)
    assert cli.main(["sweep", str(scene), "--out", str(out), "--executor", "serial", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["computed"] == 0
    assert cli.main(["plot", str(out), "--png", str(tmp_path / "m.png")]) == 0
    assert (tmp_path / "m.png").is_file()


def test_cli_sweep_bad_grid_exits_2(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text('model = "mathieu"\n[grid]\nkappa = {start = 1, stop = 0, num = 3}\n')
    assert cli.main(["sweep", str(scene), "--out", str(tmp_path / "m.zarr")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "stop must be >= start" in err


def test_cli_run_routes_a_grid_scene_to_the_sweep_runner(tmp_path, capsys):
    scene = tmp_path / "g.toml"
    scene.write_text('model = "mathieu"\nask = ["tau_min"]\n[params]\nnu = 0.1\n[grid]\n'
                     'kappa = {start = 0.1, stop = 1.2, num = 4}\n[tau_min]\ntau_max = 2.0\n')
    assert cli.main(["run", str(scene), "--out", str(tmp_path / "o"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["points"], data["computed"]) == (8, 8)
    assert (tmp_path / "o" / "g.png").is_file()
    stored = open_sweep(tmp_path / "o" / "g.zarr")
    fresh = run_sweep(scene.read_text(), executor="serial").dataset
    assert_same(stored, fresh)


def _blas_threads():
    from threadpoolctl import threadpool_info

    return max(d["num_threads"] for d in threadpool_info())


def test_process_workers_do_not_oversubscribe_blas_threads():
    cores = os.cpu_count() or 1
    with executors.open_pool("processes", workers=2) as pool:
        threads = [pool.executor.submit(_blas_threads).result() for _ in range(2)]
    assert all(t <= max(1, cores // 2) for t in threads)


def test_interrupted_pool_is_stopped_before_open_pool_returns():
    """An interrupt inside open_pool('processes') terminates the pool's busy workers (the task
    would sleep 10 minutes) and ends its management thread before the KeyboardInterrupt leaves
    open_pool: nothing is left for the interpreter's exit hook to race (Python 3.11 printed an
    OSError from its wake-up pipe after the CLI's last line)."""
    import multiprocessing
    import threading

    before = set(multiprocessing.active_children())
    with pytest.raises(KeyboardInterrupt):
        with executors.open_pool("processes", workers=2) as pool:
            busy = pool.executor.submit(time.sleep, 600)
            while not busy.running():
                time.sleep(0.01)
            raise KeyboardInterrupt
    assert set(multiprocessing.active_children()) <= before
    managers = [t for t in threading.enumerate() if type(t).__name__ == "_ExecutorManagerThread"]
    assert not managers


def test_ctrl_c_during_a_store_write_waits_for_the_chunk(tmp_path):
    """A SIGINT arriving inside ZarrStore.write is held back until the chunk (values, then its
    computed flags) is written, then raised as KeyboardInterrupt: no half-written chunk, and no
    Zarr I/O task left pending (which printed "Task was destroyed but it is pending!")."""
    import signal

    from spectralshell.runner.layout import chunks, region
    from spectralshell.runner.store import ZarrStore

    spec = sweep_spec(SCENE)
    store = ZarrStore.create(tmp_path / "w.zarr", spec)
    chunk = chunks(spec)[0]
    where = region(spec, chunk)
    shape = np.zeros(spec.shape)[where].shape
    block = {name: np.full(shape, 0.25, dtype=dtype) for name, dtype in solve.VARIABLES.items()}
    real = store._arrays["tau_min"].__setitem__
    arrays = dict(store._arrays)

    class Interrupting:  # the first array write is interrupted by a real SIGINT
        def __setitem__(self, key, value):
            os.kill(os.getpid(), signal.SIGINT)
            real(key, value)

    store._arrays = {**arrays, "tau_min": Interrupting()}
    with pytest.raises(KeyboardInterrupt):
        store.write(chunk, block)
    written = open_sweep(tmp_path / "w.zarr")
    assert bool(written["computed"].values[where].all())  # the chunk was completed first
    assert np.all(written["tau_min"].values[where] == 0.25)


def test_minimum_map_is_nan_where_no_kind_is_unstable_and_json_has_null(serial, tmp_path):
    """A cell without a marginal tau <= tau_max of either kind (the Floquet API finds none
    there) holds NaN and has_tau False in the map and its NPZ, null in its JSON; the others
    hold the smaller tau_min of the two kinds."""
    mm = minimum_map(serial.dataset, "kappa", "nu")
    tau, has = mm["tau_min"].values, mm["has_tau"].values
    assert has.any() and not has.all()
    assert np.isnan(tau[~has]).all() and np.isfinite(tau[has]).all()
    j, i = np.argwhere(~has)[0]
    nu, kappa = float(mm["nu"][j]), float(mm["kappa"][i])
    ref = ss.floquet("mathieu", kappa=kappa, nu=nu, tau_max=2.0)
    assert ref.harmonic.tau_min is None and ref.subharmonic.tau_min is None
    j, i = np.argwhere(has)[0]
    ref = ss.floquet("mathieu", kappa=float(mm["kappa"][i]), nu=float(mm["nu"][j]), tau_max=2.0)
    best = min(t for t in (ref.harmonic.tau_min, ref.subharmonic.tau_min) if t is not None)
    assert abs(tau[j, i] - best) <= 1e-10

    data = json.loads(json.dumps(map_dict(mm), allow_nan=False))
    assert [[v is None for v in row] for row in data["tau_min"]] == (~has).tolist()
    with np.load(write_npz(mm, tmp_path / "map.npz")) as npz:
        np.testing.assert_array_equal(npz["tau_min"], tau)
        np.testing.assert_array_equal(npz["has_tau"], has)


def _as_written_before_nan(store: Path, spec) -> None:
    """Rewrite a Zarr store as the version before NaN wrote it: tau_max in tau_min where
    has_tau is false (finished chunks, with their completion records, and the fill values)."""
    import zarr

    from spectralshell.runner.integrity import read_records, record_path, write_record
    from spectralshell.runner.store import stored_variables

    group = zarr.open_group(str(store), mode="r+")
    has = group["has_tau"][...]
    group["tau_min"][...] = np.where(has, group["tau_min"][...], spec.options.tau_max)
    keys = set(read_records(store))
    for chunk in chunks(spec):
        if record_path(store, spec, chunk).stem in keys:
            where = region(spec, chunk)
            write_record(store, spec, chunk, {n: np.asarray(group[n][where], dtype=t)
                                              for n, t in stored_variables(spec).items()})


def test_a_store_of_the_tau_max_convention_reads_as_nan_and_resumes(serial, tmp_path):
    """A store written before (tau_max where there is no tau) verifies, reads with NaN there,
    and a rerun completes it to the fresh sweep."""
    out = tmp_path / "old.zarr"
    spec = sweep_spec(SCENE)

    def stop(n, _):
        if n == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(SCENE, executor="serial", out=out, on_chunk=stop)
    _as_written_before_nan(out, spec)
    old = open_sweep(out)
    done = old["computed"].values
    assert int(done.sum()) == 3 * POINTS_PER_CHUNK and (~old["has_tau"].values[done]).any()
    np.testing.assert_array_equal(old["tau_min"].values[done], serial.dataset["tau_min"].values[done])
    assert np.isnan(old["tau_min"].values[~old["has_tau"].values]).all()
    resumed = run_sweep(SCENE, executor="serial", out=out)
    assert (resumed.computed, resumed.damaged) == (96 - 3 * POINTS_PER_CHUNK, 0)
    assert_same(resumed.dataset, serial.dataset)
    assert_same(open_sweep(out), serial.dataset)
    import xarray as xr  # the store as another reader sees it: one convention, migrated

    raw = xr.open_zarr(out, mask_and_scale=False).load()
    assert np.isnan(raw["tau_min"].values[~raw["has_tau"].values]).all()
    assert raw["tau_min"].attrs["note"] == "NaN where has_tau is false"


def test_a_netcdf_of_the_tau_max_convention_reads_as_nan(serial, tmp_path):
    """A NetCDF sweep written before NaN (tau_max where there is no tau, its digest of those
    values) verifies and reads with NaN there; a rerun computes nothing."""
    from spectralshell.runner.integrity import dataset_digest
    from spectralshell.runner.solve import spatial_rule
    from spectralshell.runner.store import stored_variables, to_dataset

    spec, out = sweep_spec(SCENE), tmp_path / "old.nc"
    arrays = {n: serial.dataset[n].values.copy() for n in stored_variables(spec)}
    arrays["tau_min"] = np.where(arrays["has_tau"], arrays["tau_min"], spec.options.tau_max)
    ds = to_dataset(spec, arrays)
    ds.attrs["data_sha256"] = dataset_digest(spec, arrays, spatial_rule(spec))
    ds.to_netcdf(out)
    assert_same(open_sweep(out), serial.dataset)
    assert run_sweep(SCENE, executor="serial", out=out).computed == 0


def test_ctrl_c_in_the_cli_says_what_is_kept_and_the_command_that_resumes(monkeypatch, tmp_path,
                                                                        capsys):
    """A KeyboardInterrupt in the middle of a CLI sweep: exit status 130, one line counting the
    points stored (as the store says) and the exact command; running that command finishes the
    sweep, computing only the rest, to the numbers of a fresh sweep."""
    scene = tmp_path / "s.toml"
    scene.write_text('model = "mathieu"\nask = ["tau_min"]\n[params]\nnu = 0.1\n[grid]\n'
                     'kappa = {start = 0.1, stop = 1.2, num = 12}\n[tau_min]\ntau_max = 2.0\n'
                     '[sweep]\nchunk = 3\n')
    out = tmp_path / "m.zarr"
    real, calls = solve.solve_kind, []

    def interrupted(*args):
        calls.append(1)
        if len(calls) == 15:  # in the third chunk (3 points x 2 kinds per chunk)
            raise KeyboardInterrupt
        return real(*args)

    monkeypatch.setattr(solve, "solve_kind", interrupted)
    argv = ["sweep", str(scene), "--out", str(out), "--executor", "serial"]
    assert cli.main(argv) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    found = re.fullmatch(r"spectralshell: interrupted: (\d+) of 24 points are stored in (.+); "
                         r"resume with: (.+)", err[0])
    assert found, err
    kept = int(found.group(1))
    assert kept == 12 == int(open_sweep(out)["computed"].sum()) and found.group(2) == str(out)
    command = shlex.split(found.group(3))
    assert command == ["spectralshell", *argv]

    monkeypatch.setattr(solve, "solve_kind", real)
    assert cli.main(command[1:] + ["--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["computed"], summary["skipped"]) == (24 - kept, kept)
    assert_same(open_sweep(out), run_sweep(str(scene), executor="serial").dataset)


def test_ctrl_c_in_a_sweep_without_store_keeps_nothing(monkeypatch):
    def interrupted(*args):
        raise KeyboardInterrupt

    monkeypatch.setattr(solve, "solve_kind", interrupted)
    with pytest.raises(SweepInterrupted, match="nothing kept") as caught:
        run_sweep(SCENE, executor="serial")
    assert isinstance(caught.value, KeyboardInterrupt) and caught.value.kept == 0
