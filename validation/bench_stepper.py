"""Benchmark: decay rate of the m = 2 natural mode to 1e-8 by time stepping; IMEX vs solve_ivp.

Problem: the sphere's semi-discrete system of degree m = 2, kappa = 1, nu = zeta = 0.01
(discretise/sphere_stepping.py; radial resolution chosen for a 1e-11 spatial error, so that
the error floor of the semi-discrete system is well below the target), started at
rest from the shape Yr_{2,0}, stepped to t = 40 and the decay rate Re gamma fitted from the
membrane coefficient on t in [4, 40] (solvers/rate_fit.py, samples every 0.05).
Reference for the error: the root of the exact dispersion relation (ss.natural_modes).

Package: every IMEX scheme of solvers/imex.py at halving steps. Baseline (same run, same system,
same samples and fit): scipy.integrate.solve_ivp with BDF and with Radau (constant Jacobian
passed), at decreasing rtol (atol = 1e-3 rtol). Both use one BLAS thread. Printed: error of the
decay rate against wall time (integration + fit) for each run, then the cheapest run of each
method reaching 1e-8 and the speed-up of the best IMEX run over the best solve_ivp run. Last, the
cost per step (SBDF3, 2000 steps) against the radial resolution n (state size about 2n).

Run: python validation/bench_stepper.py [--json-rows]   (about 2-4 minutes)
"""

from __future__ import annotations

import time

import numpy as np
from scipy.integrate import solve_ivp
from threadpoolctl import threadpool_limits

import spectralshell as ss
from _bench import growth, row  # validation/_bench.py (rows for bench_table.py)
from spectralshell.discretise.sphere_stepping import degree_system
from spectralshell.solvers.imex import SCHEMES
from spectralshell.solvers.rate_fit import fit_rate
from spectralshell.solvers.stepper import integrate

TARGET = 1e-8
T_END, SAMPLE, WINDOW = 40.0, 0.05, (4.0, 40.0)
M, ZETA = 2, 0.01


def fitted_rate(times, x) -> float:
    return fit_rate(times, x, window=WINDOW).growth_rate


def imex_run(system, y0, name, dt):
    every = max(1, int(round(SAMPLE / dt)))
    steps = int(round(T_END / dt))
    steps = steps // every * every
    start = time.perf_counter()
    run = integrate(system, y0, scheme=name, dt=T_END / steps, t_end=T_END, every=every,
                    observe=lambda y: y[system.membrane.start])
    rate = fitted_rate(run.times, run.values)
    return rate, time.perf_counter() - start, run.steps


def ivp_run(system, y0, method, rtol):
    L = system.L
    t_eval = np.linspace(0.0, T_END, int(round(T_END / SAMPLE)) + 1)
    start = time.perf_counter()
    sol = solve_ivp(lambda t, y: L @ y, (0.0, T_END), y0, method=method, t_eval=t_eval,
                    jac=L, rtol=rtol, atol=1e-3 * rtol)
    rate = fitted_rate(sol.t, sol.y[system.membrane.start])
    return rate, time.perf_counter() - start, sol.nfev


def main() -> None:
    exact = complex(ss.natural_modes("sphere", m=M, kappa=1.0, nu=ZETA, count=1).gamma[0])
    system = degree_system(m=M, kappa=1.0, nu=ZETA, tol=1e-11)
    y0 = system.initial_state([1.0, 0.0])
    print(f"m = {M}, zeta = {ZETA}: exact decay rate {exact.real:.15f} (dispersion relation); "
          f"state size {system.size} (n_radial = {system.n_inner}, spatial error "
          f"{system.spatial_error:.1e})\n")
    best: dict[str, tuple[float, float, str]] = {}
    with threadpool_limits(limits=1):
        print(f"{'method':<10} {'setting':>14} {'error':>10} {'seconds':>9} {'steps/nfev':>11}")
        for name, sch in SCHEMES.items():
            for dt in (0.04, 0.02, 0.01, 0.0075, 0.005, 0.0025):
                if sch.order == 1 and dt > 0.01:
                    continue
                rate, seconds, steps = imex_run(system, y0, name, dt)
                error = abs(rate - exact.real)
                print(f"{name:<10} {'dt = ' + format(dt, 'g'):>14} {error:10.2e} {seconds:9.3f} "
                      f"{steps:11d}")
                if error <= TARGET and seconds < best.get(name, (np.inf,))[0]:
                    best[name] = (seconds, error, f"dt = {dt:g}")
        for method, rtols in (("BDF", (1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-12)),
                              ("Radau", (1e-6, 1e-7, 1e-8, 1e-9, 1e-10))):
            for rtol in rtols:
                rate, seconds, nfev = ivp_run(system, y0, method, rtol)
                error = abs(rate - exact.real)
                print(f"{method:<10} {'rtol = ' + format(rtol, 'g'):>14} {error:10.2e} "
                      f"{seconds:9.3f} {nfev:11d}")
                if error <= TARGET and seconds < best.get(method, (np.inf,))[0]:
                    best[method] = (seconds, error, f"rtol = {rtol:g}")
        print(f"\ncheapest run reaching {TARGET:g} in the decay rate:")
        for name, (seconds, error, setting) in sorted(best.items(), key=lambda kv: kv[1][0]):
            print(f"  {name:<8} {setting:<14} {seconds:8.3f} s   error {error:.1e}")
        imex = {k: v for k, v in best.items() if k in SCHEMES}
        ivp = {k: v for k, v in best.items() if k not in SCHEMES}
        if imex and ivp:
            a = min(imex, key=lambda k: imex[k][0])
            b = min(ivp, key=lambda k: ivp[k][0])
            print(f"speed-up of the best IMEX run over the best solve_ivp run: "
                  f"{ivp[b][0] / imex[a][0]:.1f}x")
            row(task=f"sphere m = {M}, zeta = {ZETA}: decay rate to {TARGET:g} by time stepping",
                package_s=imex[a][0], baseline=f"scipy solve_ivp {b} ({ivp[b][2]})",
                baseline_s=ivp[b][0], error=imex[a][1], baseline_error=ivp[b][1],
                note=f"{a}, {imex[a][2]}; error vs the dispersion relation")
        else:
            print("no speed-up computed: a method family did not reach the target")

        print("\ncost per step against the radial resolution (SBDF3, 2000 steps, dt = 0.005):")
        print(f"{'n_radial':>8} {'size':>6} {'us/step':>9} {'us/step/size':>13}")
        sizes, seconds = [], []
        for n in (16, 24, 32, 48, 64, 96, 128, 192):
            sys_n = degree_system(m=M, kappa=1.0, nu=ZETA, n_radial=n)
            y = sys_n.initial_state([1.0, 0.0])
            integrate(sys_n, y, scheme="SBDF3", dt=0.005, t_end=0.05)   # factorise, warm up
            start = time.perf_counter()
            integrate(sys_n, y, scheme="SBDF3", dt=0.005, t_end=10.0, every=1000)
            per_step = (time.perf_counter() - start) / 2000 * 1e6
            print(f"{n:8d} {sys_n.size:6d} {per_step:9.1f} {per_step / sys_n.size:13.3f}")
            sizes.append(n)
            seconds.append(per_step * 1e-6)
        p = growth(label="sphere IMEX step (SBDF3)", parameter="n_radial", values=sizes,
                   seconds=seconds, note="dense LU solve per step: O(n^2) asymptotically")
        print(f"fitted cost growth per step ~ n_radial^{p:.2f}")


if __name__ == "__main__":
    main()
