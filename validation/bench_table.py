"""Run every benchmark validation/bench_*.py and write one Markdown table and the cost-growth plot.

Each script runs in its own process with ``--json-rows`` (protocol: validation/_bench.py); its
normal output streams to the terminal, and the ``BENCH {json}`` lines are collected into

* validation/BENCHMARKS.md: first issue 25's goals (``_bench.GOALS``), each with the row that
  measures it, its baseline from the same run and whether it is met ("not measured" where no
  row named it); then per row task, package time, baseline (named) and its time, ratio
  (baseline time / package time), achieved error; then the fitted cost-growth exponents and
  each script's wall and CPU time;
* validation/cost_growth.png: wall time against N, M, n_radial, l_max (log-log) with the fits.

``--quick``: every script runs its small smoke version (``_bench.quick``), and the files go to a
new temporary directory unless ``--out`` says where: a check that the pipeline runs end to end
(minutes), whose numbers measure nothing.

Run: python validation/bench_table.py [--only NAME ...] [--out DIR] [--quick]   (`make bench`)
Exit status 1 if a benchmark script fails (its rows are kept, the failure is listed).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _bench import FLAG, GOALS, PREFIX, QUICK  # noqa: E402

from spectralshell._version import libraries_line  # noqa: E402


def scripts(only: list[str] | None) -> list[Path]:
    found = sorted(p for p in HERE.glob("bench_*.py") if p.name != Path(__file__).name)
    if only:
        found = [p for p in found if p.stem in only or p.name in only]
    return found


def children_cpu() -> float:
    """CPU seconds of this process's finished children (and theirs, once waited for)."""
    used = resource.getrusage(resource.RUSAGE_CHILDREN)
    return used.ru_utime + used.ru_stime


def run_script(path: Path, quick: bool = False) -> tuple[list[dict], int, float, float]:
    """Run one benchmark, echo its output, return (records, exit status, wall s, CPU s)."""
    t0, cpu0 = time.perf_counter(), children_cpu()
    proc = subprocess.Popen([sys.executable, str(path), FLAG] + [QUICK] * quick,
                            stdout=subprocess.PIPE, text=True,
                            cwd=HERE.parent, env={**os.environ, "PYTHONPATH": os.pathsep.join(
                                filter(None, [str(HERE), os.environ.get("PYTHONPATH")]))})
    records = []
    for line in proc.stdout:
        if line.startswith(PREFIX):
            records.append({**json.loads(line[len(PREFIX):]), "script": path.name})
        else:
            sys.stdout.write(line)
            sys.stdout.flush()
    code = proc.wait()
    return records, code, time.perf_counter() - t0, children_cpu() - cpu0


def _num(x, fmt: str) -> str:
    return "-" if x is None else format(x, fmt)


def _cells(cells: list) -> str:
    return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"


def goal_lines(rows: list[dict]) -> list[str]:
    """The goals table: every goal of ``GOALS`` with the rows that measure it, or 'not
    measured' where none did (its script failed or does not emit it)."""
    lines = ["## Issue 25's goals", "",
             "Each goal with the row of this run that measures it and that row's baseline "
             "(same run); details in the rows below.", "",
             "| goal | met | package (s) | baseline | baseline (s) | ratio | measured | script |",
             "|---|---|---|---|---|---|---|---|"]
    for key, text in GOALS.items():
        mine = [r for r in rows if r.get("goal") == key]
        if not mine:
            lines.append(_cells([text, "**not measured** (no row in this run)", "-", "-", "-",
                                 "-", "-", "-"]))
        for r in mine:
            met = ("quick run: measures nothing" if r.get("quick")
                   else "yes" if r["met"] else "**no**")
            task = r["task"] + (f" ({r['note']})" if r.get("note") else "")
            lines.append(_cells([text, met, _num(r["package_s"], ".3g"), r["baseline"],
                                 _num(r["baseline_s"], ".3g"), _num(r["ratio"], ".3g"), task,
                                 f"`{r['script']}`"]))
    return lines + [""]


