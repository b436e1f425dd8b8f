"""The package as published: `python -m build` makes an sdist and a wheel (built from the sdist,
so the sdist carries the C sources and scenes), and the wheel, installed into a fresh venv, runs
`spectralshell demo`."""

from __future__ import annotations

import json
import os
import site
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SDIST_MEMBERS = ["spectralshell/solvers/_tridiagonal.c", "spectralshell/solvers/_schur.c",
                 "spectralshell/special/_lentz.c",
                 "spectralshell/params/scenes/demo.toml", "spectralshell/scenes/fig-5.18-human.toml",
                 "spectralshell/scenes/fig-5.18-gerbil.toml", "spectralshell/py.typed", "LICENSE"]


def _clean_env() -> dict[str, str]:
    """The environment without PYTHONPATH, so that only installed code can be imported."""
    return {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}


def _dependency_paths() -> list[str]:
    """The site-packages directories of the running interpreter (numpy, scipy, shtns, ...)."""
    return [p for p in site.getsitepackages() if Path(p).is_dir()]


@pytest.mark.slow
def test_wheel_installs_into_a_fresh_venv_and_runs_the_demo(tmp_path):
    dist = tmp_path / "dist"
    subprocess.run([sys.executable, "-m", "build", "--outdir", str(dist), str(ROOT)], check=True,
                   capture_output=True, env=_clean_env())
    (sdist,) = dist.glob("spectralshell-*.tar.gz")
    (wheel,) = dist.glob("spectralshell-*.whl")
    with tarfile.open(sdist) as tar:
        names = {name.split("/", 1)[1] for name in tar.getnames() if "/" in name}
    assert set(SDIST_MEMBERS) <= names
    with zipfile.ZipFile(wheel) as whl:
        shipped = whl.namelist()
    assert "spectralshell/py.typed" in shipped
    assert any(n.startswith("spectralshell/solvers/_tridiagonal.") and n.endswith(".so")
               for n in shipped)

    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    purelib = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()"
                              "['purelib'])"], check=True, capture_output=True, text=True).stdout
    # the heavy dependencies come from this interpreter's site-packages, appended after the new
    # venv's own (a plain path line: no .pth of those directories, such as an editable install's
    # finder, is run)
    Path(purelib.strip(), "_dependencies.pth").write_text("\n".join(_dependency_paths()) + "\n")
    # pip (from those directories too) run by the new interpreter installs into the new venv
    subprocess.run([str(python), "-m", "pip", "install", "-q", "--no-deps", "--no-index",
                    str(wheel)], check=True, env=_clean_env())

    where = subprocess.run(
        [str(python), "-c", "import spectralshell, spectralshell.solvers._tridiagonal as k; "
         "print(spectralshell.__file__); print(k.__file__)"],
        check=True, capture_output=True, text=True, cwd=tmp_path, env=_clean_env()).stdout.split()
    for path in where:
        assert Path(path).resolve().is_relative_to(venv.resolve())

    script = venv / "bin" / "spectralshell"
    assert script.read_text().splitlines()[0] == f"#!{python}"  # the entry point runs the venv's
    out = tmp_path / "demo-output"
    run = subprocess.run([str(script), "demo", "--out", str(out)],
                         capture_output=True, text=True, cwd=tmp_path, env=_clean_env())
    assert run.returncode == 0, run.stderr
    assert "tau_min" in run.stdout
    assert (out / "ince_strutt.png").stat().st_size > 10_000
    assert set(json.loads((out / "demo.json").read_text())) == {"floquet", "tongues", "exponents"}
