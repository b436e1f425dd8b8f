"""Executors behind one interface (``concurrent.futures.Executor``): serial, processes, Dask.

* ``serial``: :class:`SerialExecutor`, runs each task in this process when submitted (debugging,
  tests).
* ``processes``: ``concurrent.futures.ProcessPoolExecutor`` with ``workers`` processes (default:
  every core), started by 'fork' where available (see :func:`_process_context`), each limited to
  cores // workers BLAS threads (threadpoolctl), so that workers do not oversubscribe the cores,
  and each ending when the process that started it ends, even by ``kill -9`` (:func:`_die_with`).
* ``dask``: ``distributed.Client(...).get_executor()``, for a running scheduler
  (``scheduler='tcp://HOST:PORT'``, connection timeout :data:`CONNECT_TIMEOUT` seconds, which
  also bounds the wait for a first worker; the peer must first greet as a Dask scheduler does,
  :func:`_probe`, so that any other server is refused in one line within the timeout) or a
  ``LocalCluster`` on the loopback address (``scheduler='local'``, ``workers`` single-threaded
  worker processes) started and stopped here.
  Dask is the optional extra ``spectralshell[dask]``; nothing here imports it unless asked.
"""

from __future__ import annotations

import ctypes
import logging
import multiprocessing
import os
import re
import signal
import socket
import ssl
import struct
import sys
import threading
import time
from collections.abc import Iterator
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass

from .._validate import require_choice, require_int_in_range
from .._version import __version__
from ..errors import BackendUnavailable, ParameterError

EXECUTORS = ("serial", "processes", "dask")
CONNECT_TIMEOUT = 10.0  # seconds: connecting to a Dask scheduler, and waiting for its first worker
DASK_EXTRA = "executor 'dask' needs the optional extra: pip install spectralshell[dask]"
_ADDRESS = re.compile(r"^(tcp|tls)://[^\s/:]+:\d+/?$")
#: Largest first message accepted from a scheduler: its handshake (compression, Python and
#: pickle versions, msgpack in one or two frames) takes ~100 bytes.
HANDSHAKE_MAX = 65536


def _process_context():
    """'fork' where the platform has it (workers start at once, and scripts need no
    ``if __name__ == "__main__"`` guard; the parent's threads -- tqdm's monitor, Zarr's I/O loop --
    are not used by the tasks), else the platform default."""
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("fork" if "fork" in methods else None)


PR_SET_PDEATHSIG = 1  # prctl option (linux/prctl.h): a signal for this process when its parent dies
ORPHAN_POLL = 1.0  # seconds between parent checks where the kernel cannot signal (not Linux)


def _quit_quietly(signum: int, _frame) -> None:
    os._exit(128 + signum)


def _kernel_kills_orphan() -> bool:
    """Ask Linux to SIGKILL this process when its parent ends (``prctl(PR_SET_PDEATHSIG)``;
    strictly: when the parent's thread that started it ends -- :func:`open_pool`'s caller,
    which keeps it until the pool is shut down); False where that is unavailable."""
    if not sys.platform.startswith("linux"):
        return False
    libc = ctypes.CDLL(None, use_errno=True)
    return libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) == 0


def _exit_when_orphaned(parent: int) -> None:
    """End this process once ``parent`` is no longer its parent (it ended, and the process was
    re-parented), checking every ORPHAN_POLL seconds."""
    while os.getppid() == parent:
        time.sleep(ORPHAN_POLL)
    os._exit(128 + signal.SIGKILL)


def _die_with(parent: int) -> None:
    """End this worker when its parent ``parent`` (the sweep) ends, even by ``kill -9``: by the
    kernel on Linux, else by a watchdog thread polling ``os.getppid()``; at once if the parent
    ended before this was set up."""
    if not _kernel_kills_orphan():
        threading.Thread(target=_exit_when_orphaned, args=(parent,), daemon=True).start()
    if os.getppid() != parent:
        os._exit(128 + signal.SIGKILL)


def _init_worker(threads: int, parent: int) -> None:
    """Worker initialiser: at most ``threads`` BLAS/OpenMP threads in this process (a forked
    worker inherits the parent's thread pools, so environment variables would come too late),
    Ctrl-C (SIGINT to the whole process group) ends the worker at once and quietly -- the
    main process reports the interruption and keeps the finished chunks; a worker waiting for
    its next task would otherwise print a KeyboardInterrupt traceback -- and the worker ends
    with its ``parent`` process (:func:`_die_with`), so that none is left computing, holding
    memory, when the sweep is killed."""
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=threads)
    signal.signal(signal.SIGINT, _quit_quietly)
    _die_with(parent)


class SerialExecutor(Executor):
    """An Executor that runs each task in the calling process, at ``submit``."""

    def submit(self, fn, /, *args, **kwargs) -> Future:
        """Run ``fn(*args, **kwargs)`` now; the returned Future holds its result or exception."""
        future: Future = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except Exception as exc:  # noqa: BLE001 - delivered through the Future
            future.set_exception(exc)
        return future


