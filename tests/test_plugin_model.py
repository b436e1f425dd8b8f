"""A model that lives only in this test, added through the public plug-in interface
(``spectralshell.models.register``), runs floquet, tongues, exponents, a sweep and the CLI with no
edit to the package (issue 24). Its numbers are checked against oracles independent of the Hill
method: scipy's Mathieu characteristic values (uncoupled) and a solve_ivp monodromy matrix."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
import scipy.special as special
from scipy.integrate import solve_ivp

import spectralshell as ss
from spectralshell import cli
from spectralshell._validate import require_nonnegative
from spectralshell.errors import ParameterError
from spectralshell.models import HillSystem, Model, register, unregister


@dataclass(frozen=True, kw_only=True)
class TwinParams:
    """Two damped oscillators joined by a spring; the stiffness of each is pumped."""

    kappa: float = field(metadata={"help": "stiffness of oscillator 1", "units": "1"})
    ratio: float = field(default=2.0, metadata={"help": "stiffness of oscillator 2 / kappa",
                                                "units": "1"})
    coupling: float = field(default=0.0, metadata={"help": "coupling spring / kappa",
                                                   "units": "1"})
    nu: float = field(default=0.0, metadata={"help": "damping per unit time", "units": "1"})

    def __post_init__(self) -> None:
        for name in ("kappa", "ratio", "coupling", "nu"):
            object.__setattr__(self, name, require_nonnegative(name, getattr(self, name)))


def stiffness(p: TwinParams) -> np.ndarray:
    """K of u'' + nu u' + K u + 2 tau sin(t) G u = 0."""
    c = p.coupling
    return p.kappa * np.array([[1.0 + c, -c], [-c, p.ratio + c]])


def pumped(p: TwinParams) -> np.ndarray:
    """G: the oscillators' own springs are pumped, the coupling spring is not."""
    return p.kappa * np.diag([1.0, p.ratio])


def twin_hill_system(p: TwinParams) -> HillSystem:
    """D(s) = (s^2 + nu s) I + K, G = kappa diag(1, ratio): form (1) of models/base.py."""
    k = stiffness(p)
    eye = np.eye(2)
    highest = float(np.sqrt(np.linalg.eigvalsh(k).max()))
    return HillSystem(
        name="twin", block_size=2, forcing=pumped(p),
        unforced=lambda s: (s * s + p.nu * s)[:, None, None] * eye + k,
        polynomial=(k, p.nu * eye, eye), n_resonant=highest, n_highest=highest)


TWIN = Model(name="twin", summary="two coupled damped oscillators (test plug-in)",
             params=TwinParams, hill_system=twin_hill_system)


@pytest.fixture
def twin():
    register(TWIN)
    yield "twin"
    if "twin" in ss.models():
        unregister("twin")


