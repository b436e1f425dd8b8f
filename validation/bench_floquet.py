"""Benchmark: damped Mathieu tau_min, package against two named baselines in the same run.

* package: ``ss.floquet`` (structured half-size eigenproblem, truncation grown to ``tol``);
* dense: ``scipy.linalg.eig(A, B)`` of the same real-form Hill pencil at the package's final N
  (the thesis's method); equal error by construction (same truncation);
* monodromy: the multiplier -1 located by ``brentq`` on det(M(tau) + I), M from ``solve_ivp``
  (DOP853, rtol 1e-12), bracket +-0.02 around the answer, xtol = tol.

Errors are against a reference from dense QZ at N = 80. Also: structured vs dense at fixed
N = 40, 80, 160 (Mathieu; 40, 80 for the sphere and fibre), with the time of the eigenvalue
step on the half-size W alone (the compiled tridiagonal kernel for Mathieu, LAPACK ?geev for
the b = 2 models: the structured path's floor, and the ratio it caps), Fig 6.13 map points
(marginal_tau with tau_max = 1/2 against QZ of the same two truncations), and the wall time of
a 301-point two-kind Ince-Strutt diagram.
Run: python validation/bench_floquet.py
"""

from __future__ import annotations

import time

import numpy as np
import scipy.linalg as sla
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import spectralshell as ss
from _bench import best_time, row
from spectralshell._threads import one_blas_thread
from spectralshell.discretise.hill import assemble
from spectralshell.models import fibre, sphere
from spectralshell.models.mathieu import hill_system
from spectralshell.solvers import tridiagonal
from spectralshell.solvers.half_product import (block_inverses, dense_half_product,
                                                tridiagonal_half_product)
from spectralshell.solvers.marginal import dense_taus, preferred_form, solve_truncation

KAPPA, NU, KIND = 0.26, 0.1, "subharmonic"


def monodromy_det(tau: float, rtol: float = 1e-12) -> float:
    """det(M(tau) + I) of the Mathieu monodromy matrix M (DOP853 at ``rtol``, atol 1e-14): zero
    where a multiplier is -1, the subharmonic boundary."""
    def rhs(t, y):
        return [y[1], -NU * y[1] - KAPPA * (1 + 2 * tau * np.sin(t)) * y[0]]
    cols = [solve_ivp(rhs, (0, 2 * np.pi), y0, method="DOP853", rtol=rtol, atol=1e-14).y[:, -1]
            for y0 in ([1.0, 0.0], [0.0, 1.0])]
    return float(np.linalg.det(np.column_stack(cols) + np.eye(2)))


def dense_tau_min(system, n: int) -> float:
    hill = assemble(system, KIND, n, "real")
    A, B = hill.A.toarray(), hill.B.toarray()
    values = sla.eig(A, B)[0]
    values = values[np.isfinite(values) & (values.imag == 0) & (values.real > 0)].real
    return float(values.min())


