"""Benchmark: Floquet exponents of the viscous models (solvers/hill_exponents.py), block LU
against dense linear algebra.

For the sphere (m = 3, kappa = 0.02, nu = 0.006), the fibre (m = 3, kappa = 0.02, nu = 2e-4)
and the cochlea (M = 8 cosine modes, kappa = 0.5, nu = 1e-3, alpha = 1), all at tau = 0.3: the
whole exponent computation (continuation from the natural modes, argument-principle count,
refinement in N) with the determinant's phase and tr(T^{-1} T') from the block LU of the
block-tridiagonal truncation (the package), and the same algorithm with dense LAPACK solves and
slogdet of the whole (K b) x (K b) matrix (``dense=True``, the previous implementation), in the
same run. Error = largest distance (mod i) from the exponents to those at twice the final
truncation N (block LU, fixed N); the two lists are also compared with each other. Beside it,
the cost of one Newton step (one tr(T^{-1} T')) at the final N.

The large cochlea (M = 16, 32 cosine modes at a fixed N = 40, ``--large``): CPU seconds of the
whole computation (the machine is shared: wall time is not the package's), and of its
argument-principle count of the region, guarded against 2 pi between samples by
tr(T^{-1} T') at the nodes (the package) against the previous count, which sampled the phase
alone (baseline, same contour, same run); the count's error is its distance from the number of
exponents listed there (each a verified root, one per natural mode and its conjugate). Before
this count and the joint continuation of both windows (2026-12-04, one run each on a loaded
machine), the previous version took 12.2 s CPU at M = 16 (32 exponents), and at M = 32 refused
after ~100 s ('counts 32 ... but 59 were found': its count aliased 64 to 32, and the windows'
continuations had each found three exponents twice and lost others). After (one run each,
same day, loaded): M = 16 13.9 s CPU (exponents equal to 1e-15); M = 32 all 64 exponents in
88 s CPU (error estimate 3.4e-10), the guarded count 64 in 19 s CPU against the unguarded 32 in
32 s. A refusal (ConvergenceError) is printed in place of a row.

Times are the best of 3 (the dense cochlea: one call), one BLAS thread. (The first version of
the module, dense throughout, without batched counts and re-continuing at every N, took 1.2 s
for the sphere and 60 s for the cochlea; measured once, 2026-12-03.)
Run: python validation/bench_exponents.py [--large] [--json-rows]
"""

from __future__ import annotations

import os
import sys
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import spectralshell as ss  # noqa: E402
from _bench import best_time, quick, row  # noqa: E402
from spectralshell.errors import ConvergenceError  # noqa: E402
from spectralshell.models.registry import hill_system  # noqa: E402
from spectralshell.params.registry import make_params  # noqa: E402
from spectralshell.solvers.exponents import distance  # noqa: E402
from spectralshell.solvers.hill_exponents import (  # noqa: E402
    _in_strip, _slit_count, hill_exponents, pencil_family, slit_width)

TAU = 0.3
CASES = [("sphere", dict(m=3, kappa=0.02, nu=0.006)),
         ("fibre", dict(m=3, kappa=0.02, nu=2e-4)),
         ("cochlea", dict(kappa=0.5, nu=1e-3, alpha=1.0, n_spatial=8))]


def newton_step_times(system, n: int) -> tuple[float, float]:
    """Seconds of one tr(T^{-1} T') at truncation n: block LU, dense solve."""
    g = 0.1 + 0.05j
    pencil, dT = pencil_family(system, "subharmonic", n)(TAU)
    return (best_time(lambda: pencil.log_derivatives(np.array([g])), repeat=5)[0],
            best_time(lambda: np.trace(np.linalg.solve(pencil(g), dT(g))), repeat=3)[0])


def cpu_time(fn):
    """(CPU seconds of one call, its result)."""
    start = time.process_time()
    out = fn()
    return time.process_time() - start, out


