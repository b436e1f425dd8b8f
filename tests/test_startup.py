"""The command line starts light: --version and --help import neither scipy nor xarray/pandas,
a Mathieu floquet neither xarray/pandas nor scipy.optimize (issue 26; the timings are
validation/bench_startup.py)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "validation"))
import bench_startup  # noqa: E402


def imported(*args: str) -> set[str]:
    """Top-level modules and scipy submodules imported by ``python -m spectralshell ARGS``."""
    proc = subprocess.run([sys.executable, "-X", "importtime", "-m", "spectralshell", *args],
                          capture_output=True, text=True, cwd=ROOT,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    names = set()
    for line in proc.stderr.splitlines():
        if line.startswith("import time:") and "|" in line:
            name = line.rsplit("|", 1)[1].strip()
            names.add(name if name.startswith("scipy.") else name.split(".")[0])
    return names


@pytest.mark.parametrize("args", [("--version",), ("--help",)])
def test_version_and_help_import_no_scipy(args):
    found = imported(*args)
    assert "spectralshell" in found
    assert not found & {"scipy", "xarray", "pandas", "tqdm", "matplotlib"}, found


def test_a_mathieu_floquet_imports_only_what_it_uses():
    found = imported("floquet", "mathieu", "--kappa", "0.25", "--nu", "0.1", "--json")
    assert "scipy.linalg" in found  # the eigenvalue solves
    assert not found & {"xarray", "pandas", "matplotlib", "scipy.optimize", "scipy.special"}, found


def test_import_spectralshell_is_light():
    proc = subprocess.run([sys.executable, "-c", "import sys, spectralshell as ss; "
                           "print(sorted(m for m in ('scipy', 'xarray', 'pandas') if m in sys.modules)); "
                           "print(ss.floquet('mathieu', kappa=0.25, nu=0.1).subharmonic.tau_min > 0)"],
                          capture_output=True, text=True, cwd=ROOT,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert proc.stdout.split("\n")[:2] == ["[]", "True"], proc.stderr


def test_the_benchmark_takes_the_median_of_pairwise_ratios():
    found = bench_startup.Startup(package=(1.0, 3.0, 1.2), baseline=(0.5, 1.0, 0.4))
    assert found.ratios == pytest.approx((2.0, 3.0, 3.0))
    assert found.ratio == pytest.approx(3.0)
    one = bench_startup.measure(("--version",), runs=1)
    assert len(one.package) == len(one.baseline) == 1 and min(one.package + one.baseline) > 0
