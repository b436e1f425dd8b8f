"""Phase of det T and tr(T^{-1} T') of block tridiagonal matrices T, batched over many T.

T has K diagonal blocks A_k (b x b), below-diagonal blocks L_k (block row k + 1, column k) and
above-diagonal blocks U_k (row k, column k + 1). Its block LU factorisation (Gaussian
elimination by blocks, partial pivoting inside each block's solve) gives the Schur complements

    S_0 = A_0,     S_k = A_k - L_{k-1} S_{k-1}^{-1} U_{k-1},     det T = prod_k det S_k,

in O(K b^3) instead of the O((K b)^3) of a dense factorisation. For T(s) whose diagonal blocks
depend on a variable s (derivatives A'_k) and whose couplings do not, differentiating the
recursion (forward mode) gives

    dS_0 = A'_0,   dS_k = A'_k + L_{k-1} S_{k-1}^{-1} dS_{k-1} S_{k-1}^{-1} U_{k-1},
    d/ds log det T = sum_k tr(S_k^{-1} dS_k)  ( = tr(T^{-1} T') ),

the logarithmic derivative of exactly the determinant whose phase is returned, so a Newton
iteration on it and a winding count of that phase see the same function. Every operation is
vectorised over a leading batch axis (many points s at once): the cost is K small batched
solves, whatever the batch size.

Caveat: no pivoting across blocks. A Schur complement S_k that is singular to working accuracy
where T is not (a leading principal block submatrix singular) is rounded the way a continued
fraction is near a zero denominator; the result is compared with dense LAPACK in
``validation/bench_exponents.py`` and tests/test_hill_exponents.py.
"""

from __future__ import annotations

import numpy as np


def log_det_phase_and_derivative(diag: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                                 ddiag: np.ndarray | None = None
                                 ) -> tuple[np.ndarray, np.ndarray | None]:
    """(det T / |det T|, tr(T^{-1} T') or None) for a batch of block tridiagonal T.

    Parameters
    ----------
    diag : (P, K, b, b) diagonal blocks A_k of P matrices.
    lower, upper : (K - 1, b, b) couplings L_k, U_k, shared by the batch.
    ddiag : (P, K, b, b) derivatives A'_k of the diagonal blocks (the couplings are constant),
        or None for the phase alone.

    Raises
    ------
    numpy.linalg.LinAlgError : a Schur complement is exactly singular.
    """
    schur = np.empty_like(diag)
    schur[:, 0] = diag[:, 0]
    steps = None if ddiag is None else np.empty_like(ddiag)  # S_k^{-1} dS_k
    d_schur = None if ddiag is None else ddiag[:, 0]
    for k in range(1, diag.shape[1]):
        inverse = np.linalg.inv(schur[:, k - 1])
        su = inverse @ upper[k - 1]
        schur[:, k] = diag[:, k] - lower[k - 1] @ su
        if steps is not None and ddiag is not None:
            steps[:, k - 1] = inverse @ d_schur
            d_schur = ddiag[:, k] + lower[k - 1] @ steps[:, k - 1] @ su
    sign = np.prod(np.linalg.slogdet(schur)[0], axis=1)
    if steps is None:
        return sign, None
    steps[:, -1] = np.linalg.solve(schur[:, -1], d_schur)
    return sign, np.trace(steps, axis1=-2, axis2=-1).sum(axis=1)