def large_cochlea(n_spatial: int, n_temporal: int = 40) -> None:
    """The large cochlea rows (module notes): the exponents at M = ``n_spatial``, N = 40, and
    their count, guarded against unguarded."""
    params = dict(kappa=0.5, nu=1e-3, alpha=1.0, n_spatial=n_spatial)
    system = hill_system(make_params("cochlea", params))
    seeds = ss.natural_modes("cochlea", **params).gamma
    try:
        t_all, res = cpu_time(lambda: hill_exponents(system, TAU, seeds, n_temporal=n_temporal))
    except ConvergenceError as exc:
        print(f"  cochlea M = {n_spatial}, N = {n_temporal}: refused: {exc}", flush=True)
        return
    T, dT = pencil_family(system, "harmonic", n_temporal)(TAU)
    lo, hi = res.complete_in
    near = _in_strip(np.concatenate([res.gamma, seeds, np.conj(seeds)]))
    args = (T, lo, hi, slit_width(res.gamma, system.branch_point), system.branch_point, (), near)
    t_count, (_, count) = cpu_time(lambda: _slit_count(*args, dT=dT))
    t_plain, (_, plain) = cpu_time(lambda: _slit_count(*args))
    listed = len(res.gamma)
    print(f"  cochlea M = {n_spatial}, N = {n_temporal}: {listed} exponents in {t_all:.1f} s CPU "
          f"(error estimate {res.error_estimate:.1e}); count {count} in {t_count:.1f} s CPU, "
          f"unguarded count {plain} in {t_plain:.1f} s CPU", flush=True)
    row(task=f"cochlea M={n_spatial} N={n_temporal}: argument-principle count of the exponents' "
             f"region at tau = {TAU} (CPU s; error = |count - {listed} listed|)",
        package_s=t_count, baseline="the previous count: sampled phase alone, 16 per edge",
        baseline_s=t_plain, error=abs(count - listed), baseline_error=abs(plain - listed),
        note=f"whole exponent computation {t_all:.1f} s CPU, error estimate "
             f"{res.error_estimate:.1e}")


def main() -> None:
    print(f"Floquet exponents at tau = {TAU}: block LU (package) vs dense LU (baseline)")
    for model, params in CASES[:1] if quick() else CASES:  # --quick: a smoke run (_bench.py)
        system = hill_system(make_params(model, params))
        seeds = ss.natural_modes(model, **params).gamma
        t_block, block = best_time(lambda: hill_exponents(system, TAU, seeds))
        t_dense, dense = best_time(lambda: hill_exponents(system, TAU, seeds, dense=True),
                                   repeat=1 if model == "cochlea" else 3)
        reference = hill_exponents(system, TAU, seeds, n_temporal=2 * block.n_temporal).gamma
        error, dense_error = distance(block.gamma, reference), distance(dense.gamma, reference)
        between = distance(block.gamma, dense.gamma) if len(block.gamma) == len(dense.gamma) else np.inf
        step_block, step_dense = newton_step_times(system, block.n_temporal)
        label = f"{model} {' '.join(f'{k}={v:g}' for k, v in params.items())}"
        print(f"  {label:<44} N = {block.n_temporal:3d}  {len(block.gamma)} exponents  "
              f"block {t_block:7.3f} s (error {error:.1e})  dense {t_dense:7.3f} s "
              f"(error {dense_error:.1e})  x{t_dense / t_block:5.1f}  |block - dense| {between:.1e}  "
              f"one Newton step {step_block * 1e3:.2f} ms vs {step_dense * 1e3:.2f} ms", flush=True)
        row(task=f"{label}: Floquet exponents at tau = {TAU} (tol 1e-10), N = {block.n_temporal}, "
                 f"{len(block.gamma)} exponents (error = distance to those at N = "
                 f"{2 * block.n_temporal}; block vs dense {between:.1e})",
            package_s=t_block, baseline="the same algorithm with dense LU / slogdet (dense=True)",
            baseline_s=t_dense, error=error, baseline_error=dense_error)


if __name__ == "__main__":
    if "--large" in sys.argv:
        for m in (16, 32):
            large_cochlea(m)
    else:
        main()
