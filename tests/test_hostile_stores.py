"""Hostile stores and processes: damaged chunks are found, reported and recomputed; one writer
per store; pool workers end with a killed sweep."""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from spectralshell import cli
from spectralshell.errors import ParameterError, StoreBusy, StoreDamaged
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.runner import open_sweep, run_sweep
from spectralshell.runner.integrity import write_record
from spectralshell.runner.layout import chunk_key, chunks, region
from spectralshell.runner.lock import lock_path
from spectralshell.runner.store import stored_variables

SCENE = {"model": "mathieu", "ask": ["tau_min"],
         "grid": {"nu": [0.0, 0.1], "kappa": {"start": 0.05, "stop": 1.5, "num": 12}},
         "tau_min": {"tau_max": 2.0}, "sweep": {"chunk": 4}}
SPEC = sweep_spec(SCENE)
PLAN = chunks(SPEC)
TARGET = PLAN[4]  # nu = 0.1, kappa[4:8]
OTHER = PLAN[1]  # nu = 0, kappa[4:8]
KEY, OTHER_KEY = chunk_key(SPEC, TARGET), chunk_key(SPEC, OTHER)
POINTS = 4 * 2  # points of one chunk (two kinds)
ROOT = Path(__file__).resolve().parents[1]
#: A sweep in another process, 0.1 s per solve (so that it is still running when the test acts):
#: argv = scene JSON, out, executor, workers, 'watchdog' (no kernel parent-death signal) or ''.
SLOW_SWEEP = """
import json, sys, time
from spectralshell.runner import executors, run_sweep, solve
real = solve.solve_kind
def slow(*args):
    time.sleep(0.1)
    return real(*args)
solve.solve_kind = slow
if sys.argv[5] == "watchdog":
    executors._kernel_kills_orphan = lambda: False
run_sweep(json.loads(sys.argv[1]), out=sys.argv[2], executor=sys.argv[3],
          workers=int(sys.argv[4]))
"""


def tree(path: Path) -> dict[str, bytes]:
    """Every file of a store (relative path -> bytes)."""
    return {str(p.relative_to(path)): p.read_bytes() for p in sorted(path.rglob("*"))
            if p.is_file()}


