"""The public API is typed: every function spectralshell exports annotates all its parameters
and its return, and mypy, with the configuration of pyproject.toml ([tool.mypy]: the public
modules strictly, and tests/typecheck_public_api.py, which uses the API as the README does),
reports no error."""

from __future__ import annotations

import inspect
import subprocess
import sys
from pathlib import Path

import spectralshell as ss

ROOT = Path(__file__).resolve().parents[1]


def test_exported_functions_are_fully_annotated():
    functions = {name: getattr(ss, name) for name in ss.__all__
                 if inspect.isfunction(getattr(ss, name))}
    assert {"floquet", "tongues", "tau_map", "simulate", "models"} <= set(functions)
    missing = [f"{name}({p})" for name, f in functions.items()
               for p, param in inspect.signature(f).parameters.items()
               if param.annotation is inspect.Parameter.empty]
    missing += [f"{name} -> ?" for name, f in functions.items()
                if inspect.signature(f).return_annotation is inspect.Signature.empty]
    assert missing == []


def test_mypy_reports_no_error():
    run = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental",
                          "--cache-dir", "/dev/null"], cwd=ROOT,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert run.stdout.startswith("Success: no issues found")
