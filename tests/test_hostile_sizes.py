"""Sizes and costs are refused before work starts; a peer that is not a Dask scheduler is refused
in one line within the connection timeout (issue 23, section 4)."""

import fcntl
import http.server
import os
import pty
import select
import socket
import struct
import subprocess
import sys
import termios
import threading
import time
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import spectralshell as ss
from spectralshell import cli
from spectralshell.errors import ParameterError
from spectralshell.params.grid import parse_int_range, parse_range
from spectralshell.params.limits import POINTS
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.runner import executors, run_sweep
from spectralshell.runner import floquet as floquet_runner
from spectralshell.solvers.cost import duration, spatial_cost, temporal_schedule

ROOT = Path(__file__).resolve().parents[1]
LIMIT = int(POINTS.default)
RAISE = "SPECTRALSHELL_MAX_POINTS"
WAIT = 120  # seconds: a bounded wait for a refusal (imports on a loaded machine), not a speed test


@pytest.fixture(autouse=True)
def default_limits(monkeypatch):
    for limit in ("SPECTRALSHELL_MAX_POINTS", "SPECTRALSHELL_MAX_MEMORY",
                  "SPECTRALSHELL_MAX_SECONDS"):
        monkeypatch.delenv(limit, raising=False)


@settings(max_examples=60, deadline=None)
@given(num=st.integers(LIMIT + 1, 10**30),
       start=st.floats(-1e3, 1e3).filter(lambda x: x == 0 or abs(x) >= 1e-100))  # input range
def test_huge_range_is_refused_with_the_limit_and_how_to_raise_it(num, start):
    with pytest.raises(ParameterError) as err:
        parse_range("kappa", f"{start}:{start + 1}:{num}")
    message = str(err.value)
    assert "\n" not in message and "grid points" in message
    # the API names its keyword (the CLI turns it into --max-points: test_cli_names_its_flags)
    assert str(LIMIT) in message and "max_points=" in message and "--" not in message
    assert RAISE in message


@settings(max_examples=30, deadline=None)
@given(num=st.integers(2, 2000))
def test_range_within_the_limit_is_accepted(num):
    assert parse_range("kappa", f"0:1:{num}").size == num
    with pytest.raises(ParameterError, match=r"limit of 1\b"):
        parse_range("kappa", f"0:1:{num}", max_points=1)


@settings(max_examples=40, deadline=None)
@given(lo=st.integers(2, 200), hi=st.integers(201, 10**40))
def test_degree_range_is_checked_on_its_ends(lo, hi):
    with pytest.raises(ParameterError, match=r"must be an integer in \[2, 200\]"):
        parse_int_range("m", f"{lo}:{hi}", (2, 200))


def test_integer_range_without_bounds_counts_its_values():
    with pytest.raises(ParameterError, match="grid points"):
        parse_int_range("m", "0:10000000000000")
    assert parse_int_range("m", "3:5") == [3, 4, 5]


def test_tongues_refuses_a_huge_grid_before_any_solve(monkeypatch):
    monkeypatch.setattr(floquet_runner, "_map", lambda *a, **k: pytest.fail("solved"))
    with pytest.raises(ParameterError, match="kappa = '0:1:100000000' is invalid"):
        ss.tongues("mathieu", kappa="0:1:100000000", nu=0.1)
    with pytest.raises(ParameterError, match="kappa is invalid: it needs 5 grid points"):
        ss.tongues("mathieu", kappa=[0.1, 0.2, 0.3, 0.4, 0.5], nu=0.1, max_points=4)


def test_the_limit_is_raised_by_keyword_and_environment(monkeypatch):
    res = ss.tongues("mathieu", kappa="0.1:0.3:3", nu=0.1, max_points=3, tips=False, workers=1)
    assert res.kappa.size == 3
    monkeypatch.setenv(RAISE, "2")
    with pytest.raises(ParameterError, match="limit of 2;"):
        ss.tongues("mathieu", kappa="0.1:0.3:3", nu=0.1)
    monkeypatch.setenv(RAISE, "lots")
    with pytest.raises(ParameterError, match="SPECTRALSHELL_MAX_POINTS = 'lots' is invalid"):
        ss.tongues("mathieu", kappa="0.1:0.3:3", nu=0.1)


