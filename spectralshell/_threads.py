"""One BLAS thread for a block of code, without threadpoolctl's per-call library scan."""

from __future__ import annotations

import functools

from threadpoolctl import ThreadpoolController


@functools.lru_cache(maxsize=1)
def _controller() -> ThreadpoolController:
    return ThreadpoolController()


def blas_libraries() -> str:
    """The BLAS/OpenMP libraries loaded in this process, as 'name version' joined by '; '."""
    return "; ".join(sorted({f"{d.get('internal_api')} {d.get('version')}"
                             for d in _controller().info()}))


def one_blas_thread():
    """Context limiting BLAS/OpenMP to one thread. The libraries are looked up once, at the first
    call (a new ``threadpoolctl.threadpool_limits`` scans the process's libraries on every call,
    ~3 ms; this costs ~11 us). On small and medium dense problems (orders up to a few hundred)
    OpenBLAS's threads only cost: the dense eig of the structured W of the sphere (balancing,
    norm, ?geev) took 1.1-2x longer on 2 threads than on 1 at orders 162-598 (2-core machine)."""
    return _controller().limit(limits=1)
