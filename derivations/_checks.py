"""Check harness shared by the derivation scripts: record and print each check, then summarise.

A script calls ``check(name, ok, detail)`` for every claim it verifies, ``section(title)`` between
parts, and returns ``summary()`` as its exit status (1 if any check failed).
"""

from __future__ import annotations

import time
from typing import Callable

import mpmath as mp

T0 = time.time()
RESULTS: list[tuple[str, bool, str]] = []


def check(name: str, ok: bool, detail: str = "") -> bool:
    """Record and print one check; returns ``ok``."""
    RESULTS.append((name, bool(ok), detail))
    print(f"  [{'PASS' if ok else 'FAIL'}] {name}" + (f"  ({detail})" if detail else ""))
    return bool(ok)


def section(title: str) -> None:
    """Print the elapsed time and a banner for the next part."""
    print(f"  (t = {time.time() - T0:.1f} s)")
    print("\n" + "=" * 78 + f"\n{title}\n" + "=" * 78)


def summary() -> int:
    """Print the pass count, runtime and every failed check; the exit status (0: all passed)."""
    failed = [(name, detail) for name, ok, detail in RESULTS if not ok]
    print(f"\n  {len(RESULTS) - len(failed)}/{len(RESULTS)} checks passed; "
          f"runtime {time.time() - T0:.1f} s")
    for name, detail in failed:
        print(f"  FAILED: {name} {detail}")
    return 1 if failed else 0


def check_singular_at(name: str, rows: Callable[[mp.mpc], mp.matrix], mode: mp.mpc) -> bool:
    """Record that the square ``rows(gamma)`` are singular at the natural mode ``mode`` (smallest
    over largest singular value below 1e-25) and not 0.01 away from it (above 1e-8)."""
    def ratio(gamma):
        sv = mp.svd_c(rows(gamma), compute_uv=False)
        return min(sv) / max(sv)

    there, off = ratio(mode), ratio(mode + mp.mpf("0.01"))
    return check(name, there < 1e-25 and off > 1e-8,
                 f"gamma = {mp.nstr(mode, 12)}, s_min/s_max {mp.nstr(there, 3)} there, "
                 f"{mp.nstr(off, 3)} at gamma + 0.01")
