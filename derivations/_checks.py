"""Check harness shared by the derivation scripts: record and print each check, then summarise.

A script calls ``check(name, ok, detail)`` for every claim it verifies, ``section(title)`` between
parts, and returns ``summary()`` as its exit status (1 if any check failed).
"""

from __future__ import annotations

import time

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
