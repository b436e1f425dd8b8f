"""Benchmark: nonlinear frequency coefficients (thesis 7.3), symbolic generation and direct check.

* symbolic: ``derivations/lindstedt_sphere.py``'s exact Lindstedt-Poincare solve (Gaunt structure
  constants from sympy.physics.wigner, exact rational arithmetic), timed from a cold cache for
  m = 2..8 (k = 0) and for every generated (m, k); compared with the generated module.
* direct: ``frequency_slope`` (Newton on the time-periodic orbit of the full nonlinear equations, no
  expansion in eps), for m = 2, 3, 4 (k = 0) and the non-axisymmetric (3, 3); time and achieved
  relative agreement with the exact coefficients (requirement: <= 1e-4).

The radial-only membrane model is that of the thesis; see spectralshell.models.sphere_nonlinear.
Run: python validation/bench_lindstedt.py [--full]   (--full adds (4, 2), (4, 3), m = 5, 6 direct;
     --quick: (2, 0) alone)
"""

from __future__ import annotations

import importlib.util
import sys
import time
from pathlib import Path

from _bench import best_time, quick, row
from spectralshell.models import nonlinear_coefficients as nc
from spectralshell.models import sphere_nonlinear
from spectralshell.solvers.nonlinear_orbit import frequency_slope

ROOT = Path(__file__).resolve().parents[1]


def load_generator():
    spec = importlib.util.spec_from_file_location("lindstedt_sphere", ROOT / nc.GENERATOR)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def main() -> int:
    full = "--full" in sys.argv
    gen = load_generator()
    ok = True
    print("symbolic Lindstedt-Poincare (cold cache)")
    symbolic = [("m = 2..8, k = 0", [(m, 0) for m in range(2, 9)]),
                ("all generated (m, k)", gen.GENERATED_RANGE)]
    if quick():  # a smoke run (validation/_bench.py)
        symbolic = [("m = 2, k = 0", [(2, 0)])]
    for label, pairs in symbolic:
        t0 = time.perf_counter()
        res = {key: gen.solve(*key) for key in pairs}
        dt = time.perf_counter() - t0
        same = all(gen.c_pair(r["c"]) == nc.EXACT[key] for key, r in res.items() if key in nc.EXACT)
        ok &= same
        print(f"  {label:24s} {dt:6.1f} s   matches generated file: {same}")
    print("\ndirect periodic-orbit solve: fitted eps^2 slope vs exact c")
    print(f"  {'(m, k)':8s} {'c exact':>16s} {'c direct':>16s} {'rel. diff':>10s} {'fit unc.':>10s} {'time':>7s}")
    cases = [(2, 0), (3, 0), (4, 0), (3, 3)] + ([(4, 2), (4, 3), (5, 0), (6, 0)] if full else [])
    cases = cases[:1] if quick() else cases
    for m, k in cases:
        t0 = time.perf_counter()
        fit = frequency_slope(sphere_nonlinear, m, k)
        dt = time.perf_counter() - t0
        c = nc.lp_coefficient(m, k)
        rel = abs(fit.c - c) / abs(c)
        ok &= rel <= 1e-4
        print(f"  ({m}, {k})   {c:16.12f} {fit.c:16.12f} {rel:10.1e} {fit.uncertainty / abs(c):10.1e} {dt:6.1f}s")
        row(task=f"nonlinear coefficient c_{{{m},{k}}} (thesis 7.3)",
            package_s=best_time(lambda: nc.lp_coefficient(m, k), 20)[0],
            baseline="direct periodic-orbit Newton + eps^2 fit (solvers/nonlinear_orbit.py)",
            baseline_s=dt, error=0.0, baseline_error=rel,
            note="package: the exact generated value; baseline error relative to it")
    print("\nall within 1e-4:" if ok else "\nFAILED", ok)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