def map_points() -> None:
    """One Fig 6.13 map point per kind (sphere, cardiac atrium; marginal_tau with tau_max = 1/2
    and tol = 1e-8 as ss.tau_map runs it, two truncations) against QZ of the same two
    truncations (scipy.linalg.eigvals(A, B) of the real-form pencils, assembled)."""
    from spectralshell.models.registry import hill_system
    from spectralshell.params.physical import CARDIAC, sphere_forced_params
    from spectralshell.params.registry import make_params
    from spectralshell.solvers.marginal import marginal_tau
    physical = {k: CARDIAC[k] for k in ("rho", "mu", "radius")}
    print("Fig 6.13 map points: marginal_tau(tau_max = 1/2) vs QZ of the same two truncations")
    for sigma, bpm, m in ((5e3, 300.0, 3), (1e4, 150.0, 3), (2e4, 50.0, 6)):
        params = sphere_forced_params({**physical, "sigma": sigma, "bpm": bpm, "m": m})
        system = hill_system(make_params("sphere", params))  # as tau_map's sweep builds it
        for kind in ("harmonic", "subharmonic"):
            t_pkg, res = best_time(lambda: marginal_tau(system, kind, tol=1e-8, tau_max=0.5),
                                   3 if system.n_resonant < 60 else 1)
            pencils = [assemble(system, kind, n, "real") for n in (res.n_previous, res.n_temporal)]
            dense = [(h.A.toarray(), h.B.toarray()) for h in pencils]
            t_qz, taus = best_time(lambda: [dense_taus_of(A, B) for A, B in dense], repeat=1)
            last = taus[-1][(taus[-1] >= 0) & (taus[-1] <= 0.5)]
            if res.tau_min is None:
                error = None if not last.size else float("inf")
            else:
                error = abs(res.tau_min - last[0]) if last.size else float("inf")
            print(f"  sigma {sigma:g} dyn/cm, {bpm:g} bpm, m = {m}, {kind}: N = {res.n_previous}, "
                  f"{res.n_temporal}; tau_min {res.tau_min}; package {t_pkg:.3e} s, QZ "
                  f"{t_qz:.3e} s, ratio {t_qz / t_pkg:.1f}, error {error}", flush=True)
            row(task=f"Fig 6.13 map point sigma {sigma:g} dyn/cm, {bpm:g} bpm, m = {m}, {kind}: "
                     f"tau_min <= 1/2 (tol 1e-8), N = {res.n_previous}, {res.n_temporal}",
                package_s=t_pkg, baseline="QZ (scipy.linalg.eigvals(A, B)) of the same two "
                "truncations", baseline_s=t_qz, error=error,
                note="error = |tau_min - QZ's at the final N|; none <= 1/2 in both: no error")


def eigen_step_time(half) -> float:
    """Time of the package's eigenvalue step on the half-size W alone: the compiled kernel on
    W's diagonals for a scalar model (tridiagonal W), else LAPACK ?geev of the dense W on one
    BLAS thread (as marginal.ONE_THREAD_ORDERS runs it)."""
    inv = block_inverses(half)
    if half.diag.shape[1] == 1:
        d, p = tridiagonal_half_product(half, inv)
        return best_time(lambda: tridiagonal.eigenvalues(d, p), repeat=7)[0]
    W = dense_half_product(half, inv)
    with one_blas_thread():
        return best_time(lambda: sla.eigvals(W, check_finite=False), repeat=5)[0]


