"""Start-up time of the command line against ``python -c "import numpy"`` (issue 26).

Each command runs as a whole process (start-up, imports, work, exit), in turn with the baseline
(A B A B ...) after one warm-up pair, RUNS times; the ratio package / baseline is taken pair by
pair, so that a machine whose speed drifts during the run still gives a fair ratio. Printed:
min and median of each time and the median ratio, with the issue's limit (``--version`` and
``--help`` <= 3x, a Mathieu ``floquet`` <= 6x). Exit status 1 if a median ratio is above its
limit.

Run: python validation/bench_startup.py [--runs N]   (also from bench_table.py, ``make bench``)
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _bench import row  # noqa: E402

BASELINE = (sys.executable, "-c", "import numpy")
#: (what is timed, the spectralshell arguments, the largest median ratio allowed)
COMMANDS = (("spectralshell --version", ("--version",), 3.0),
            ("spectralshell --help", ("--help",), 3.0),
            ("spectralshell floquet mathieu (tol 1e-10)",
             ("floquet", "mathieu", "--kappa", "0.25", "--nu", "0.1", "--json"), 6.0))
RUNS = 7


def wall(argv: tuple[str, ...]) -> float:
    """Wall seconds of one run of ``argv`` as a process (its output discarded)."""
    t0 = time.perf_counter()
    subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return time.perf_counter() - t0


@dataclass(frozen=True)
class Startup:
    """Times (s) of the package command and of the baseline, and their pairwise ratios."""

    package: tuple[float, ...]
    baseline: tuple[float, ...]

    @property
    def ratios(self) -> tuple[float, ...]:
        return tuple(a / b for a, b in zip(self.package, self.baseline))

    @property
    def ratio(self) -> float:
        """Median of the pairwise ratios package / baseline."""
        return statistics.median(self.ratios)


def measure(args: tuple[str, ...], runs: int = RUNS) -> Startup:
    """Time ``python -m spectralshell ARGS`` and the baseline in turn, ``runs`` pairs after a
    warm-up pair (which fills the file cache)."""
    command = (sys.executable, "-m", "spectralshell", *args)
    wall(command), wall(BASELINE)
    pairs = [(wall(command), wall(BASELINE)) for _ in range(runs)]
    return Startup(tuple(p for p, _ in pairs), tuple(b for _, b in pairs))


def main() -> int:
    runs = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else RUNS
    print(f"start-up against python -c 'import numpy', {runs} pairs each (min / median s)")
    over = []
    for task, args, limit in COMMANDS:
        found = measure(args, runs)
        pkg, base = statistics.median(found.package), statistics.median(found.baseline)
        verdict = "ok" if found.ratio <= limit else "OVER THE LIMIT"
        print(f"  {task:<44} {min(found.package):.3f} / {pkg:.3f}   numpy "
              f"{min(found.baseline):.3f} / {base:.3f}   ratio {found.ratio:.2f} "
              f"(limit {limit:g}) {verdict}")
        row(task=f"start-up: {task}", package_s=pkg, baseline="python -c 'import numpy'",
            baseline_s=base, error=None,
            note=f"whole process, median of {runs}; package/baseline = {found.ratio:.2f} "
                 f"(limit {limit:g}x)")
        if found.ratio > limit:
            over.append(task)
    return 1 if over else 0


if __name__ == "__main__":
    raise SystemExit(main())
