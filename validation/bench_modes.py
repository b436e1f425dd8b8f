"""Benchmark: one natural mode of the sphere (m = 2, zeta = 0.01) by the dispersion relation
against the radial Chebyshev eigenproblem, each with its achieved error, in one run.

Reference: the dispersion-relation root polished with mpmath at 30 digits. The Chebyshev
baseline is run at the smallest resolution (n_inner = n_outer = n, complex-scaled exterior) whose
error is below 1e-8, found by scanning n upwards.
"""

from __future__ import annotations

import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import spectralshell as ss  # noqa: E402
from _bench import row  # noqa: E402
from spectralshell.discretise.sphere_radial import radial_operators  # noqa: E402
from spectralshell.solvers.eigen import finite_eigenvalues  # noqa: E402

M, ZETA = 2, 0.01


def timed(fn, repeat: int):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def chebyshev_mode(n: int, target: complex) -> complex:
    ops = radial_operators(m=M, nu=ZETA, n_inner=n, n_outer=n, exterior_angle=-np.pi / 3)
    values = finite_eigenvalues(*ops.pencil(1.0))
    return complex(values[np.argmin(np.abs(values - target))])


def main() -> None:
    ref = complex(ss.natural_modes("sphere", m=M, zeta=ZETA, count=1, precision=30).gamma[0])
    t_disp, res = timed(lambda: ss.natural_modes("sphere", m=M, zeta=ZETA, count=1), 50)
    err_disp = abs(res.gamma[0] - ref)
    for n in range(8, 81, 4):
        err = abs(chebyshev_mode(n, ref) - ref)
        if err < 1e-8 * abs(ref):
            break
    t_cheb, value = timed(lambda: chebyshev_mode(n, ref), 5)
    err_cheb = abs(value - ref)
    print(f"sphere natural mode m = {M}, zeta = {ZETA}: gamma = {ref:.15g} (mpmath, 30 digits)")
    print(f"{'method':<44} {'time s':>10} {'error':>9}")
    print(f"{'dispersion relation (Newton in beta)':<44} {t_disp:10.2e} {err_disp:9.1e}")
    print(f"{'radial Chebyshev eigenproblem, n = ' + str(n):<44} {t_cheb:10.2e} {err_cheb:9.1e}")
    print(f"ratio {t_cheb / t_disp:.0f}x (target >= 1000x)")
    row(task=f"sphere natural mode, m = {M}, zeta = {ZETA} (dispersion relation, Newton in beta)",
        package_s=t_disp, baseline=f"radial Chebyshev eigenproblem, n = {n}", baseline_s=t_cheb,
        error=err_disp, baseline_error=err_cheb, note="errors against the 30-digit mpmath root")


if __name__ == "__main__":
    main()
