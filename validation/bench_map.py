"""Benchmark: a coarse thesis Fig 6.13 map (minimum tau <= 1/2 of the viscous sphere over
stiffness sigma and beat rate, cgs, m = 2..6, both kinds, tol 1e-8), package against a named
baseline in the same run.

* package: ``ss.tau_map`` (the sweep engine: per point and kind ``solve_kind``, continuation
  along the bpm lines), serial;
* baseline: the straightforward path, an independent ``marginal_tau(system, kind, tol=1e-8,
  tau_max=0.5)`` per cell, degree and kind, each system built from the public pieces
  (``sphere_forced_params`` -> ``make_params`` -> ``hill_system``), nothing shared.

Both run on one BLAS thread, as each of the map's worker processes does on a 2-core machine
(``runner.executors``), alternating package and baseline; the best of ``REPEAT`` runs is kept.
The error is the largest |tau_min difference| over every cell, degree and kind (a cell without
tau <= 1/2 has tau_min = 1/2 in both), and the has_tau masks must agree. The 200 x 200 time on
2 cores is projected as (package time per cell) x 200^2 / 2: the coarse grid samples the same
(sigma, bpm) rectangle uniformly, so its mean cell cost stands for the fine grid's, and the
cells are independent (two worker processes of one BLAS thread each; perfect scaling assumed).

``--profile``: also the split of the package's time (cProfile, one run) by stage: D(s)
evaluation, Hill assembly, block inverses, half product W, balancing, the eigenvalue step,
the certificate, the rest of the solver (per truncation) and the sweep engine.
Run: python validation/bench_map.py [--size 16] [--profile]   (--quick: 4 x 4)
"""

from __future__ import annotations

import argparse
import cProfile
import pstats

import numpy as np

import spectralshell as ss
from _bench import best_time, quick, row
from spectralshell._threads import one_blas_thread
from spectralshell.models.registry import hill_system
from spectralshell.params.physical import CARDIAC, sphere_forced_params
from spectralshell.params.registry import make_params
from spectralshell.solvers.marginal import marginal_tau

TOL, TAU_MAX, DEGREES, KINDS = 1e-8, 0.5, (2, 3, 4, 5, 6), ("harmonic", "subharmonic")
PHYSICAL = {k: CARDIAC[k] for k in ("rho", "mu", "radius")}
REPEAT = 2
FINE, CORES = 200, 2
#: Profile stages: (label, function names whose cumulative time is the stage, names whose
#: cumulative time is subtracted -- nested stages counted on their own).
STAGES = (
    ("D(s) evaluation (Bessel-ratio kernels, models/sphere.py)", ("poloidal_unforced",), ()),
    ("Hill assembly, besides D(s) (discretise/hill.py)", ("assemble",),
     ("poloidal_unforced",)),
    ("block inverses A_k^-1 (half_product.block_inverses)", ("block_inverses",), ()),
    ("half product W (half_product.dense_half_product)", ("dense_half_product",), ()),
    ("balancing ?gebal and norm (marginal.structured_spectrum)", ("structured_spectrum",),
     ("_eigenvalues", "dense_half_product")),
    ("eigenvalue step ?geev of W (marginal._eigenvalues)", ("_eigenvalues",), ()),
    ("certificate (marginal.certified_bound)", ("certified_bound",), ()),
)


def package_map(size: int):
    """The map by ``ss.tau_map``, serial."""
    return ss.tau_map("sphere", x=("sigma", f"{CARDIAC['sigma_range'][0]}:"
                                   f"{CARDIAC['sigma_range'][1]}:{size}"),
                      y=("bpm", f"50:650:{size}"), m="2:6", tau_max=TAU_MAX, tol=TOL,
                      physical=PHYSICAL, workers=1)


