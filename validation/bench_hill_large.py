"""Benchmark: the structured tau_min paths on long and wide Hill pencils, against dense eig.

Each line prints the package's time and the baseline's in the same run, and their agreement:

* package: ``marginal_tau`` (method 'auto': dense eig of the half-size product W below
  KRYLOV_MIN_ORDER, Arnoldi on the real form above), or one truncation by a named method;
* dense eig: ``scipy.linalg.eigvals(A, B)`` (QZ) of the same real-form pencil at the package's
  final truncation (issue 3's baseline), where feasible; else dense eig of W ('structured').

Cases: damped Mathieu needing N >= 40 (kappa = 100, 400: 20 and 40 tongues below tau = 1/2); the
sphere at N = 40, 80; coupled damped Mathieu oscillators with the cochlea's graded stiffness
(block size M = 30, 60, 250; tests/test_marginal_fast.py builds them); one point of the Fig 6.13
tau map (all m = 2..6, both kinds) with the dense path against 'auto'.
Shift-invert cover (solvers/shift_invert.py): one truncation N = 16 of the cochlea at low forcing
frequency (sigma = 1e7 dyn/cm, omega = 314 rad/s; M = 64, 128), where the smallest-|tau| Arnoldi
gives up, against dense eig of W and against that Arnoldi followed by dense eig (the previous
'auto' path); and a cochlea case where the smallest-|tau| Arnoldi answers (kappa = 0.5,
nu = 1e-3, alpha = 1), against the cover alone. With --json-rows these print BENCH rows;
``--quick`` (a smoke run) only issue 25's point, at M = 16.
BLAS runs single-threaded for both sides (the machine is shared: threaded OpenBLAS under load
spends most of its time waiting; marginal_tau limits block models to one thread itself,
solvers/marginal.py on_block_threads).
Run: python validation/bench_hill_large.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from _bench import best_time, best_times, quick, row
from spectralshell.models.registry import hill_system
from spectralshell.discretise.hill import assemble
from spectralshell.models import cochlea, sphere
from spectralshell.models.mathieu import hill_system as mathieu
from spectralshell.params.physical import CARDIAC, cochlea_params, sphere_forced_params
from spectralshell.params.registry import make_params
from spectralshell.solvers.half_product import smallest_taus
from spectralshell.solvers.marginal import (coarser, dense_taus, krylov_form, krylov_min_order,
                                            marginal_tau, preferred_form, structured_taus,
                                            truncation_taus)
from spectralshell.solvers.shift_invert import interval_taus

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from test_marginal_fast import cochlea_like  # noqa: E402  (the test model, not a copy)

KINDS = ("harmonic", "subharmonic")


def qz_tau_min(system, kind: str, n: int) -> float:
    taus = dense_taus(assemble(system, kind, n, "real"))
    return float(taus[taus > 0].min())


def equal_error_table() -> None:
    print("damped Mathieu, tol = 1e-10: marginal_tau (all truncations) vs one QZ at its final N")
    print(f"{'case':>22} {'kind':>12} {'N':>4} | {'package s':>10} {'QZ s':>9} {'ratio':>6} | "
          f"{'|diff|':>8} {'error est':>9}")
    for kappa, nu in ((100.0, 1e-3), (400.0, 1e-2)):
        system = mathieu(kappa=kappa, nu=nu)
        for kind in KINDS:
            t_pkg, res = best_time(lambda: marginal_tau(system, kind, tol=1e-10))
            t_qz, ref = best_time(lambda: qz_tau_min(system, kind, res.n_temporal))
            print(f"{f'kappa={kappa:g} nu={nu:g}':>22} {kind:>12} {res.n_temporal:4d} | "
                  f"{t_pkg:10.2e} {t_qz:9.2e} {t_qz / t_pkg:6.1f} | "
                  f"{abs(res.tau_min - ref):8.1e} {res.error_estimate:9.1e}")


def truncation_table() -> None:
    print("\none truncation N: dense eig of W ('structured') and Arnoldi ('krylov') "
          "vs QZ of (A, B)")
    print(f"{'case':>24} {'N':>4} {'kind':>12} | {'W eig s':>9} {'krylov s':>9} {'QZ s':>9} | "
          f"{'QZ/W':>6} {'QZ/kry':>6} | {'|diff| W':>8} {'|diff| kry':>10}")
    cases = [("mathieu kappa=400 nu=.01", mathieu(kappa=400.0, nu=1e-2), (63, 160)),
             ("sphere m=3 k=0.02 nu=.006", sphere.hill_system(m=3, kappa=0.02, nu=0.006), (40, 80)),
             ("oscillators M=10", cochlea_like(10), (20,)),
             ("oscillators M=20", cochlea_like(20), (20,)),
             ("oscillators M=30", cochlea_like(30), (20,))]
    for name, system, ns in cases:
        for n in ns:
            for kind in KINDS:
                t_w, w = best_time(lambda: truncation_taus(system, kind, n, method="dense"))
                t_k, k = best_time(lambda: truncation_taus(system, kind, n, method="krylov"))
                t_qz, qz = best_time(lambda: qz_tau_min(system, kind, n), repeat=1)
                krylov_ok = k.method == "krylov"
                print(f"{name:>24} {n:4d} {kind:>12} | {t_w:9.2e} "
                      f"{t_k if krylov_ok else np.nan:9.2e} {t_qz:9.2e} | {t_qz / t_w:6.1f} "
                      f"{t_qz / t_k if krylov_ok else np.nan:6.1f} | {abs(w.tau[0] - qz):8.1e} "
                      f"{abs(k.tau[0] - qz) if krylov_ok else np.nan:10.1e}"
                      + ("" if krylov_ok else "  (Arnoldi not used: the Krylov space would "
                                               "exceed a third of the operator)"))


def block_table() -> None:
    print("\ncoupled oscillators (graded stiffness kappa e^{-alpha|x|}, M spatial modes), "
          "marginal_tau at n_temporal = 20 (and its N = 15 comparison)")
    print(f"{'M':>4} {'kind':>12} | {'package s':>10} {'dense W s':>10} {'ratio':>6} | "
          f"{'tau_min':>18} {'|diff|':>8} {'method':>8}")
    with threadpool_limits(1):
        system = cochlea_like(60)
        for kind in KINDS:
            t_pkg, res = best_time(lambda: marginal_tau(system, kind, n_temporal=20), repeat=2)
            t_d, dense = best_time(lambda: marginal_tau(system, kind, n_temporal=20,
                                                        method="dense"), repeat=1)
            print(f"{60:4d} {kind:>12} | {t_pkg:10.2e} {t_d:10.2e} {t_d / t_pkg:6.1f} | "
                  f"{res.tau_min:18.15f} {abs(res.tau_min - dense.tau_min):8.1e} {res.method:>8}")
    system = cochlea_like(250)
    for kind in KINDS:
        t_pkg, res = best_time(lambda: marginal_tau(system, kind, n_temporal=20), repeat=2)
        print(f" 250 {kind:>12} | {t_pkg:10.2e} {'-':>10} {'-':>6} | {res.tau_min:18.15f} "
              f"{'-':>8} {res.method:>8}  (N = 20 vs 15: error estimate "
              f"{res.error_estimate:.1e})")
    print("M = 250 at a small truncation, Arnoldi against dense eig of W (agreement check):")
    with threadpool_limits(1):
        for kind in KINDS:
            n = 4
            t_k, k = best_time(lambda: truncation_taus(system, kind, n, method="krylov"), repeat=1)
            form = preferred_form(kind, system.block_size)
            t_d, d = best_time(lambda: structured_taus(assemble(system, kind, n, form)), repeat=1)
            print(f" 250 {kind:>12} N = {n}: krylov {t_k:.2e} s, dense W {t_d:.2e} s, "
                  f"|diff tau_min| = {abs(k.tau[0] - d[0]):.1e}, real tau <= {k.complete_to:.3f} "
                  f"listed: {k.tau.size} vs {np.sum(d <= k.complete_to * (1 + 1e-9))}")


def cardiac_point() -> None:
    print("\nFig 6.13 (sphere, cardiac): one tau-map point = m = 2..6 x both kinds, tau_max = 1/2, "
          "tol = 1e-8")
    phys = {k: CARDIAC[k] for k in ("rho", "mu", "radius")}
    for sigma, bpm in ((2e4, 50.0), (1e4, 412.0)):
        systems = [hill_system(make_params("sphere", sphere_forced_params(
            {**phys, "sigma": sigma, "bpm": bpm, "m": m}))) for m in range(2, 7)]
        row = {}
        for method in ("dense", "auto"):
            row[method] = best_time(lambda: [marginal_tau(s, k, tol=1e-8, tau_max=0.5,
                                                          method=method)
                                             for s in systems for k in KINDS], repeat=2)
        (t_d, dense), (t_a, auto) = row["dense"], row["auto"]
        same = all((a.tau_min == d.tau_min) or abs(a.tau_min - d.tau_min) < 1e-12
                   for a, d in zip(auto, dense))
        print(f"sigma = {sigma:g} dyn/cm, {bpm:g} bpm: dense path {t_d:.3f} s, auto {t_a:.3f} s "
              f"(largest N {max(r.n_temporal for r in auto)}, methods "
              f"{sorted({r.method for r in auto})}), same tau_min: {same}")


def _cover_case(name: str, system, kind: str, n: int, previous_auto: bool) -> None:
    """One truncation: package ('auto', tau_max = 1/2) against dense eig of W and, if
    ``previous_auto``, against the smallest-|tau| Arnoldi run to its end plus dense eig."""
    t_pkg, pkg = best_time(lambda: truncation_taus(system, kind, n, tau_max=0.5), repeat=2)
    t_d, dense = best_time(lambda: truncation_taus(system, kind, n, tau_max=0.5,
                                                   method="dense"), repeat=1)
    ref = dense.tau[dense.tau <= 0.5]
    err = abs(pkg.tau[0] - ref[0]) if pkg.tau.size and ref.size else (
        0.0 if not pkg.tau.size and not ref.size else np.inf)
    upper = min(0.5, pkg.complete_to)  # every real tau up to here must be listed, and only those
    edge = upper * (1 + 1e-9)  # the last listed tau may be complete_to itself, up to rounding
    mine, listed = np.sum(pkg.tau <= edge), np.sum(ref <= edge)
    task = f"{name}, one truncation M = {system.block_size}, N = {n}, {kind}, tau_max 1/2"
    line = (f"{name:>26} M={system.block_size:3d} {kind:>12} | {pkg.method:>12} {t_pkg:8.2f} s | "
            f"dense W {t_d:7.2f} s ({t_d / t_pkg:5.1f}x) | tau_min {pkg.tau[0] if pkg.tau.size else np.nan:.12f} "
            f"|diff| {err:.1e} | real tau <= {upper:.3f}: {mine} (dense {listed})")
    note = (f"method {pkg.method}; error = |tau_min - tau_min(dense eig of W, same pencil)|; "
            f"real tau <= min(1/2, complete_to) = {upper:.4f} listed: {mine} (dense {listed})")
    row(task=task, package_s=t_pkg, baseline="dense eig of W (method='dense'), same pencil",
        baseline_s=t_d, error=err, baseline_error=0.0, note=note)
    if previous_auto:
        hill = assemble(system, kind, n, "real")
        t_s, found = best_time(lambda: smallest_taus(hill, tau_max=0.5), repeat=1)
        answered = found is not None
        t_prev = t_s + (0.0 if answered else t_d)
        line += f" | smallest-|tau| Arnoldi {t_s:.2f} s ({'answered' if answered else 'gave up'})"
        row(task=task, package_s=t_pkg,
            baseline="smallest-|tau| Arnoldi, then dense eig of W if it gives up (previous auto)",
            baseline_s=t_prev, error=err, baseline_error=0.0 if not answered else None,
            note=note + f"; the Arnoldi {'answered' if answered else 'gave up'} after {t_s:.2f} s")
    print(line, flush=True)


def cover_table() -> None:
    print("\nshift-invert cover of [0, 1/2] (tau_max = 1/2), one truncation N = 16, against dense "
          "eig of W of the same pencil and the smallest-|tau| Arnoldi (1 BLAS thread)")
    low = cochlea_params({"sigma": 1e7, "omega": 314.0})
    for m, kinds in ((64, KINDS), (128, KINDS)):
        system = cochlea.hill_system(kappa=low["kappa"], nu=low["nu"], alpha=low["alpha"],
                                     n_spatial=m)
        for kind in kinds:  # at M = 128 the subharmonic Arnoldi runs > 90 s before giving up
            _cover_case("cochlea omega=314", system, kind, 16,
                        previous_auto=not (m == 128 and kind == "subharmonic"))
    easy = cochlea.hill_system(kappa=0.5, nu=1e-3, alpha=1.0, n_spatial=64)
    for kind in KINDS:
        _cover_case("cochlea kappa=.5 nu=1e-3", easy, kind, 16, previous_auto=False)
        hill = assemble(easy, kind, 16, "real")
        t_pkg, pkg = best_time(lambda: truncation_taus(easy, kind, 16, tau_max=0.5), repeat=2)
        t_c, cover = best_time(lambda: interval_taus(hill, 0.5, smallest_only=True), repeat=2)
        err = abs(cover.tau[0] - pkg.tau[0])
        print(f"{'':>26} M= 64 {kind:>12} | the cover alone {t_c:.2f} s ({len(cover.shifts)} "
              f"shifts) against the package's {pkg.method} {t_pkg:.2f} s, |diff tau_min| {err:.1e}")
        row(task=f"cochlea kappa=.5 nu=1e-3 alpha=1, one truncation M = 64, N = 16, {kind}, "
                 "tau_max 1/2 (smallest-|tau| Arnoldi answers)",
            package_s=t_pkg, baseline="shift-invert cover alone (interval_taus)", baseline_s=t_c,
            error=0.0, baseline_error=err,
            note=f"package method {pkg.method}; errors against the package's tau_min")


#: Issue 25's cochlea point: low forcing frequency (omega = 600 rad/s, Table 5.1 otherwise:
#: alpha = 1.56), M = 80 spatial modes, N = 10, subharmonic.
ISSUE_POINT = {"omega": 600.0}
#: Issue 25's goal for that point: the package >= GOAL_RATIO x a dense solve of the halved pencil.
GOAL_RATIO = 10.0
#: Calls of each side, the best kept: the package's four truncations take 0.13-0.18 s as the
#: best of 7 in back-to-back runs on this shared VM (best of 3 gave 9.3-15.9x over four runs).
POINT_REPEAT = 7


def low_frequency_point(big: int = 80) -> None:
    """Issue 25's cochlea point at M = big = 80, N = 10 (subharmonic, tau_max 1/2): one
    truncation by the package against dense eig of W of the same pencil, and the four
    truncations a fixed-truncation solve needs for its error estimates (N and coarser(N), at
    M and M / 2) by 'auto' against the same four by dense eig of W (the goal: >= 10x)."""
    p = cochlea_params(ISSUE_POINT)
    systems = {m: cochlea.hill_system(kappa=p["kappa"], nu=p["nu"], alpha=p["alpha"],
                                      n_spatial=m) for m in (big, big // 2)}
    print(f"\ncochlea omega = 600 rad/s (alpha = {p['alpha']:.3f}), M = {big}, N = 10, "
          "subharmonic, tau_max 1/2 (1 BLAS thread)")
    _cover_case("cochlea omega=600 (issue 25's point)", systems[big], "subharmonic", 10,
                previous_auto=False)
    cases = [(m, n) for m in (big, big // 2) for n in (10, coarser(10))]

    def four(method: str) -> list[float]:
        return [truncation_taus(systems[m], "subharmonic", n, tau_max=0.5, method=method).tau[0]
                for m, n in cases]

    t_pkg, c_pkg, pkg = best_times(lambda: four("auto"), POINT_REPEAT)
    t_d, c_d, dense = best_times(lambda: four("dense"), POINT_REPEAT)
    err = max(abs(a - b) for a, b in zip(pkg, dense))
    print(f"  the point's four truncations (M, N) = {cases}: auto {t_pkg:.2f} s, dense W "
          f"{t_d:.2f} s ({t_d / t_pkg:.1f}x; CPU time {c_pkg:.2f} s against {c_d:.2f} s, "
          f"{c_d / c_pkg:.1f}x), max |diff tau_min| {err:.1e} (auto: Arnoldi from half order "
          f"{krylov_min_order(systems[big // 2])} for blocks > 2 x 2, so at M = {big // 2} too; "
          f"on the {krylov_form('subharmonic', big)} form's complex W)")
    row(task="cochlea omega=600 alpha=1.56 (issue 25's point), subharmonic, tau_max 1/2: the "
             f"four truncations of a fixed-truncation solve at M = {big}, N = 10, (M, N) = "
             f"{cases}",
        package_s=t_pkg, baseline="the same four truncations by dense eig of W", baseline_s=t_d,
        error=err, baseline_error=0.0,
        note=f"error = max |tau_min - tau_min(dense eig of W)|; CPU time {c_pkg:.3f} s against "
             f"{c_d:.3f} s ({c_d / c_pkg:.1f}x); met: wall-time ratio >= {GOAL_RATIO:g} and "
             "error <= 1e-9",
        goal="cochlea-point", met=big == 80 and t_d / t_pkg >= GOAL_RATIO and err <= 1e-9)


def main() -> None:
    if quick():  # a smoke run (validation/_bench.py): the goal's point at M = 16
        with threadpool_limits(1):
            low_frequency_point(16)
        return
    with threadpool_limits(1):
        equal_error_table()
        truncation_table()
        cardiac_point()
        cover_table()
        low_frequency_point()
    block_table()


if __name__ == "__main__":
    main()
