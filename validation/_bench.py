"""Row protocol shared by the benchmark scripts ``validation/bench_*.py`` (read by bench_table.py).

A benchmark keeps printing its own human-readable output. Run with ``--json-rows`` it also prints,
for each result, one line ``BENCH {json}`` on stdout:

* a table row (:func:`row`): task, package time, the named baseline and its time (same run),
  their ratio, and the achieved error of the package (and of the baseline);
* a cost-growth series (:func:`growth`): wall time against one resolution parameter
  ('N' temporal truncation, 'M' spatial modes, 'n_radial' radial nodes, 'l_max' degree), with
  the fitted exponent of t ~ parameter^p.

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


def enabled() -> bool:
    """True when the script was started with ``--json-rows``."""
    return FLAG in sys.argv


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(float(x)) else float(x)


def _emit(record: dict[str, Any]) -> None:
    if enabled():
        print(PREFIX + json.dumps(record), flush=True)


def row(*, task: str, package_s: float, baseline: str, baseline_s: float | None,
        error: float | None, baseline_error: float | None = None, note: str = "") -> None:
    """One row of the benchmark table (printed only with ``--json-rows``).

    task : what is computed (parameters included). package_s : wall time of the package (s).
    baseline : the named alternative method timed in the same run; baseline_s its wall time.
    error : achieved error of the package's answer against a reference (say which in ``note``);
    baseline_error : the baseline's. ratio = baseline_s / package_s is added here.
    """
    ratio = None if not baseline_s or not package_s else baseline_s / package_s
    _emit({"type": "row", "task": task, "package_s": float(package_s), "baseline": baseline,
           "baseline_s": _finite(baseline_s), "ratio": _finite(ratio), "error": _finite(error),
           "baseline_error": _finite(baseline_error), "note": note})


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