@pytest.fixture(scope="module")
def clean(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("clean") / "map.zarr"
    run_sweep(SCENE, executor="serial", out=out)
    return out


def _copy_other_cell(store: Path) -> None:  # another cell's file at this cell's name
    shutil.copy(store / "tau_min" / OTHER_KEY, store / "tau_min" / KEY)


def _other_cells_record(store: Path) -> None:  # another cell's record and files at this one
    for name in ("tau_min", "has_tau", "error_estimate", "n_temporal", "computed"):
        if (store / name / OTHER_KEY).exists():
            shutil.copy(store / name / OTHER_KEY, store / name / KEY)
    shutil.copy(store / ".chunks" / f"{OTHER_KEY}.json", store / ".chunks" / f"{KEY}.json")


def _foreign_store_record(store: Path, tmp_path: Path) -> None:  # same chunk, another scene
    other = {**SCENE, "tau_min": {"tau_max": 1.0}}
    run_sweep(other, executor="serial", out=tmp_path / "other.zarr")
    for name in ("tau_min", "has_tau", "error_estimate", "n_temporal", "computed", ".chunks"):
        for found in (tmp_path / "other.zarr" / name).glob(f"{KEY}*"):
            shutil.copy(found, store / name / found.name)


def _directory_instead(store: Path) -> None:
    (store / "tau_min" / KEY).unlink()
    (store / "tau_min" / KEY / "x").mkdir(parents=True)


DAMAGE = {
    "chunk file deleted": lambda s, t: (s / "tau_min" / KEY).unlink(),
    "garbage chunk": lambda s, t: (s / "tau_min" / KEY).write_bytes(b"garbage" * 9),
    "empty chunk": lambda s, t: (s / "error_estimate" / KEY).write_bytes(b""),
    "truncated chunk": lambda s, t: (s / "tau_min" / KEY).write_bytes(
        (s / "tau_min" / KEY).read_bytes()[:40]),
    "another variable's chunk": lambda s, t: shutil.copy(s / "n_temporal" / KEY,
                                                          s / "tau_min" / KEY),
    "another cell's chunk": lambda s, t: _copy_other_cell(s),
    "another cell's chunk and record": lambda s, t: _other_cells_record(s),
    "another store's chunk and record": _foreign_store_record,
    "a directory instead of a chunk": lambda s, t: _directory_instead(s),
    "garbage record": lambda s, t: (s / ".chunks" / f"{KEY}.json").write_text("{"),
}


@pytest.mark.parametrize("damage", list(DAMAGE))
def test_a_damaged_chunk_is_refused_then_recomputed_alone_to_the_clean_store(
        damage, clean, tmp_path, capsys):
    store = tmp_path / "map.zarr"
    shutil.copytree(clean, store)
    DAMAGE[damage](store, tmp_path)

    with pytest.raises(StoreDamaged, match=r"1 of 6 chunks missing, unreadable or altered"):
        open_sweep(store)
    assert cli.main(["plot", str(store), "--png", str(tmp_path / "m.png")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "is damaged" in err and "rerun" in err
    assert not (tmp_path / "m.png").exists()

    seen = []
    run = run_sweep(SCENE, executor="serial", out=store, on_chunk=lambda n, r: seen.append(r.index))
    assert seen == [TARGET.index]
    assert (run.computed, run.damaged, run.skipped) == (POINTS, POINTS, SPEC.size - POINTS)
    assert tree(store) == tree(clean)


def test_a_chunk_without_record_reads_as_unfinished_and_is_recomputed(clean, tmp_path):
    """A writer killed before a chunk's record (temporary files left), or a removed record."""
    store = tmp_path / "map.zarr"
    shutil.copytree(clean, store)
    (store / ".chunks" / f"{KEY}.json").unlink()
    (store / "tau_min" / KEY).unlink()  # its values are not served either
    (store / "tau_min" / f"{KEY[:-2]}.0123abcd.partial").write_bytes(b"half a chunk")
    (store / ".chunks" / "0123abcd.partial").write_text('{"chunk"')

    partial = open_sweep(store)
    where = region(SPEC, TARGET)
    assert not partial["computed"].values[where].any() and partial["computed"].sum() == SPEC.size - POINTS
    assert np.isnan(partial["tau_min"].values[where]).all()  # no value there
    assert not partial["has_tau"].values[where].any()

    run = run_sweep(SCENE, executor="serial", out=store)
    assert (run.computed, run.damaged) == (POINTS, 0)
    assert tree(store) == tree(clean)


def test_altered_coordinates_are_refused_then_rewritten(clean, tmp_path):
    import zarr

    store = tmp_path / "map.zarr"
    shutil.copytree(clean, store)
    zarr.open_group(str(store), mode="r+")["kappa"][3] = 9.0
    with pytest.raises(StoreDamaged, match="coordinates kappa altered"):
        open_sweep(store)
    assert run_sweep(SCENE, executor="serial", out=store).computed == 0
    assert tree(store) == tree(clean)


def test_an_undamaged_store_reads_back_as_the_run(clean):
    fresh = run_sweep(SCENE, executor="serial").dataset
    back = open_sweep(clean)
    assert list(back.data_vars) == list(fresh.data_vars)
    for name in back.variables:
        np.testing.assert_array_equal(back[name].values, fresh[name].values, err_msg=name)
    assert back.attrs == json.loads(json.dumps(fresh.attrs))


def _written_before_complete_to(store: Path) -> None:
    """``store`` as a version before complete_to wrote it: no such array (nor in the
    consolidated metadata), and each chunk's record the digest of the other variables."""
    import zarr

    shutil.rmtree(store / "complete_to")
    meta = json.loads((store / ".zmetadata").read_text())
    meta["metadata"] = {k: v for k, v in meta["metadata"].items()
                        if not k.startswith("complete_to/")}
    (store / ".zmetadata").write_text(json.dumps(meta, indent=4))
    group = zarr.open_group(str(store), mode="r")
    for chunk in PLAN:
        where = region(SPEC, chunk)
        write_record(store, SPEC, chunk, {name: np.asarray(group[name][where], dtype=dtype)
                                          for name, dtype in stored_variables(SPEC).items()
                                          if name != "complete_to"})


def test_a_store_written_before_complete_to_says_so_and_is_recomputed(clean, tmp_path, capsys):
    """Its empty points were never proved: reading refuses it in one line that says why (not
    as damage, exit status 2 as for damage), and a rerun recomputes every chunk, counts them as
    outdated, not damaged, and ends equal to a clean run."""
    store = tmp_path / "map.zarr"
    shutil.copytree(clean, store)
    _written_before_complete_to(store)
    why = r"written before certified empty answers \(no complete_to: its empty points"
    with pytest.raises(StoreDamaged, match=why + r".*recompute its 6 finished chunks"):
        open_sweep(store)
    assert cli.main(["plot", str(store), "--png", str(tmp_path / "m.png")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "certified empty answers" in err and "damaged" not in err
    assert not (tmp_path / "m.png").exists()

    run = run_sweep(SCENE, executor="serial", out=store)
    assert (run.computed, run.outdated, run.damaged) == (SPEC.size, SPEC.size, 0)
    line = cli._sweep_text(run.summary())
    assert "\n" not in line and f"{SPEC.size} of them in outdated chunks of the store" in line \
        and "damaged" not in line
    assert tree(store) == tree(clean)


METADATA_DAMAGE = {
    "group attributes garbage": lambda store: (store / ".zattrs").write_bytes(b"\x00{garbage"),
    "consolidated metadata removed": lambda store: (store / ".zmetadata").unlink(),
    "group marker removed": lambda store: (store / ".zgroup").unlink(),
    "array metadata garbage": lambda store: (store / "tau_min" / ".zarray").write_text("[1, 2"),
    "array metadata of another shape": lambda store: (store / "has_tau" / ".zarray").write_text(
        (store / "has_tau" / ".zarray").read_text().replace("12", "13")),
}


@pytest.mark.parametrize("damage", list(METADATA_DAMAGE))
def test_damaged_metadata_is_refused_then_rebuilt_by_a_rerun(damage, clean, tmp_path, capsys):
    """The completion records say whose store it is: reading refuses it in one line, and a
    rerun of the same scene rebuilds the metadata from the scene, keeps every chunk whose
    values still match its record, and ends equal to a clean run."""
    store = tmp_path / "map.zarr"
    shutil.copytree(clean, store)
    METADATA_DAMAGE[damage](store)
    with pytest.raises(StoreDamaged, match="metadata cannot be read.*rerun its sweep"):
        open_sweep(store)
    assert cli.main(["plot", str(store), "--png", str(tmp_path / "m.png")]) == 2
    assert "\n" not in capsys.readouterr().err.strip()
    run = run_sweep(SCENE, executor="serial", out=store)
    assert run.computed == 0 and run.damaged == 0
    assert tree(store) == tree(clean)


def test_metadata_is_not_rebuilt_over_another_sweeps_chunks(clean, tmp_path):
    """Records of another scene: the store is not this sweep's, and stays untouched."""
    store = tmp_path / "map.zarr"
    shutil.copytree(clean, store)
    (store / ".zattrs").write_text("{")
    before = tree(store)
    other = {**SCENE, "tau_min": {"tau_max": 3.0}}
    with pytest.raises(ParameterError, match="not a readable spectralshell sweep"):
        run_sweep(other, executor="serial", out=store)
    assert tree(store) == before


def _rewrite_netcdf(path: Path, change) -> None:
    """Rewrite a NetCDF sweep with ``change(ds)`` applied, its attributes (and digest) kept."""
    import xarray as xr

    with xr.open_dataset(path) as ds:
        ds = ds.load()
    change(ds)
    path.unlink()
    ds.to_netcdf(path)


NETCDF_DAMAGE = {
    "value": lambda ds: ds["tau_min"].values.__setitem__((1, 4, 0), 0.123),
    "computed flag": lambda ds: ds["computed"].values.__setitem__((0, 0, 1), False),
    "coordinate": lambda ds: ds.__setitem__("kappa", ds["kappa"] + 1e-9),
    "digest removed": lambda ds: ds.attrs.pop("data_sha256"),
}


@pytest.mark.parametrize("damage", list(NETCDF_DAMAGE))
def test_a_damaged_netcdf_is_refused_then_recomputed_whole(damage, tmp_path, capsys):
    """A NetCDF sweep is written at once, with one digest of its values and axes: any change
    is refused on reading; a rerun recomputes it and ends equal to a clean run."""
    clean = tmp_path / "clean.nc"
    run_sweep(SCENE, executor="serial", out=clean)
    out = tmp_path / "map.nc"
    shutil.copy(clean, out)
    np.testing.assert_array_equal(open_sweep(out)["tau_min"].values,
                                  open_sweep(clean)["tau_min"].values)
    _rewrite_netcdf(out, NETCDF_DAMAGE[damage])
    with pytest.raises(StoreDamaged, match="is damaged.*rerun"):
        open_sweep(out)
    assert cli.main(["plot", str(out), "--png", str(tmp_path / "m.png")]) == 2
    assert "is damaged" in capsys.readouterr().err
    run = run_sweep(SCENE, executor="serial", out=out)
    assert (run.computed, run.damaged) == (SPEC.size, SPEC.size)
    back, want = open_sweep(out), open_sweep(clean)
    for name in want.variables:
        np.testing.assert_array_equal(back[name].values, want[name].values, err_msg=name)


def _start(out: Path, executor: str = "serial", workers: int = 1,
           watchdog: bool = False, scene: dict = SCENE) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    return subprocess.Popen([sys.executable, "-c", SLOW_SWEEP, json.dumps(scene), str(out),
                             executor, str(workers), "watchdog" if watchdog else ""], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def wait_for(condition, what: str, seconds: float = 60.0) -> None:
    """Poll ``condition`` until it holds; fail after ``seconds`` (a bound, not a measurement)."""
    deadline = time.monotonic() + seconds
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail(f"gave up waiting for {what} after {seconds:g} s")
        time.sleep(0.05)


def _holds_lock(proc: subprocess.Popen, out: Path) -> bool:
    try:
        return json.loads(lock_path(out).read_text())["pid"] == proc.pid
    except (OSError, ValueError, KeyError):
        return False


def _alive(pid: int) -> bool:
    """The process exists and is not a zombie (an ended orphan may wait to be reaped)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def _children(pid: int) -> list[int]:
    found = []
    for task in Path(f"/proc/{pid}/task").glob("*"):
        try:
            found += [int(c) for c in (task / "children").read_text().split()]
        except OSError:
            pass
    return found


def _kill_and_expect_gone(sweep: subprocess.Popen, started, what: str, seconds: float) -> None:
    """SIGKILL the sweep once ``started()`` has returned the processes it started, and wait for
    them to end (any still alive when the test ends are killed)."""
    below: list[int] = []
    try:
        below = started()
        sweep.send_signal(signal.SIGKILL)
        sweep.wait()
        wait_for(lambda: not any(_alive(p) for p in below), what, seconds=seconds)
    finally:
        sweep.kill()
        for p in below:
            if _alive(p):
                os.kill(p, signal.SIGKILL)


def _descendants(pid: int) -> list[int]:
    """Every process below ``pid`` (children, their children, ...)."""
    found = _children(pid)
    return found + [d for c in found for d in _descendants(c)]


def _spawned(pid: int) -> list[int]:
    """The processes below ``pid`` started by multiprocessing's 'spawn' (a cluster's workers)."""
    out = []
    for p in _descendants(pid):
        try:
            if b"spawn_main" in Path(f"/proc/{p}/cmdline").read_bytes():
                out.append(p)
        except OSError:
            pass
    return out


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_local_cluster_processes_end_with_a_killed_sweep(tmp_path):
    """A LocalCluster (executor 'dask', scheduler 'local'): its worker processes, started by
    'spawn', and every other process below the sweep end once the sweep is killed."""
    pytest.importorskip("distributed")
    # spawned workers do not see SLOW_SWEEP's sleep: a grid of ~1 min of work keeps them busy
    long = {**SCENE, "grid": {"nu": [0.1], "kappa": {"start": 0.05, "stop": 3.0, "num": 100000}},
            "sweep": {"chunk": 256}}
    sweep = _start(tmp_path / "map.zarr", executor="dask", workers=2, scene=long)
    def cluster() -> list[int]:
        wait_for(lambda: len(_spawned(sweep.pid)) >= 2, "two cluster workers", seconds=90.0)
        wait_for(lambda: (tmp_path / "map.zarr" / ".chunks").is_dir(), "a first chunk",
                 seconds=90.0)
        return _descendants(sweep.pid)

    _kill_and_expect_gone(sweep, cluster, "the orphaned cluster to end", seconds=30.0)


@pytest.mark.parametrize("start", ["fresh", "resume"])
def test_a_second_writer_gets_one_line_and_a_killed_writer_frees_the_store(
        start, clean, tmp_path, capsys):
    out = tmp_path / "map.zarr"
    if start == "resume":
        shutil.copytree(clean, out)
        for record in list((out / ".chunks").glob("*.json"))[:3]:
            record.unlink()
    writer = _start(out)
    try:
        wait_for(lambda: _holds_lock(writer, out), "the first writer's lock")
        with pytest.raises(StoreBusy, match=rf"being written by another process \(pid "
                                            rf"{writer.pid} on .*, since .*\): wait"):
            run_sweep(SCENE, executor="serial", out=out)
        scene = tmp_path / "s.toml"
        scene.write_text('model = "mathieu"\n[params]\nnu = 0\n[grid]\nkappa = [0.5]\n')  # refused before reading
        assert cli.main(["sweep", str(scene), "--out", str(out), "--executor", "serial"]) == 2
        err = capsys.readouterr().err.strip()
        assert "\n" not in err and "being written by another process" in err
        if start == "fresh":
            wait_for(lambda: any((out / ".chunks").glob("*.json")), "a first finished chunk")
    finally:
        writer.kill()  # kill -9: the kernel releases its lock
        writer.wait()
    run = run_sweep(SCENE, executor="serial", out=out)
    assert run.damaged == 0 and (start == "resume" or run.computed < SPEC.size)
    assert tree(out) == tree(clean)
    assert not lock_path(out).exists()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("watchdog", [False, True], ids=["kernel", "watchdog"])
def test_pool_workers_end_with_a_killed_sweep(watchdog, tmp_path):
    sweep = _start(tmp_path / "map.zarr", executor="processes", workers=2, watchdog=watchdog)
    def pool() -> list[int]:
        wait_for(lambda: len(_children(sweep.pid)) == 2, "two pool workers")
        return _children(sweep.pid)

    _kill_and_expect_gone(sweep, pool, "the orphaned workers to end", seconds=10.0)
