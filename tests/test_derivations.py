"""The sympy derivations behind the formulas still hold (each script exits 0 when they do)."""

import subprocess
import sys
from pathlib import Path

import pytest

DERIVATIONS = Path(__file__).resolve().parents[1] / "derivations"


#: The scripts that take 17-40 s each run with the slow tests (make test-all), the others
#: with make test (kept under 10 minutes).
LONG = pytest.mark.slow


@pytest.mark.parametrize("script", [
    "mathieu_mapping.py", pytest.param("sphere_linear.py", marks=LONG),
    pytest.param("fibre_linear.py", marks=LONG), "cochlea_linear.py", "cochlea_wkb.py",
    "fibre_modes.py", pytest.param("fibre_radial.py", marks=LONG), "cochlea_vertical.py",
    "natural_mode_blocks.py"])
def test_derivation_script_passes(script):
    done = subprocess.run([sys.executable, str(DERIVATIONS / script)], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr


@pytest.mark.slow
def test_nonuniform_stiffness_derivation_passes():
    """derivations/sphere_nonuniform.py (about 80 s: exact sympy integrals)."""
    done = subprocess.run([sys.executable, str(DERIVATIONS / "sphere_nonuniform.py")],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