def markdown(records: list[dict], status: dict[str, tuple], quick: bool = False) -> str:
    """BENCHMARKS.md from the scripts' records and ``status``: script name -> (exit status,
    wall s, rows, CPU s)."""
    rows = [r for r in records if r["type"] == "row"]
    series = [r for r in records if r["type"] == "growth"]
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    wall = sum(s[1] for s in status.values())
    lines = ["# spectralshell benchmarks", ""]
    if quick:
        lines += ["**Quick smoke run (`bench_table.py --quick`): small cases only; these numbers "
                  "measure nothing.**", ""]
    lines += [f"{datetime.now(timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}, {libraries_line()}, "
              f"{os.cpu_count()} cores, load average {load[0]:.1f} at the "
              f"end; {wall / 60:.0f} min in all. Times are wall-clock seconds from one run of "
              "`make bench` (best of several calls where the script says so); ratio = baseline "
              "time / package time (> 1: the package is faster); errors are against each "
              "script's stated reference.", ""]
    lines += goal_lines(rows)
    lines += ["## All rows", "",
              "| task | package (s) | baseline | baseline (s) | ratio | error | baseline error "
              "| script |",
              "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        task = r["task"] + (f" ({r['note']})" if r.get("note") else "")
        if r.get("goal"):
            task = f"**goal {r['goal']}**: " + task
        lines.append(_cells([task, _num(r["package_s"], ".3g"), r["baseline"],
                             _num(r["baseline_s"], ".3g"), _num(r["ratio"], ".3g"),
                             _num(r["error"], ".1e"), _num(r["baseline_error"], ".1e"),
                             f"`{r['script']}`"]))
    if series:
        lines += ["", "## Cost growth", "", "![cost growth](cost_growth.png)", "",
                  "| series | parameter | range | fitted exponent p (t ~ parameter^p) | script |",
                  "|---|---|---|---|---|"]
        for s in series:
            lines.append(f"| {s['label']} | {s['parameter']} | {min(s['values']):g}-{max(s['values']):g} | "
                         f"{s['exponent']:.2f} | `{s['script']}` |")
    lines += ["", "## Scripts", "",
              "| script | exit status | rows | wall time (s) | CPU time (s) |",
              "|---|---|---|---|---|"]
    for name, (code, seconds, n, cpu) in status.items():
        state = "ok" if code == 0 else f"**failed ({code})**"
        lines.append(f"| `{name}` | {state} | {n} | {seconds:.0f} | {cpu:.0f} |")
    missing = [name for name, (code, _, n, _) in status.items() if code == 0 and n == 0]
    if missing:
        lines += ["", "Scripts without rows do not implement `--json-rows` yet (validation/_bench.py): "
                  + ", ".join(f"`{m}`" for m in missing) + "."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="+", help="run only these scripts (stem or file name)")
    parser.add_argument("--out", help="directory of BENCHMARKS.md and cost_growth.png "
                        "(default validation/; with --quick a new temporary directory)")
    parser.add_argument("--quick", action="store_true",
                        help="small smoke cases of every script (numbers measure nothing)")
    args = parser.parse_args(argv)
    out = Path(args.out if args.out else tempfile.mkdtemp(prefix="bench-quick-") if args.quick
               else HERE)
    out.mkdir(parents=True, exist_ok=True)
    records, status = [], {}
    for path in scripts(args.only):
        print(f"== {path.name}", flush=True)
        found, code, seconds, cpu = run_script(path, args.quick)
        records += found
        status[path.name] = (code, seconds, len(found), cpu)
        print(f"== {path.name}: exit {code}, {len(found)} rows, {seconds:.0f} s wall, "
              f"{cpu:.0f} s CPU", flush=True)
    series = [r for r in records if r["type"] == "growth"]
    if series:
        sys.path.insert(0, str(HERE.parent))
        from spectralshell.plots.validation_chart import save_growth

        save_growth(series, out / "cost_growth.png")
    table = out / "BENCHMARKS.md"
    table.write_text(markdown(records, status, args.quick))
    print(f"wrote {table}" + (f" and {out / 'cost_growth.png'}" if series else ""))
    return 0 if all(s[0] == 0 for s in status.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
