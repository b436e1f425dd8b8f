"""Row protocol shared by the benchmark scripts ``validation/bench_*.py`` (read by bench_table.py).

A benchmark keeps printing its own human-readable output. Run with ``--json-rows`` it also prints,
for each result, one line ``BENCH {json}`` on stdout:

* a table row (:func:`row`): task, package time, the named baseline and its time (same run),
  their ratio, and the achieved error of the package (and of the baseline);
* a cost-growth series (:func:`growth`): wall time against one resolution parameter
  ('N' temporal truncation, 'M' spatial modes, 'n_radial' radial nodes, 'l_max' degree), with
  the fitted exponent of t ~ parameter^p.

A row that measures one of issue 25's goals (:data:`GOALS`) names it (``goal=``) and says whether
this run meets it (``met=``); bench_table.py lists every goal first, with its row's package and
baseline times, and says "not measured" for a goal no row of the run named.

``--quick`` (bench_table.py passes it on with ``--quick``): a script that takes more than a few
seconds runs a small version of its measurements (:func:`quick`), the others run as usual; a
check that the whole pipeline runs, whose numbers measure nothing (its goal rows say so).

Usage in a script (``validation/`` is on sys.path when the script runs)::

    from _bench import best_time, growth, row
    t_pkg, res = best_time(lambda: ss.floquet(...))
    t_base, ref = best_time(lambda: baseline(...))
    row(task="damped Mathieu tau_min, tol 1e-10", package_s=t_pkg, baseline="dense QZ (scipy.linalg.eig)",
        baseline_s=t_base, error=abs(res... - ref), baseline_error=...)

``python validation/bench_table.py`` runs every bench_*.py with ``--json-rows`` and writes
validation/BENCHMARKS.md and validation/cost_growth.png.
"""

from __future__ import annotations

import json
import math
import sys
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

PREFIX = "BENCH "
FLAG = "--json-rows"
QUICK = "--quick"

#: Issue 25's speed goals, each measured by one row of ``make bench`` (key -> the goal as stated
#: in BENCHMARKS.md); the definitions are the issue's, word for word where it gives numbers.
GOALS = {
    "fig-6.13": "Fig 6.13 at 200 x 200 (sphere, m = 2..6, both kinds, tau <= 1/2, tol 1e-8): "
                "<= 60 s on 2 cores, the same map (every cell within its tolerance of today's; "
                "checked on the seeded sample of cells the baseline solves)",
    "fig-5.18": "Fig 5.18, both panels at 200 x 200: <= 1 hour on 16 workers, projected from the "
                "per-cell cost measured on a fixed random sample of >= 100 cells (seeded), the "
                "projection method printed; same values (the row judges the time alone: its "
                "sampled cells are solved by the package only)",
    "cochlea-point": "cochlea point omega = 600 rad/s, alpha = 1.56, M = 80, N = 10, subharmonic: "
                     ">= 10x a dense solve of the halved pencil at the same M, N",
    "sphere-truncation": "sphere one truncation, N = 40..80, both kinds: >= 30x dense eig(A, B) "
                         "(at every N and kind)",
    "fibre-truncation": "fibre one truncation, N = 40..80, both kinds: >= 30x dense eig(A, B) "
                        "(at every N and kind)",
}


def enabled() -> bool:
    """True when the script was started with ``--json-rows``."""
    return FLAG in sys.argv


def quick() -> bool:
    """True when the script was started with ``--quick``: a smoke run of small cases."""
    return QUICK in sys.argv


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(float(x)) else float(x)


def _emit(record: dict[str, Any]) -> None:
    if enabled():
        print(PREFIX + json.dumps(record), flush=True)


def row(*, task: str, package_s: float, baseline: str, baseline_s: float | None,
        error: float | None, baseline_error: float | None = None, note: str = "",
        goal: str | None = None, met: bool | None = None) -> None:
    """One row of the benchmark table (printed only with ``--json-rows``).

    task : what is computed (parameters included). package_s : wall time of the package (s).
    baseline : the named alternative method timed in the same run; baseline_s its wall time.
    error : achieved error of the package's answer against a reference (say which in ``note``);
    baseline_error : the baseline's. ratio = baseline_s / package_s is added here.
    goal : the key in :data:`GOALS` of the goal this row measures, with ``met`` whether this run
    meets it (both or neither; in a ``--quick`` run the row is marked as measuring nothing).
    """
    if (goal is None) != (met is None):
        raise ValueError(f"row {task!r}: goal and met go together (goal = {goal!r}, met = {met!r})")
    if goal is not None and goal not in GOALS:
        raise ValueError(f"row {task!r}: goal = {goal!r} is not one of {sorted(GOALS)}")
    ratio = None if not baseline_s or not package_s else baseline_s / package_s
    record = {"type": "row", "task": task, "package_s": float(package_s), "baseline": baseline,
              "baseline_s": _finite(baseline_s), "ratio": _finite(ratio), "error": _finite(error),
              "baseline_error": _finite(baseline_error), "note": note}
    if goal is not None:
        record.update(goal=goal, met=bool(met), quick=quick())
    _emit(record)


def fit_exponent(values: Sequence[float], seconds: Sequence[float]) -> float:
    """Slope p of log t = p log x + c (least squares over all points)."""
    return float(np.polyfit(np.log(np.asarray(values, float)), np.log(np.asarray(seconds, float)), 1)[0])


def growth(*, label: str, parameter: str, values: Sequence[float], seconds: Sequence[float],
           note: str = "") -> float:
    """A cost-growth series: wall time against ``parameter``; returns the fitted exponent."""
    p = fit_exponent(values, seconds)
    _emit({"type": "growth", "label": label, "parameter": parameter,
           "values": [float(v) for v in values], "seconds": [float(t) for t in seconds],
           "exponent": p, "note": note})
    return p


def best_time(fn: Callable[[], Any], repeat: int = 3,
              clock: Callable[[], float] = time.perf_counter) -> tuple[float, Any]:
    """(best wall time over ``repeat`` calls, the last result); ``clock=time.process_time``
    gives CPU time instead, less sensitive to a shared machine's load."""
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = clock()
        out = fn()
        best = min(best, clock() - t0)
    return best, out


def best_times(fn: Callable[[], Any], repeat: int = 3) -> tuple[float, float, Any]:
    """(best wall time, best CPU time, the last result) over the same ``repeat`` calls: CPU
    time beside wall time without timing the calls twice."""
    wall, cpu, out = math.inf, math.inf, None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        wall, cpu = min(wall, time.perf_counter() - t0), min(cpu, time.process_time() - c0)
    return wall, cpu, out
