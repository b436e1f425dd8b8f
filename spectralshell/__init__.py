"""spectralshell: Floquet stability, natural modes and spectral time stepping of immersed elastic
membranes with periodically pumped stiffness K(t) = kappa (1 + 2 tau sin t).

Public API::

    import spectralshell as ss
    ss.floquet("mathieu", kappa=0.25, nu=0.1)           # marginal tau, harmonic + subharmonic
    ss.tongues("mathieu", kappa="0:3:301", nu=0.1)      # Ince-Strutt diagram + finger tips
    ss.exponents("mathieu", kappa=1, nu=0.1, tau=0.3)   # Floquet exponents gamma
    ss.stability("sphere", tau=0.45, m="2:6", kappa=0.02, nu=0.006)  # which degrees resonate
    ss.natural_modes("sphere", m=2, kappa=1, nu=0.01)   # decay rates and frequencies (tau = 0)
    ss.floquet("cochlea", omega=1000)                   # basilar membrane, Table 5.1 units
    ss.response("cochlea", omega=1000)                  # pure-tone BM envelope (thesis 5.5)
    ss.tau_map("sphere", x=("kappa", "0.01:0.3:50"), y=("nu", "1e-4:1e-2:50"), m="2:6")
    ss.models()                                         # registered models (README "Adding a model")
    ss.run_scene("scene.toml")                          # a planned scene
    ss.sweep("map.toml", out="map.zarr")                # a parameter sweep -> xarray.Dataset
    ss.lp_coefficient(2)                                # lambda = lambda0 (1 + c eps^2), thesis 7.3
    ss.simulate({"params": {"kappa": 0.06, "nu": 0.002, "tau": 0.25},
                 "initial": {"shape": "2:0"}, "simulate": {"t_end": 200}})  # time stepping
    ss.benchmark("sphere-release", radius=0.5)        # reference data for IB/FSI codes
    ss.plot.tongues(ss.tongues("mathieu", kappa="0:3:301", nu=0.1), ax=None)  # -> Axes
    ss.floquet("mathieu", kappa=0.25, nu=0.1).plot(ax=ax)  # results draw themselves too
"""

import importlib
from typing import Any

from ._version import __version__
from .errors import BackendUnavailable, ConvergenceError, ParameterError, SpectralShellError
from .models import models  # registers the built-in models (light: no scipy)

#: The public functions, defined in :mod:`spectralshell.api` and imported on first use
#: (PEP 562), so that ``import spectralshell`` -- and every command-line start, ``--version``
#: included -- does not pay for scipy and the solvers until a computation needs them.
_LAZY = dict.fromkeys(("benchmark", "exponents", "floquet", "lp_coefficient", "natural_modes", "open_sweep",
                       "response", "run_scene", "simulate", "stability", "sweep", "tau_map",
                       "tongues"), ".api")

__all__ = ["__version__", "floquet", "tongues", "exponents", "stability", "natural_modes", "tau_map",
           "run_scene", "sweep", "open_sweep", "lp_coefficient", "simulate", "response", "benchmark", "models",
           "SpectralShellError", "ParameterError", "ConvergenceError", "BackendUnavailable", "plot"]


def __getattr__(name: str) -> Any:
    """The public functions (from :mod:`spectralshell.api`) and ``spectralshell.plot`` (the
    drawing functions, :mod:`spectralshell.plots.public`), imported on first use."""
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name], __name__), name)
    if name == "plot":
        return importlib.import_module(".plots.public", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY) | {"plot"})