@dataclass(frozen=True, eq=False)
class Pool:
    """An open executor: ``executor``, the number of tasks it runs at once (``slots``) and a
    one-line ``description``."""

    executor: Executor
    slots: int
    name: str
    description: str


def check_executor(executor: str, workers: int | None,
                   scheduler: str | None) -> tuple[str, int | None, str | None]:
    """Validated (executor, workers, scheduler), before anything starts.

    Raises
    ------
    ParameterError : unknown executor, workers < 1, a scheduler without executor 'dask', or a
        scheduler that is neither 'local' nor 'tcp://HOST:PORT' / 'tls://HOST:PORT'.
    """
    executor = require_choice("executor", executor, EXECUTORS)
    if workers is not None:
        workers = require_int_in_range("workers", workers, 1)
    if executor == "serial" and workers not in (None, 1):
        raise ParameterError(f"workers = {workers} is invalid with executor 'serial': must be 1 "
                             "or omitted")
    if scheduler is not None and executor != "dask":
        raise ParameterError(f"scheduler = {scheduler!r} is invalid with executor {executor!r}: "
                             "a scheduler needs executor 'dask'")
    if executor == "dask":
        scheduler = "local" if scheduler is None else scheduler
        if scheduler != "local" and not (isinstance(scheduler, str) and _ADDRESS.match(scheduler)):
            raise ParameterError(f"scheduler = {scheduler!r} is invalid: must be 'local' or an "
                                 "address tcp://HOST:PORT")
        if scheduler != "local" and workers is not None:
            raise ParameterError(f"workers = {workers} is invalid with scheduler {scheduler!r}: "
                                 "a running cluster has its own workers")
    return executor, workers, scheduler


def _worker_version() -> str:
    """spectralshell version of a Dask worker (run there by ``Client.run``)."""
    return __version__


def _import_distributed():
    try:
        import distributed
    except ImportError:
        raise BackendUnavailable(DASK_EXTRA) from None
    return distributed


def _open_socket(host: str, port: int, deadline: float) -> socket.socket:
    """A TCP connection to (host, port), retried while refused until ``deadline``
    (time.monotonic); OSError (or TimeoutError) when none is made by then."""
    while True:
        try:
            return socket.create_connection((host, port), timeout=max(deadline - time.monotonic(),
                                                                       0.01))
        except ConnectionRefusedError:
            if time.monotonic() + 0.1 >= deadline:
                raise
            time.sleep(0.1)


def _receive(sock: socket.socket, size: int, deadline: float) -> bytes:
    """Exactly ``size`` bytes from ``sock`` by ``deadline``; TimeoutError or EOFError if not."""
    data = b""
    while len(data) < size:
        sock.settimeout(max(deadline - time.monotonic(), 0.01))
        chunk = sock.recv(size - len(data))
        if not chunk:
            raise EOFError("closed")
        data += chunk
    return data


def _greeting_ok(message: bytes) -> bool:
    """Whether ``message`` is framed as Dask's first message (distributed.comm.tcp): a count of
    frames (1..16), their lengths, then exactly that many bytes."""
    if len(message) < 16:
        return False
    (count,) = struct.unpack_from("<Q", message)
    if not 1 <= count <= 16 or len(message) < 8 * (count + 1):
        return False
    lengths = struct.unpack_from(f"<{count}Q", message, 8)
    return 8 * (count + 1) + sum(lengths) == len(message)


def _probe(distributed, address: str, timeout: float) -> None:
    """Refuse (ParameterError) a peer at ``address`` that does not greet as a Dask scheduler
    within ``timeout`` s, before a Client connects to it.

    A Dask listener sends its handshake first: an 8-byte length, then that many bytes of frames
    (distributed.comm.tcp). Only a length up to HANDSHAKE_MAX is read, so a peer that answers
    something else (a web server, which waits for a request and gets the probe's timeout;
    garbage, whose first 8 bytes read as an absurd length) costs neither the Client's hang
    nor its allocation of that length. tls:// is probed through the client's TLS context of
    the Dask configuration.
    """
    scheme, rest = address.rstrip("/").split("://")
    host, port = rest.rsplit(":", 1)
    deadline = time.monotonic() + timeout
    try:
        sock = _open_socket(host, int(port), deadline)
    except OSError as exc:
        raise ParameterError(f"scheduler = {address!r} is unreachable: no Dask scheduler answered "
                             f"within {timeout:g} s ({type(exc).__name__})") from None
    try:
        if scheme == "tls":
            context = distributed.Security().get_connection_args("client")["ssl_context"] \
                or ssl.create_default_context()
            sock = context.wrap_socket(sock, server_hostname=host if context.check_hostname
                                       else None)
        (size,) = struct.unpack("<Q", _receive(sock, 8, deadline))
        if not 16 <= size <= HANDSHAKE_MAX:
            raise ValueError(f"a first message of {size} bytes")
        if not _greeting_ok(_receive(sock, size, deadline)):
            raise ValueError("a first message not framed as Dask's")
    except (OSError, EOFError, ValueError) as exc:  # TimeoutError and ssl.SSLError are OSErrors
        why = {TimeoutError: "no greeting", EOFError: "a closed connection",
               ValueError: str(exc)}.get(type(exc), type(exc).__name__)
        raise ParameterError(f"scheduler = {address!r} is not a Dask scheduler: the peer answered "
                             f"with {why} within {timeout:g} s, where a scheduler sends its "
                             "handshake at once") from None
    finally:
        sock.close()


