"""Benchmark: resolution and time of the radial Chebyshev natural modes for 1e-8 relative error.

Package: ``radial_operators`` (discretise/sphere_radial.py) + ``finite_eigenvalues``
(solvers/eigen.py), kappa = 1, nu = zeta, exterior_scale from ``exterior_scale_hint`` with
|s| of the target mode. Baseline (same run): the root of the exact dispersion relation
(det D(s) = 0 poloidal, D_Phi(s) = 0 toroidal; result file of derivations/sphere_linear.py),
mpmath secant at 30 digits from a 3-digit seed; it is also the reference for the error.

For every (component, m, zeta, exterior angle) the script finds the smallest n_inner (with
n_outer = 120) and the smallest n_outer (with n_inner = 80), in steps of 4, from which the error
stays below 1e-8 for the next two steps; it then raises both together until the pair itself
passes. Printed: n_inner, n_outer, the error there, the wall time of one assembly + QZ at that
resolution (best of 3) and of the mpmath root. angle 0 is the real (time-stepper) exterior; it
is skipped at zeta = 1, where it does not resolve the modes (see test_real_map_fails_honestly).
Run: python validation/bench_modes_chebyshev_resolution.py   (about 30 s with one BLAS thread)
"""

from __future__ import annotations

import time

import mpmath as mp
import numpy as np

from _bench import quick, row
from spectralshell.discretise.sphere_radial import exterior_scale_hint, radial_operators
from spectralshell.solvers.eigen import finite_eigenvalues

TOL = 1e-8
SEEDS = {
    "poloidal": {(2, 1e-3): -0.045 + 2.148j, (2, 1e-2): -0.156 + 2.056j,
                 (2, 1e-1): -0.663 + 1.814j, (2, 1.0): -0.935 + 0.222j,
                 (3, 1e-3): -0.085 + 4.059j, (3, 1e-2): -0.292 + 3.884j,
                 (3, 1e-1): -1.19 + 3.355j, (3, 1.0): -1.325 + 0.0502j,
                 (4, 1e-3): -0.134 + 6.196j, (4, 1e-2): -0.460 + 5.920j,
                 (4, 1e-1): -1.858 + 5.032j, (4, 1.0): -1.545 + 0.00383j},
    "toroidal": {(2, 1e-3): -7.939 + 13.747j, (2, 1e-2): -3.704 + 6.381j,
                 (2, 1e-1): -1.900 + 2.963j, (2, 1.0): -0.8816 + 0.01276j,
                 (3, 1e-3): -14.62 + 25.32j, (3, 1e-2): -6.826 + 11.754j,
                 (3, 1e-1): -3.556 + 5.441j, (3, 1.0): -1.544 + 0.00382j,
                 (4, 1e-3): -21.64 + 37.47j, (4, 1e-2): -10.108 + 17.392j,
                 (4, 1e-1): -5.347 + 8.041j, (4, 1.0): -2.1233 + 0.000526j}}


def dispersion(component: str, s, m: int, nu: float):
    """det D(s) or D_Phi(s) of derivations/sphere_linear_result.md, kappa = 1, mpmath."""
    mp.mp.dps = 30
    s = mp.mpc(s)
    beta = mp.sqrt(s / nu)
    P = beta * mp.besseli(m + 1.5, beta) / mp.besseli(m + 0.5, beta)
    Q = beta * mp.besselk(m - 0.5, beta) / mp.besselk(m + 0.5, beta)
    q = (m - 1) * (m + 2)
    if component == "toroidal":
        return nu * s * (2 * m + 1 + P + Q) + q
    yy = s**2 * (mp.mpf(2 * m + 1) / (m * (m + 1)) + m / ((m + 1) * Q) + (m + 1) / (m * P)) + q
    yp = s**2 * (m / Q - (m + 1) / P)
    return yy * (s**2 * (1 / Q + 1 / P) + q) - yp**2 / (m * (m + 1))


def exact_root(component: str, m: int, nu: float, seed: complex) -> complex:
    x0 = mp.mpc(seed)
    return complex(mp.findroot(lambda s: dispersion(component, s, m, nu),
                               (x0, x0 * (1 + mp.mpf("1e-6"))), solver="secant",
                               tol=mp.mpf(10) ** -50, verify=False))


def error(component, m, nu, n_inner, n_outer, angle, exact) -> float:
    ops = radial_operators(m=m, nu=nu, component=component, n_inner=n_inner, n_outer=n_outer,
                           exterior_angle=angle,
                           exterior_scale=exterior_scale_hint(nu=nu, s_scale=abs(exact)))
    values = finite_eigenvalues(*ops.pencil(1.0))
    return float(np.min(np.abs(values - exact)) / abs(exact))


def smallest(err_of_n, start=8, stop=200, step=4) -> int | None:
    for n in range(start, stop, step):
        if all(err_of_n(n + k * step) < TOL for k in range(3)):
            return n
    return None


def best_time(fn, repeat: int = 3) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    print(f"{'component':9s} {'m':>2s} {'zeta':>6s} {'angle':>6s} {'n_in':>5s} {'n_out':>5s} "
          f"{'size':>5s} {'error':>8s} {'t_cheb':>8s} {'t_mpmath':>8s}")
    for component, seeds in SEEDS.items():
        if quick():  # a smoke run (validation/_bench.py): the first mode alone
            seeds = dict(list(seeds.items())[:1])
        for (m, zeta), seed in seeds.items():
            t_mp = best_time(lambda: exact_root(component, m, zeta, seed), repeat=1)
            exact = exact_root(component, m, zeta, seed)
            for angle in (0.0, -np.pi / 3):
                if angle == 0.0 and zeta == 1.0:
                    continue
                ni = smallest(lambda n: error(component, m, zeta, n, 120, angle, exact))
                no = smallest(lambda n: error(component, m, zeta, 80, n, angle, exact))
                if ni is None or no is None:
                    print(f"{component:9s} {m:2d} {zeta:6.0e} {angle:6.3f}  not reached")
                    continue
                while error(component, m, zeta, ni, no, angle, exact) >= TOL:
                    ni, no = ni + 4, no + 4
                err = error(component, m, zeta, ni, no, angle, exact)
                ops = radial_operators(m=m, nu=zeta, component=component, n_inner=ni,
                                       n_outer=no, exterior_angle=angle)
                t = best_time(lambda: finite_eigenvalues(*radial_operators(
                    m=m, nu=zeta, component=component, n_inner=ni, n_outer=no,
                    exterior_angle=angle,
                    exterior_scale=exterior_scale_hint(nu=zeta, s_scale=abs(exact))).pencil(1.0)))
                print(f"{component:9s} {m:2d} {zeta:6.0e} {angle:6.3f} {ni:5d} {no:5d} "
                      f"{ops.size:5d} {err:8.1e} {t:7.3f}s {t_mp:7.3f}s", flush=True)
                row(task=f"{component} natural modes, m = {m}, zeta = {zeta:g}, exterior angle "
                         f"{angle:.3f}: radial Chebyshev n = {ni}/{no} (assembly + QZ, all modes)",
                    package_s=t, baseline="mpmath secant on the exact dispersion relation (one root)",
                    baseline_s=t_mp, error=err, note="relative error of the mode against that root")


if __name__ == "__main__":
    main()