def dense_taus_of(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Real tau of the pencil (A, B) by QZ (the thesis's method), either sign."""
    values = sla.eigvals(A, B)
    values = values[np.isfinite(values)]
    return np.sort(values.real[np.abs(values.imag) <= 1e-9 * np.abs(values)])


def main() -> None:
    system = hill_system(kappa=KAPPA, nu=NU)
    ref = float(min(t for t in dense_taus(assemble(system, KIND, 80, "real")) if t > 0))
    print(f"damped Mathieu, kappa = {KAPPA}, nu = {NU}, {KIND} tau_min; reference {ref:.15f} (QZ, N = 80)\n")
    print(f"{'tol':>8} {'N':>4} | {'package s':>10} {'error':>8} | {'dense eig s':>11} {'error':>8} "
          f"{'ratio':>6} | {'monodromy s':>11} {'error':>8} {'ratio':>7}")
    for tol in (1e-6, 1e-8, 1e-10, 1e-12):
        t_pkg, res = best_time(lambda: ss.floquet("mathieu", kind=KIND, tol=tol, kappa=KAPPA, nu=NU), 5)
        m = res.subharmonic
        t_dense, tau_dense = best_time(lambda: dense_tau_min(system, m.n_temporal), 5)
        t_mono, tau_mono = best_time(lambda: brentq(monodromy_det, ref - 0.02, ref + 0.02,
                                                    xtol=tol), repeat=1)
        print(f"{tol:8.0e} {m.n_temporal:4d} | {t_pkg:10.2e} {abs(m.tau_min - ref):8.1e} | "
              f"{t_dense:11.2e} {abs(tau_dense - ref):8.1e} {t_dense / t_pkg:6.1f} | "
              f"{t_mono:11.2e} {abs(tau_mono - ref):8.1e} {t_mono / t_pkg:7.0f}")
        task = f"damped Mathieu tau_min (kappa {KAPPA}, nu {NU}, {KIND}), tol {tol:.0e}, N = {m.n_temporal}"
        row(task=task, package_s=t_pkg, baseline="dense scipy.linalg.eig(A, B), same pencil",
            baseline_s=t_dense, error=abs(m.tau_min - ref), baseline_error=abs(tau_dense - ref),
            note="errors against QZ at N = 80")
        row(task=task, package_s=t_pkg, baseline="solve_ivp monodromy (DOP853) + brentq",
            baseline_s=t_mono, error=abs(m.tau_min - ref), baseline_error=abs(tau_mono - ref),
            note="errors against QZ at N = 80")

    print("\nfixed truncation N: one structured solve vs dense scipy.linalg.eig(A, B), same pencil;\n"
          "eig(W): the eigenvalue step alone (the compiled tridiagonal kernel for Mathieu, b = 1; "
          "LAPACK ?geev of the\nhalf-size W for b = 2), the floor of the structured path; "
          "ceiling = dense / eig(W), the ratio it could reach with nothing else")
    print(f"{'model':>28} {'N':>4} {'kind':>12} | {'structured s':>12} | {'dense eig s':>11} | "
          f"{'ratio':>6} | {'eig(W) s':>9} {'ceiling':>7} | {'|diff tau_min|':>14}")
    models = {"mathieu kappa=0.26 nu=0.1": system,
              "sphere m=3 k=0.02 nu=0.006": sphere.hill_system(m=3, kappa=0.02, nu=0.006),
              "fibre m=3 k=0.02 nu=2e-4": fibre.hill_system(m=3, kappa=0.02, nu=2e-4)}
    for name, model in models.items():
        for n in (40, 80, 160) if model is system else (40, 80):
            for kind in ("harmonic", "subharmonic"):
                t_fast, (taus, _, _) = best_time(lambda: solve_truncation(model, kind, n), 5)
                hill = assemble(model, kind, n, "real")
                A, B = hill.A.toarray(), hill.B.toarray()
                t_dense, values = best_time(lambda: sla.eig(A, B)[0], repeat=3)
                values = values[np.isfinite(values) & (np.abs(values.imag) <= 1e-9 * np.abs(values))
                                & (values.real > 0)].real
                half = assemble(model, kind, n, preferred_form(kind, model.block_size))
                t_w = eigen_step_time(half)
                print(f"{name:>28} {n:4d} {kind:>12} | {t_fast:12.2e} | {t_dense:11.2e} | "
                      f"{t_dense / t_fast:6.1f} | {t_w:9.2e} {t_dense / t_w:7.1f} | "
                      f"{abs(taus.min() - values.min()):14.1e}")
                how = ("the O(N^2) tridiagonal kernel on W" if model.block_size == 1
                       else "dense eig of W")
                row(task=f"{name}: every real tau of one truncation, N = {n}, {kind} "
                         f"(package: assembly + {how})", package_s=t_fast,
                    baseline="dense scipy.linalg.eig(A, B), same pencil (assembled)",
                    baseline_s=t_dense, error=abs(taus.min() - values.min()),
                    note=f"error = |tau_min - tau_min(eig(A, B))|; the eigen step alone takes "
                         f"{t_w:.2e} s: ratio ceiling {t_dense / t_w:.1f}x with it")
        print()
    map_points()

    t0 = time.perf_counter()
    diagram = ss.tongues("mathieu", kappa="0:3:301", nu=NU, kind="both")
    print(f"\n301-point two-kind Ince-Strutt diagram with {len(diagram.tips)} tips: "
          f"{time.perf_counter() - t0:.2f} s (target < 2 s)")


if __name__ == "__main__":
    main()
