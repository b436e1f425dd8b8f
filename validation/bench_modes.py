"""Benchmark: one natural mode of the sphere (m = 2, zeta = 0.01) by the dispersion relation
against the radial Chebyshev eigenproblem, each with its achieved error, in one run.

Reference: the dispersion-relation root polished with mpmath at 30 digits. The Chebyshev
baseline is run at the smallest resolution (n_inner = n_outer = n, complex-scaled exterior) whose
error is below 1e-8, found by scanning n upwards.

Ratio ceiling: the same API call at nu = 0 (whose modes are the closed form +-i lambda0, (7.4):
no root is sought) costs what every call pays for validating the parameters and building the
result with its error estimates. The baseline's time divided by that floor bounds the ratio any
root finder behind ``ss.natural_modes`` could reach.
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
    t_floor, _ = timed(lambda: ss.natural_modes("sphere", m=M, kappa=1.0, nu=0.0, count=1), 50)
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
    print(f"{'the same API call at nu = 0 (no root finding)':<44} {t_floor:10.2e}")
    ceiling = t_cheb / t_floor
    print(f"ratio {t_cheb / t_disp:.0f}x (target >= 1000x; ceiling {ceiling:.0f}x set by the API "
          "call's own cost)")
    row(task=f"sphere natural mode, m = {M}, zeta = {ZETA} (dispersion relation, Newton in beta)",
        package_s=t_disp, baseline=f"radial Chebyshev eigenproblem, n = {n}", baseline_s=t_cheb,
        error=err_disp, baseline_error=err_cheb,
        note=f"errors against the 30-digit mpmath root; ratio ceiling {ceiling:.0f}x: the same "
             f"call at nu = 0, which seeks no root, takes {t_floor * 1e6:.0f} us")


if __name__ == "__main__":
    main()
