"""Run every benchmark validation/bench_*.py and write one Markdown table and the cost-growth plot.

Each script runs in its own process with ``--json-rows`` (protocol: validation/_bench.py); its
normal output streams to the terminal, and the ``BENCH {json}`` lines are collected into

* validation/BENCHMARKS.md: per row task, package time, baseline (named) and its time, ratio
  (baseline time / package time), achieved error; then the fitted cost-growth exponents;
* validation/cost_growth.png: wall time against N, M, n_radial, l_max (log-log) with the fits.

Run: python validation/bench_table.py [--only NAME ...] [--out DIR]   (`make bench`)
Exit status 1 if a benchmark script fails (its rows are kept, the failure is listed).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _bench import FLAG, PREFIX  # noqa: E402

from spectralshell._version import libraries_line  # noqa: E402


def scripts(only: list[str] | None) -> list[Path]:
    found = sorted(p for p in HERE.glob("bench_*.py") if p.name != Path(__file__).name)
    if only:
        found = [p for p in found if p.stem in only or p.name in only]
    return found


def run_script(path: Path) -> tuple[list[dict], int, float]:
    """Run one benchmark, echo its output, return (records, exit status, seconds)."""
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, str(path), FLAG], stdout=subprocess.PIPE, text=True,
                            cwd=HERE.parent, env={**os.environ, "PYTHONPATH": os.pathsep.join(
                                filter(None, [str(HERE), os.environ.get("PYTHONPATH")]))})
    records = []
    for line in proc.stdout:
        if line.startswith(PREFIX):
            records.append({**json.loads(line[len(PREFIX):]), "script": path.name})
        else:
            sys.stdout.write(line)
            sys.stdout.flush()
    return records, proc.wait(), time.perf_counter() - t0


def _num(x, fmt: str) -> str:
    return "-" if x is None else format(x, fmt)


def markdown(records: list[dict], status: dict[str, tuple[int, float, int]]) -> str:
    rows = [r for r in records if r["type"] == "row"]
    series = [r for r in records if r["type"] == "growth"]
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    lines = ["# spectralshell benchmarks", "",
             f"{datetime.now(timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}, {libraries_line()}, "
             f"{os.cpu_count()} cores, load average {load[0]:.1f} at the "
             "end. Times are wall-clock seconds from one run of `make bench` (best of several calls "
             "where the script says so); ratio = baseline time / package time (> 1: the package is "
             "faster); errors are against each script's stated reference.", "",
             "| task | package (s) | baseline | baseline (s) | ratio | error | baseline error | script |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        task = r["task"] + (f" ({r['note']})" if r.get("note") else "")
        cells = [task, _num(r["package_s"], ".3g"), r["baseline"], _num(r["baseline_s"], ".3g"),
                 _num(r["ratio"], ".3g"), _num(r["error"], ".1e"), _num(r["baseline_error"], ".1e"),
                 f"`{r['script']}`"]
        lines.append("| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |")
    if series:
        lines += ["", "## Cost growth", "", "![cost growth](cost_growth.png)", "",
                  "| series | parameter | range | fitted exponent p (t ~ parameter^p) | script |",
                  "|---|---|---|---|---|"]
        for s in series:
            lines.append(f"| {s['label']} | {s['parameter']} | {min(s['values']):g}-{max(s['values']):g} | "
                         f"{s['exponent']:.2f} | `{s['script']}` |")
    lines += ["", "## Scripts", "", "| script | exit status | rows | wall time (s) |", "|---|---|---|---|"]
    for name, (code, seconds, n) in status.items():
        state = "ok" if code == 0 else f"**failed ({code})**"
        lines.append(f"| `{name}` | {state} | {n} | {seconds:.0f} |")
    missing = [name for name, (code, _, n) in status.items() if code == 0 and n == 0]
    if missing:
        lines += ["", "Scripts without rows do not implement `--json-rows` yet (validation/_bench.py): "
                  + ", ".join(f"`{m}`" for m in missing) + "."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="+", help="run only these scripts (stem or file name)")
    parser.add_argument("--out", default=str(HERE), help="directory of BENCHMARKS.md and cost_growth.png")
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    records, status = [], {}
    for path in scripts(args.only):
        print(f"== {path.name}", flush=True)
        found, code, seconds = run_script(path)
        records += found
        status[path.name] = (code, seconds, len(found))
    series = [r for r in records if r["type"] == "growth"]
    if series:
        sys.path.insert(0, str(HERE.parent))
        from spectralshell.plots.validation_chart import save_growth

        save_growth(series, out / "cost_growth.png")
    table = out / "BENCHMARKS.md"
    table.write_text(markdown(records, status))
    print(f"wrote {table}" + (f" and {out / 'cost_growth.png'}" if series else ""))
    return 0 if all(code == 0 for code, _, _ in status.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