def test_memory_of_the_results_is_estimated_before_the_work(monkeypatch):
    monkeypatch.setenv("SPECTRALSHELL_MAX_MEMORY", "1000")
    with pytest.raises(ParameterError, match="bytes of results.*SPECTRALSHELL_MAX_MEMORY"):
        ss.tongues("mathieu", kappa="0.1:0.3:3", nu=0.1)


def test_tau_map_counts_x_y_and_degrees(monkeypatch):
    monkeypatch.setattr(sys.modules["spectralshell.runner.sweep"], "run_sweep", lambda *a, **k: pytest.fail("solved"))
    with pytest.raises(ParameterError, match=r"grid kappa x nu x m = 1000 x 1000 x 2"):
        ss.tau_map("sphere", x=("kappa", "0.01:0.2:1000"), y=("nu", "0.001:0.01:1000"), m="2:3")
    with pytest.raises(ParameterError, match=r"m = 400 is invalid: must be an integer in \[2, 200\]"):
        ss.tau_map("sphere", x=("kappa", "0.01:0.2:3"), y=("nu", "0.001:0.01:3"), m="2:400")


def test_stability_refuses_degrees_beyond_the_model_before_solving(monkeypatch):
    monkeypatch.setattr(floquet_runner, "floquet", lambda *a, **k: pytest.fail("solved"))
    with pytest.raises(ParameterError, match=r"m = 100000 is invalid: must be an integer in \[2, 200\]"):
        ss.stability("sphere", tau=0.4, m="2:100000", kappa=0.1, nu=0.01)


@settings(max_examples=25, deadline=None)
@given(nums=st.lists(st.integers(10, 10**12), min_size=2, max_size=3))
def test_sweep_grid_is_refused_by_its_total(nums):
    grid = {name: f"0.01:0.5:{n}" for name, n in zip(("kappa", "nu", "tau"), nums)}
    grid.pop("tau", None)
    total = 2
    for n in list(grid.values()):
        total *= int(n.rsplit(":", 1)[1])
    scene = {"model": "mathieu", "grid": grid}
    if total > LIMIT:
        with pytest.raises(ParameterError, match="grid .*is invalid: it needs .*grid points"):
            sweep_spec(scene)
    else:
        assert sweep_spec(scene).size == total


def test_sweep_limit_is_raised_per_scene():
    scene = {"model": "mathieu", "grid": {"kappa": "0.1:0.3:3", "nu": [0.1, 0.2]}}
    with pytest.raises(ParameterError, match="grid kappa x nu x kind = 3 x 2 x 2"):
        sweep_spec(scene, max_points=11)
    assert sweep_spec(scene, max_points=12).size == 12
    with pytest.raises(ParameterError, match=r"grid m = 5000 is invalid: must be an integer in \[2, 200\]"):
        sweep_spec({"model": "sphere", "params": {"kappa": 0.1}, "grid": {"m": "2:5000"}})


def _cli(*argv: str, timeout: float = WAIT) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "spectralshell", *argv], capture_output=True,
                          text=True, timeout=timeout, env=env, cwd=ROOT)


def test_cli_refuses_the_huge_kappa_range_in_one_line():
    proc = _cli("tongues", "mathieu", "--nu", "0.1", "--kappa", "0:1:100000000")
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "--max-points" in proc.stderr


def test_cli_max_points_flag(capsys):
    assert cli.main(["tongues", "mathieu", "--nu", "0.1", "--kappa", "0.1:0.3:3", "--no-tips",
                     "--max-points", "2"]) == 2
    assert "limit of 2;" in capsys.readouterr().err