def _connect(distributed, address: str):
    _probe(distributed, address, CONNECT_TIMEOUT)
    try:
        client = distributed.Client(address, timeout=f"{CONNECT_TIMEOUT}s", set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise ParameterError(f"scheduler = {address!r} is unreachable: no Dask scheduler answered "
                             f"within {CONNECT_TIMEOUT:g} s ({type(exc).__name__})") from None
    try:
        client.wait_for_workers(1, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError):
        client.close()
        raise ParameterError(f"scheduler = {address!r} has no workers after {CONNECT_TIMEOUT:g} s: "
                             f"start some with `dask worker {address}`") from None
    return client


def _check_versions(client, address: str) -> None:
    try:
        versions = client.run(_worker_version)
    except Exception as exc:  # noqa: BLE001 - e.g. spectralshell missing on a worker
        raise ParameterError(f"scheduler = {address!r}: its workers cannot run spectralshell "
                             f"({type(exc).__name__}: {exc}); install spectralshell "
                             f"{__version__} on every worker") from None
    wrong = {w: v for w, v in versions.items() if v != __version__}
    if wrong:
        worker, version = next(iter(wrong.items()))
        raise ParameterError(f"scheduler = {address!r}: worker {worker} runs spectralshell "
                             f"{version}, this client {__version__}: install the same version")


@contextmanager
def _dask_pool(scheduler: str, workers: int | None, max_tasks: int | None) -> Iterator[Pool]:
    distributed = _import_distributed()
    cluster = None
    if scheduler == "local":
        n = workers or os.cpu_count() or 1
        n = max(1, min(n, max_tasks)) if max_tasks else n
        cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                           host="127.0.0.1", dashboard_address=None,
                                           silence_logs=logging.ERROR)
        client = distributed.Client(cluster, set_as_default=False)
    else:
        client = _connect(distributed, scheduler)
    try:
        if cluster is None:
            _check_versions(client, scheduler)
        slots = max(1, sum(client.nthreads().values()))
        where = f"LocalCluster of {slots} workers" if cluster else f"Dask scheduler {scheduler}"
        yield Pool(client.get_executor(pure=False), slots, "dask", f"{where} ({slots} threads)")
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


@contextmanager
def open_pool(executor: str = "processes", *, workers: int | None = None,
              scheduler: str | None = None, max_tasks: int | None = None) -> Iterator[Pool]:
    """Start an executor and stop it on exit (on an error or Ctrl-C: without waiting for queued
    tasks). ``max_tasks`` caps the number of local processes started (no more than there are
    tasks). A LocalCluster starts its workers by 'spawn': a script that uses it needs the
    ``if __name__ == "__main__":`` guard.

    Raises
    ------
    ParameterError : invalid arguments (see :func:`check_executor`), or an unreachable scheduler.
    BackendUnavailable : executor 'dask' without the extra installed.
    """
    executor, workers, scheduler = check_executor(executor, workers, scheduler)
    if executor == "serial":
        yield Pool(SerialExecutor(), 1, "serial", "serial (this process)")
        return
    if executor == "dask":
        with _dask_pool(scheduler, workers, max_tasks) as pool:
            yield pool
        return
    n = workers or os.cpu_count() or 1
    n = max(1, min(n, max_tasks)) if max_tasks else n
    threads = max(1, (os.cpu_count() or 1) // n)
    others = set(multiprocessing.active_children())
    pool = ProcessPoolExecutor(max_workers=n, mp_context=_process_context(),
                               initializer=_init_worker, initargs=(threads, os.getpid()))
    try:
        yield Pool(pool, n, "processes", f"{n} processes")
    except BaseException:
        _stop_now(pool, others)
        raise
    pool.shutdown(wait=True)


def _stop_now(pool: ProcessPoolExecutor, others: set) -> None:
    """Stop ``pool`` without waiting for its tasks: cancel the queued ones, terminate its
    workers (the child processes not in ``others``, those alive before it started), and join
    its management thread, which then ends at once. Returning before that thread ends would
    leave it racing the interpreter's exit hook for its wake-up pipe (Python 3.11: the hook can
    write to the pipe just closed, and prints an OSError traceback after our last line)."""
    for child in set(multiprocessing.active_children()) - others:
        child.terminate()
    pool.shutdown(wait=True, cancel_futures=True)
