"""The package's version, and the versions of what its numbers are computed with (provenance)."""

from __future__ import annotations

import functools
import platform

__version__ = "0.1.0"


@functools.lru_cache(maxsize=1)
def _libraries() -> tuple[tuple[str, str], ...]:
    import mpmath
    import numpy
    import scipy
    import scipy.linalg  # noqa: F401  (loads scipy's BLAS before the thread controller looks)

    from ._threads import blas_libraries

    return (("python", platform.python_version()), ("numpy", numpy.__version__),
            ("scipy", scipy.__version__), ("mpmath", mpmath.__version__),
            ("blas", blas_libraries()))


def libraries() -> dict[str, str]:
    """Versions of Python, numpy, scipy, mpmath and the BLAS/LAPACK numpy and scipy load.

    Results agree across builds of these to their error estimates, not bit for bit: dense
    eigensolvers and factorisations round differently between BLAS builds and versions
    (differences of ~cond(A) eps), so a reproduction of a stored result needs these too.
    Looked up once per process.
    """
    return dict(_libraries())


def libraries_line() -> str:
    """:func:`libraries` as one line, 'python 3.11.7, numpy 2.4.6, ...' (report headers)."""
    return ", ".join(f"{k} {v}" for k, v in _libraries())


def stamp() -> dict[str, object]:
    """The part of every provenance that names the software: package, version, libraries."""
    return {"package": "spectralshell", "version": __version__, "libraries": libraries()}