# --- the cochlea's cost ----------------------------------------------------------------------


def test_cochlea_at_low_forcing_frequency_is_refused_with_what_it_needs(monkeypatch):
    """Refused before any marginal tau is solved (a solve here would fail the test)."""
    import spectralshell.solvers.spatial_refinement as refinement

    def no_solve(*args, **kwargs):
        raise AssertionError("marginal_tau ran before the cost was refused")

    monkeypatch.setattr(refinement, "marginal_tau", no_solve)
    monkeypatch.setattr(sys.modules["spectralshell.runner.solve"], "marginal_tau", no_solve)
    with pytest.raises(ParameterError) as err:
        ss.floquet("cochlea", omega=10.0)
    message = str(err.value)
    assert "N = 316, M = 32" in message and "seconds (estimated)" in message
    assert "max_seconds=" in message and "n_spatial=" in message and "--" not in message


def test_fixed_truncations_are_priced_and_the_limit_is_raised():
    """A fixed M with N refined is priced and refused above the limit; with both M and N fixed
    nothing is refined, and the caller's size is not refused (the way out the message names)."""
    kwargs = dict(omega=1000.0, n_spatial=8, kind="harmonic")
    with pytest.raises(ParameterError, match="cochlea solve needing N = .*, M = 8.*n_temporal="):
        ss.floquet("cochlea", max_seconds=1e-9, **kwargs)
    assert ss.floquet("cochlea", max_seconds=60, **kwargs).n_spatial == 8
    assert ss.floquet("cochlea", max_seconds=1e-9, n_temporal=12, **kwargs).n_spatial == 8
    with pytest.raises(ParameterError, match="max_seconds = 5 is invalid for model 'mathieu'"):
        ss.floquet("mathieu", kappa=1.0, max_seconds=5)


def test_cost_model_follows_the_truncation_schedule():
    factory = lambda m: floquet_runner.spatial_system("cochlea", {"kappa": 53.9, "nu": 1.6e-4,
                                                         "alpha": 1.56}, m)
    system = factory(16)
    schedule = temporal_schedule(system)
    assert schedule[0] == int(system.n_resonant) + 9 and schedule[-1] >= system.n_highest + 8
    assert temporal_schedule(system, 40) == (30, 40)
    fixed = spatial_cost(factory, ["harmonic"], n_spatial=16, n_temporal=40)
    auto = spatial_cost(factory, ["harmonic", "subharmonic"])
    assert fixed.seconds == fixed.seconds_max and fixed.levels == 2
    # refined: the first window (16, 24, 32) at least, the ladder 16, 24, ..., 384, 512 at most
    assert auto.n_spatial == 32 and auto.levels == 11 and auto.seconds < auto.seconds_max
    assert [duration(s) for s in (0.42, 720, 6120)] == ["0.42 s", "12 min", "1.7 h"]


