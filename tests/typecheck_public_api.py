"""Uses of the public API with the types a user relies on; checked by mypy (tests/test_typing.py),
never run. A signature that stops accepting these arguments, or a return type that changes,
fails the check."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

import spectralshell as ss
from spectralshell.results.floquet import (ExponentsResult, FloquetResult, StabilityResult,
                                           TonguesResult)
from spectralshell.results.modes import NaturalModesResult
from spectralshell.results.records import MarginalTau
from spectralshell.results.response import ResponseResult
from spectralshell.results.stepped import SteppedRun
from spectralshell.results.trajectory import Trajectory


def uses() -> None:
    """Each call as the README and the examples write it, with the type of its result."""
    res: FloquetResult = ss.floquet("mathieu", kappa=0.25, nu=0.1, kind="subharmonic", tol=1e-10)
    sub: MarginalTau | None = res.subharmonic
    diagram: TonguesResult = ss.tongues("mathieu", kappa="0:3:301", nu=0.1, workers=1)
    ss.tongues("mathieu", kappa=np.linspace(0.1, 3.0, 30), nu=0.1)
    ss.tongues("mathieu", kappa=[0.25, 1.0], nu=0.1, tau_max=1.0)
    gamma: np.ndarray = ss.exponents("mathieu", kappa=1, nu=0.1, tau=0.3).gamma
    verdict: StabilityResult = ss.stability("sphere", tau=0.45, m="2:6", kappa=0.02, nu=0.006)
    ss.stability("sphere", tau=0.45, m=[2, 3], kappa=0.02, nu=0.006)
    modes: NaturalModesResult = ss.natural_modes("sphere", m=2, zeta=0.01, count=1)
    ss.natural_modes("cochlea", physical={"sigma": 6e5}, n_spatial=16)
    tone: ResponseResult = ss.response("cochlea", omega=1000.0, kind="tone")
    fine: xr.Dataset = ss.tau_map("sphere", x=("kappa", "0.01:0.3:50"), y=("nu", "1e-4:1e-2:50"),
                                  m="2:6", physical=None, workers=1)
    swept: xr.Dataset = ss.sweep(Path("map.toml"), executor="serial", out="map.zarr")
    again: xr.Dataset = ss.open_sweep("map.zarr")
    run: Trajectory | SteppedRun = ss.simulate({"params": {"kappa": 0.06, "nu": 0.002,
                                                           "tau": 0.25}})
    if isinstance(run, Trajectory):
        print(run.modes, run.fits)
    stepped = ss.simulate("fibre", m=3, kappa=0.02, nu=2e-4, tau=0.124)
    if isinstance(stepped, SteppedRun):
        rate: float = stepped.growth_rate + stepped.error_estimate
        print(rate, stepped.series, stepped.values.shape)
    c: float = ss.lp_coefficient(2)
    names: tuple[str, ...] = ss.models()
    scene: dict[str, object] = ss.run_scene("scene.toml", workers=1)
    error: type[ValueError] = ss.ParameterError
    print(res, sub, diagram, gamma, verdict, modes, tone, fine, swept, again, run, c, names, scene,
          error, ss.__version__)
