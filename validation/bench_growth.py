"""Benchmark: how the cost of one solve grows with each resolution parameter (fitted power laws).

* N (temporal truncation): one truncation of the Hill pencil, ``truncation_taus`` (the solver's
  own choice of structured / Krylov path), subharmonic, for the Mathieu equation, the sphere
  (m = 3, kappa = 0.02, nu = 0.006) and the fibre (m = 3, kappa = 0.02, nu = 2e-4), and for the
  cochlea (M = 16 cosine modes, kappa = 0.5, nu = 1e-3, alpha = 1) when the model is present;
  beside it the dense QZ of the same real-form pencil (``scipy.linalg.eigvals(A, B)``), the
  thesis's method, as a named baseline row at the largest N.
* M (spatial cosine modes of the cochlea, N = 10): the same one-truncation solve.
* n_radial (radial Chebyshev nodes per side, sphere m = 2, zeta = 0.01): assembly + QZ of the
  radial pencil (discretise/sphere_radial.py), whose eigenvalues are the natural modes.
* l_max (spherical-harmonic degree): one synthesis + analysis pair on the dealiased SHTns grid
  (discretise/shtns_adapter.py), the per-step explicit cost of the coupled (non-uniform kappa)
  time stepper.

Each time is the best of 3 with one BLAS thread. Run: python validation/bench_growth.py [--json-rows]
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.linalg as sla  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

from _bench import best_time, growth, row  # noqa: E402
from spectralshell.discretise.hill import assemble  # noqa: E402
from spectralshell.discretise.sphere_radial import radial_operators  # noqa: E402
from spectralshell.models import fibre, mathieu, sphere  # noqa: E402
from spectralshell.solvers.eigen import finite_eigenvalues  # noqa: E402
from spectralshell.solvers.marginal import truncation_taus  # noqa: E402

KIND = "subharmonic"


def _cochlea(n_spatial: int):
    try:
        from spectralshell.models import cochlea
    except ImportError:
        return None
    return cochlea.hill_system(kappa=0.5, nu=1e-3, alpha=1.0, n_spatial=n_spatial)


def series(label: str, parameter: str, values, solve) -> None:
    seconds = [best_time(lambda v=v: solve(v))[0] for v in values]
    p = growth(label=label, parameter=parameter, values=values, seconds=seconds)
    cells = "  ".join(f"{v:g}: {t:.2e}" for v, t in zip(values, seconds))
    print(f"  {label:<44} p = {p:5.2f}   {cells}", flush=True)


def dense_baseline(label: str, system, n: int) -> None:
    t_pkg, found = best_time(lambda: truncation_taus(system, KIND, n))
    hill = assemble(system, KIND, n, "real")
    A, B = hill.A.toarray(), hill.B.toarray()
    t_qz, values = best_time(lambda: sla.eigvals(A, B), repeat=1)
    values = values[np.isfinite(values) & (np.abs(values.imag) <= 1e-9 * np.abs(values)) & (values.real > 0)]
    diff = abs(found.tau.min() - values.real.min()) if found.tau.size and values.size else None
    row(task=f"{label}: one Hill truncation, N = {n}, {KIND}", package_s=t_pkg,
        baseline="dense QZ of the same pencil (scipy.linalg.eigvals(A, B))", baseline_s=t_qz,
        error=diff, note="error = |tau_min - tau_min(QZ)|, same truncation")
    print(f"  {label}, N = {n}: package {t_pkg:.2e} s ({found.method}), dense QZ {t_qz:.2e} s, "
          f"ratio {t_qz / t_pkg:.1f}, |diff tau_min| {diff}", flush=True)


def main() -> None:
    systems = {"mathieu (kappa 0.26, nu 0.1)": mathieu.hill_system(kappa=0.26, nu=0.1),
               "sphere (m 3, kappa 0.02, nu 0.006)": sphere.hill_system(m=3, kappa=0.02, nu=0.006),
               "fibre (m 3, kappa 0.02, nu 2e-4)": fibre.hill_system(m=3, kappa=0.02, nu=2e-4)}
    cochlea16 = _cochlea(16)
    if cochlea16 is not None:
        systems["cochlea (M 16, kappa 0.5, nu 1e-3, alpha 1)"] = cochlea16
    with threadpool_limits(1):
        print("== time of one truncation against N")
        for label, system in systems.items():
            values = [10, 20, 40, 80] if label.startswith("cochlea") else [10, 20, 40, 80, 160, 320]
            series(label, "N", values, lambda n, s=system: truncation_taus(s, KIND, n))
        print("== package against dense QZ at one N")
        for label, system in systems.items():
            dense_baseline(label, system, 40 if label.startswith("cochlea") else 160)
        if cochlea16 is not None:
            print("== time of one truncation (N = 10) against the number M of cochlea modes")
            series("cochlea (N 10, kappa 0.5, nu 1e-3, alpha 1)", "M", [4, 8, 16, 32, 64],
                   lambda m: truncation_taus(_cochlea(m), KIND, 10))
        print("== radial Chebyshev pencil (assembly + QZ) against nodes per side")
        series("sphere natural modes (m 2, zeta 0.01)", "n_radial", [16, 24, 32, 48, 64, 96],
               lambda n: finite_eigenvalues(*radial_operators(m=2, nu=0.01, n_inner=n, n_outer=n,
                                                              exterior_angle=-np.pi / 3).pencil(1.0)))
        try:
            from spectralshell.discretise.shtns_adapter import grid
        except ImportError as exc:  # SHTns missing: no l_max series
            print(f"== l_max: skipped ({exc})")
            return
        print("== SHTns synthesis + analysis on the dealiased grid against l_max")

        def transform_pair(l_max: int):
            g = grid(l_max)
            coeffs = {(m, k): 1.0 / (1 + m) for m in range(l_max + 1) for k in range(-m, m + 1)}
            return g.analyse(g.synthesise(coeffs))

        series("scalar transform pair (shtns_adapter)", "l_max", [16, 32, 64, 128], transform_pair)


if __name__ == "__main__":
    main()