def _start_under_a_terminal(argv: list[str], until: str, timeout: float) -> str:
    """stderr of the CLI run with a terminal as stderr, until ``until`` appears (then killed)."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 250, 0, 0))  # a wide terminal
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-m", "spectralshell", *argv], stdout=subprocess.PIPE,
                            stderr=slave, env=env, cwd=ROOT)
    os.close(slave)
    seen, deadline = b"", time.monotonic() + timeout
    try:
        while until.encode() not in seen and time.monotonic() < deadline and proc.poll() is None:
            if select.select([master], [], [], 0.5)[0]:
                try:
                    seen += os.read(master, 4096)
                except OSError:
                    break
    finally:
        proc.kill()
        proc.wait()
        os.close(master)
    return seen.decode(errors="replace")


def test_cli_cochlea_low_frequency_refuses_and_high_frequency_starts_with_an_estimate():
    proc = _cli("floquet", "cochlea", "--omega", "10")
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1
    assert "estimated" in proc.stderr and "--max-seconds" in proc.stderr
    shown = _start_under_a_terminal(["floquet", "cochlea", "--omega", "1e5"], "about", WAIT)
    assert "cochlea (N = 15, M = 32: about" in shown and "up to" in shown, shown


# --- Dask peers that are not schedulers ------------------------------------------------------


class _Quiet(http.server.BaseHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture
def web_server():
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _Quiet)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"tcp://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


def _raw_server(greeting: bytes):
    """A TCP server on 127.0.0.1 that sends ``greeting`` to each client and holds it open."""
    listener = socket.create_server(("127.0.0.1", 0))
    held, stop = [], threading.Event()

    def serve():
        listener.settimeout(0.1)
        while not stop.is_set():
            try:
                conn, _ = listener.accept()
            except OSError:  # the timeout, or the listener closed
                continue
            held.append(conn)
            conn.sendall(greeting)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    return f"tcp://127.0.0.1:{listener.getsockname()[1]}", stop, listener, held


@pytest.fixture(params=[b"\xff" * 64, b"", b"SSH-2.0-OpenSSH_9.6\r\n", b"\x10" + b"\x00" * 7 + b"x" * 16],
                ids=["garbage", "silent", "banner", "bad-frames"])
def raw_server(request):
    address, stop, listener, held = _raw_server(request.param)
    yield address
    stop.set()
    listener.close()
    for conn in held:
        conn.close()


def _refused_in_time(address: str) -> str:
    t0 = time.perf_counter()
    with pytest.raises(ParameterError) as err:
        executors._probe(None, address, 1.0)
    assert time.perf_counter() - t0 < 5
    message = str(err.value)
    assert "\n" not in message and "is not a Dask scheduler" in message
    return message


def test_a_web_server_is_not_a_scheduler(web_server):
    assert "no greeting within 1 s" in _refused_in_time(web_server)


def test_other_peers_are_not_schedulers(raw_server):
    _refused_in_time(raw_server)


def test_a_refused_connection_is_unreachable():
    with pytest.raises(ParameterError, match="unreachable: no Dask scheduler answered within 0.3 s"):
        executors._probe(None, "tcp://127.0.0.1:9", 0.3)


def test_sweep_on_a_garbage_peer_fails_in_one_line(monkeypatch, tmp_path):
    pytest.importorskip("distributed")
    monkeypatch.setattr(executors, "CONNECT_TIMEOUT", 1.0)
    address, stop, listener, held = _raw_server(b"\xff" * 64)
    try:
        with pytest.raises(ParameterError, match="is not a Dask scheduler: the peer answered with "
                                                 "a first message of 18446744073709551615 bytes"):
            run_sweep({"model": "mathieu", "params": {"nu": 0.0}, "grid": {"kappa": [0.1, 0.2]}},
                      executor="dask",
                      scheduler=address, out=tmp_path / "x.zarr")
    finally:
        stop.set()
        listener.close()
        for conn in held:
            conn.close()
    assert not (tmp_path / "x.zarr").exists()


def test_response_prices_its_marginal_solves_before_running():
    """response's parametric kinds solve marginal_tau at M and M // 2: a low forcing frequency
    (omega = 10 rad/s: N up to 400 at M = 128) is refused before any solve, with the limit and
    the keyword that raises it; the tone solves none and takes no max_seconds."""
    with pytest.raises(ParameterError, match=r"cochlea solve needing N = \d+, M = 128.*max_seconds="):
        ss.response("cochlea", omega=10.0, kind="subharmonic")
    with pytest.raises(ParameterError, match="max_seconds = 5 is invalid for kind = 'tone'"):
        ss.response("cochlea", omega=1000.0, max_seconds=5)
    result = subprocess.run([sys.executable, "-m", "spectralshell", "response", "cochlea",
                             "--omega", "10", "--kind", "harmonic"],
                            capture_output=True, text=True, timeout=WAIT)
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    assert "--max-seconds" in result.stderr