def baseline_map(sigma: np.ndarray, bpm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(tau_min, has_tau) over (sigma, bpm, m, kind) by independent ``marginal_tau`` solves;
    tau_min = TAU_MAX where there is none below it (as the sweep stores it)."""
    tau = np.full((len(sigma), len(bpm), len(DEGREES), len(KINDS)), TAU_MAX)
    for i, s in enumerate(sigma):
        for j, b in enumerate(bpm):
            for q, m in enumerate(DEGREES):
                params = sphere_forced_params({**PHYSICAL, "sigma": float(s), "bpm": float(b),
                                               "m": m})
                system = hill_system(make_params("sphere", params))
                for r, kind in enumerate(KINDS):
                    found = marginal_tau(system, kind, tol=TOL, tau_max=TAU_MAX).tau_min
                    tau[i, j, q, r] = TAU_MAX if found is None else found
    return tau, tau < TAU_MAX


def ordered(ds, name: str) -> np.ndarray:
    """Variable ``name`` of the map as (sigma, bpm, m, kind)."""
    return ds[name].transpose("sigma", "bpm", "m", "kind").sel(m=list(DEGREES),
                                                              kind=list(KINDS)).values


def profile_split(size: int) -> None:
    """Print the package's time by stage (cProfile of one run; see STAGES)."""
    profiler = cProfile.Profile()
    with one_blas_thread():
        profiler.runcall(package_map, size)
    stats = pstats.Stats(profiler).stats
    cumulative: dict[str, float] = {}
    for (_, _, name), (_, _, _, cum, _) in stats.items():
        cumulative[name] = cumulative.get(name, 0.0) + cum
    total = cumulative["package_map"]
    solver = cumulative["marginal_tau"] + cumulative.get("solve_continued", 0.0)
    print(f"\nprofile of one package run ({total:.2f} s under cProfile):")
    counted = 0.0
    for label, names, minus in STAGES:
        t = (sum(cumulative.get(n, 0.0) for n in names)
             - sum(cumulative.get(n, 0.0) for n in minus))
        counted += t
        print(f"  {label:62s} {t:7.2f} s {100 * t / total:5.1f} %")
    for label, t in (("solver overhead per truncation (marginal.py, Python)", solver - counted),
                     ("sweep engine (params, systems, chunks, store)", total - solver)):
        print(f"  {label:62s} {t:7.2f} s {100 * t / total:5.1f} %")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=int, default=16)
    parser.add_argument("--profile", action="store_true")
    args, _ = parser.parse_known_args()
    size = min(args.size, 4) if quick() else args.size  # --quick: a smoke run (_bench.py)
    print(f"Fig 6.13 map, {size} x {size} (sigma, bpm), m = 2..6, both kinds, tau <= 1/2, "
          f"tol {TOL:g}, serial, one BLAS thread; best of {REPEAT}, alternating")
    t_pkg = t_base = np.inf
    with one_blas_thread():
        for _ in range(REPEAT):
            t, ds = best_time(lambda: package_map(size), repeat=1)
            t_pkg = min(t_pkg, t)
            sigma, bpm = ds["sigma"].values, ds["bpm"].values
            t, (tau, has) = best_time(lambda: baseline_map(sigma, bpm), repeat=1)
            t_base = min(t_base, t)
    error = float(np.abs(ordered(ds, "tau_min") - tau).max())
    same_mask = bool(np.array_equal(ordered(ds, "has_tau"), has))
    cells = size * size
    projected = t_pkg / cells * FINE ** 2 / CORES
    print(f"  package  (ss.tau_map):                   {t_pkg:8.2f} s "
          f"({1e3 * t_pkg / cells:.1f} ms per cell)")
    print(f"  baseline (independent marginal_tau):     {t_base:8.2f} s "
          f"({1e3 * t_base / cells:.1f} ms per cell), ratio {t_base / t_pkg:.2f}")
    print(f"  max |tau_min difference| {error:.2e} (tol {TOL:g}); has_tau masks equal: "
          f"{same_mask}; {int(has.sum())} of {has.size} (cell, m, kind) have tau <= 1/2")
    print(f"  projected {FINE} x {FINE} on {CORES} cores: {projected:.0f} s "
          f"(= package s per cell x {FINE}^2 / {CORES}: uniform sample of the same rectangle, "
          "independent cells, one BLAS thread per worker; target 60 s)")
    row(task=f"Fig 6.13 map {size} x {size}, m = 2..6, both kinds, tau <= 1/2, tol {TOL:g}, "
             "serial", package_s=t_pkg,
        baseline="independent marginal_tau per cell, degree and kind", baseline_s=t_base,
        error=error if same_mask else float("inf"),
        note=f"error = max |tau_min - baseline's| over the map; projected {FINE} x {FINE} on "
             f"{CORES} cores {projected:.0f} s (per-cell time x {FINE}^2 / {CORES})")
    if args.profile:
        profile_split(size)


if __name__ == "__main__":
    main()