def monodromy(p: TwinParams, tau: float) -> np.ndarray:
    """4 x 4 monodromy matrix over one period 2 pi, scipy DOP853 at rtol 1e-12 (oracle)."""
    k, g = stiffness(p), pumped(p)

    def rhs(t, y):
        u, v = y[:2], y[2:]
        return np.concatenate([v, -p.nu * v - (k + 2 * tau * np.sin(t) * g) @ u])

    cols = [solve_ivp(rhs, (0, 2 * np.pi), y0, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
            for y0 in np.eye(4)]
    return np.column_stack(cols)


def test_the_plug_in_is_listed_and_its_parameters_checked(twin):
    assert "twin" in ss.models()
    with pytest.raises(ParameterError, match="nu"):
        ss.floquet("twin", kappa=0.3, nu=-1.0)
    unregister("twin")
    assert "twin" not in ss.models()
    with pytest.raises(ParameterError, match="model = 'twin'"):
        ss.floquet("twin", kappa=0.3)


@pytest.mark.parametrize("order,char_value,kind", [(1, special.mathieu_a, "subharmonic"),
                                                    (2, special.mathieu_b, "harmonic")])
def test_uncoupled_boundaries_are_scipy_mathieu_values_of_either_oscillator(twin, order,
                                                                            char_value, kind):
    """Oracle: with coupling 0 the twins are two Mathieu equations, kappa and ratio * kappa;
    at 4 kappa_j = a_r(q) a marginal tau is q / (4 kappa_j) (t = 2x - pi/2, tests/test_mathieu)."""
    q = 0.8
    kappa_2 = char_value(order, q) / 4  # the second oscillator sits on the curve
    ratio = 1.7
    res = getattr(ss.floquet("twin", kind=kind, kappa=kappa_2 / ratio, ratio=ratio), kind)
    assert np.min(np.abs(res.tau - q / (4 * kappa_2))) < 1e-10


@pytest.mark.parametrize("kind,target", [("harmonic", 1.0), ("subharmonic", -1.0)])
def test_coupled_damped_tau_min_gives_monodromy_multiplier(twin, kind, target):
    """Oracle: at tau_min one eigenvalue of the solve_ivp monodromy matrix is +1 (harmonic) or
    -1 (subharmonic)."""
    p = TwinParams(kappa=0.3, ratio=1.5, coupling=0.4, nu=0.05)
    res = getattr(ss.floquet("twin", kind=kind, kappa=p.kappa, ratio=p.ratio,
                             coupling=p.coupling, nu=p.nu), kind)
    assert res.error_estimate < 1e-10
    multipliers = np.linalg.eigvals(monodromy(p, res.tau_min))
    assert np.min(np.abs(multipliers - target)) < 1e-7


def test_exponents_are_logarithms_of_the_monodromy_multipliers(twin):
    p = TwinParams(kappa=0.3, ratio=1.5, coupling=0.4, nu=0.05)
    tau = 0.2
    res = ss.exponents("twin", tau=tau, kappa=p.kappa, ratio=p.ratio, coupling=p.coupling,
                       nu=p.nu)
    got = np.exp(2 * np.pi * np.asarray(res.gamma))
    want = np.linalg.eigvals(monodromy(p, tau))
    assert got.shape == want.shape
    assert max(np.min(np.abs(got - w)) for w in want) < 1e-8
    assert max(np.min(np.abs(want - g)) for g in got) < 1e-8


def test_tongues_a_sweep_and_a_map_agree_with_the_point_solve_and_the_oracle(twin):
    p = TwinParams(kappa=0.3, ratio=1.5, coupling=0.4, nu=0.05)
    kappas = [0.2, 0.3, 0.45]
    diagram = ss.tongues("twin", kappa=kappas, kind="subharmonic", ratio=p.ratio,
                         coupling=p.coupling, nu=p.nu, tips=False, workers=1)
    scene = {"model": "twin", "ask": ["tau_min"],
             "params": {"ratio": p.ratio, "coupling": p.coupling, "nu": p.nu},
             "grid": {"kappa": kappas, "kind": ["subharmonic"]}, "tau_min": {"tau_max": 2.0}}
    data = ss.sweep(scene, executor="processes", workers=2)
    swept = data["tau_min"].sel(kind="subharmonic").values
    for kappa, row, tau in zip(kappas, diagram.rows, swept):
        tau_min = row["subharmonic"].tau_min
        assert abs(tau - tau_min) < 1e-9
        q = TwinParams(kappa=kappa, ratio=p.ratio, coupling=p.coupling, nu=p.nu)
        multipliers = np.linalg.eigvals(monodromy(q, tau_min))
        assert np.min(np.abs(multipliers + 1.0)) < 1e-7
    mapped = ss.tau_map("twin", x=("kappa", kappas), y=("nu", [p.nu]), kind="subharmonic",
                        tau_max=2.0, tol=1e-10, ratio=p.ratio, coupling=p.coupling, workers=1)
    np.testing.assert_allclose(mapped["tau_min"].sel(kind="subharmonic").values[:, 0], swept,
                               atol=1e-9)


def test_the_cli_offers_the_plug_in_with_its_parameters(twin, capsys):
    with pytest.raises(SystemExit):
        cli.main(["floquet", "twin", "-h"])
    help_text = capsys.readouterr().out
    assert "--coupling" in help_text and "coupling spring / kappa [dimensionless]" in help_text
    assert cli.main(["floquet", "twin", "--kappa", "0.3", "--ratio", "1.5", "--coupling", "0.4",
                     "--nu", "0.05", "--kind", "subharmonic", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    want = ss.floquet("twin", kind="subharmonic", kappa=0.3, ratio=1.5, coupling=0.4, nu=0.05)
    assert out["subharmonic"]["tau_min"] == pytest.approx(want.subharmonic.tau_min, abs=1e-12)
    assert cli.main(["floquet", "twin", "--kappa", "-1"]) == 2
    assert "kappa" in capsys.readouterr().err


def test_an_installed_plug_in_reaches_the_command_line(tmp_path, twin):
    """A distribution declaring the entry point ``spectralshell.models`` (here a bare dist-info
    directory on the path, as pip would leave it) adds its model to ``spectralshell``."""
    (tmp_path / "twin_plugin.py").write_text(
        "from spectralshell.models import register\n"
        "from test_plugin_model import TWIN\n"
        "register(TWIN)\n")
    info = tmp_path / "twin_plugin-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: twin-plugin\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[spectralshell.models]\ntwin = twin_plugin\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(tmp_path), str(Path(__file__).parent), os.environ.get("PYTHONPATH", "")])}
    run = subprocess.run([sys.executable, "-m", "spectralshell", "floquet", "twin", "--kappa",
                          "0.3", "--kind", "subharmonic", "--json"], capture_output=True,
                         text=True, env=env, timeout=120)
    assert run.returncode == 0, run.stderr
    want = ss.floquet("twin", kind="subharmonic", kappa=0.3)
    got = json.loads(run.stdout)["subharmonic"]["tau_min"]
    assert got == pytest.approx(want.subharmonic.tau_min, abs=1e-12)
    (info / "entry_points.txt").write_text("[spectralshell.models]\ntwin = no_such_module\n")
    run = subprocess.run([sys.executable, "-m", "spectralshell", "floquet", "mathieu", "--kappa",
                          "0.3"], capture_output=True, text=True, env=env, timeout=120)
    assert run.returncode == 2
    assert "plug-in 'twin'" in run.stderr and "no_such_module" in run.stderr
