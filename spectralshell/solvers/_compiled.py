"""The compiled kernel ``_schur`` with SciPy's BLAS and LAPACK routines handed over to it, once,
at import: the zgemv of its block sweeps (:mod:`.shift_invert`) and the zgetrf, zgetri, zgetrs
and zgemm of its rotated log det (:mod:`.contour`), the very routines ``scipy.linalg`` calls.
Modules that call the kernel import it from here."""

import scipy.linalg.cython_blas
import scipy.linalg.cython_lapack

from . import _schur

_schur.use_scipy(scipy.linalg.cython_blas.__pyx_capi__["zgemv"],
                 *(scipy.linalg.cython_lapack.__pyx_capi__[name]
                   for name in ("zgetrf", "zgetri", "zgetrs")),
                 scipy.linalg.cython_blas.__pyx_capi__["zgemm"])

__all__ = ["_schur"]
