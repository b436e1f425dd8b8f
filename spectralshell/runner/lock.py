"""One writer per sweep output: an advisory lock on a hidden file next to it.

``map.zarr`` (or ``map.nc``) is written only while ``.map.zarr.lock`` in the same directory is
held with ``flock``. The kernel releases the lock when its holder ends in any way (``kill -9``
included), so a lock is never left stale; the holder writes its pid, host and start time into
the file for the message the next writer gets. The file is removed by the holder on release.
The lock is advisory: it keeps spectralshell processes apart, not other programs, and it holds
on a local file system (flock over NFS depends on the client).
"""

from __future__ import annotations

import fcntl
import json
import os
import socket
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import StoreBusy


def lock_path(out: Path) -> Path:
    """The lock file of the output ``out``: ``.NAME.lock`` in its directory."""
    return out.parent / f".{out.name}.lock"


def _holder(fd: int) -> str:
    """'pid N on HOST, since TIME' from a held lock file (its holder may not have written it
    yet)."""
    try:
        info = json.loads(os.pread(fd, 4096, 0))
        since = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(info["since"]))
        return f"pid {info['pid']} on {info['host']}, since {since}"
    except (ValueError, KeyError, TypeError, OSError):
        return "pid unknown: it is just starting"


def _same_file(fd: int, path: Path) -> bool:
    """``fd`` is still the file at ``path`` (a releasing holder unlinks it)."""
    try:
        return os.path.samestat(os.fstat(fd), os.stat(path))
    except FileNotFoundError:
        return False


def _acquire(out: Path) -> int:
    """An open descriptor of ``out``'s lock file, locked exclusively by this process.

    Raises
    ------
    StoreBusy : another process holds the lock.
    """
    path = lock_path(out)
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = _holder(fd)
            os.close(fd)
            raise StoreBusy(f"out = {str(out)!r} is being written by another process "
                            f"({holder}): wait for it to finish or choose another out") from None
        if _same_file(fd, path):
            return fd
        os.close(fd)  # we locked a file its holder had just removed: take the new one


@contextmanager
def writer_lock(out: Path) -> Iterator[None]:
    """Hold the lock of the output ``out`` for the block, then remove it.

    Raises
    ------
    StoreBusy : another process is writing ``out``.
    """
    fd = _acquire(out)
    try:
        info = {"pid": os.getpid(), "host": socket.gethostname(), "since": time.time()}
        os.ftruncate(fd, 0)
        os.pwrite(fd, json.dumps(info).encode(), 0)
        yield
    finally:
        os.unlink(lock_path(out))
        os.close(fd)
