"""Simulation scenes: validated input of ``spectralshell simulate`` / ``ss.simulate``.

A scene (TOML file, TOML string or mapping) of the sphere::

    model = "sphere"
    [params]
    kappa = 0.06           # or an expression in theta (polar), phi (azimuth): non-uniform kappa
    nu = 0.002             # 0: inviscid (the Mathieu equation per degree, no fluid grid)
    tau = 0.25             # K = kappa (1 + 2 tau sin t)
    [initial]
    shape = "2:0"          # radial displacement: modes "m:k[:amplitude], ..." (real orthonormal
                           # harmonics Yr_{m,k}, k = -m..m) or an expression in theta, phi
    amplitude = 0.05       # amplitude of listed modes without one
    twist = "3:1"          # optional tangential (toroidal X^Phi) displacement, same syntax
    [simulate]
    t_end = 200
    scheme = "SBDF3"       # a name of spectralshell.solvers.imex.SCHEMES
    dt = 0.01              # optional (default: from the fastest degree, aligned to 2 pi)
    n_radial = 48          # optional radial nodes per side (default: chosen to reach tol)
    tol = 1e-9             # target relative spatial error
    l_max = 24             # degree cut-off of expressions (shape, kappa) and, when given, of the
                           # degrees a non-uniform kappa couples (default there: two products)
    [output]
    dir = "simulate-output"

Expressions (e.g. "0.05*sin(theta)**2*cos(2*phi)") are arithmetic in theta and phi: numbers, pi, e,
+ - * / **, parentheses and sin, cos, tan, exp, log, sqrt, abs; nothing else is accepted (no Python,
no sympy). They must be finite everywhere on the sphere, and a kappa expression positive; see
:mod:`spectralshell.params.expression` for the grammar and its limits (length, nesting, exponents).

Every other model that can be time-stepped (the fibre, the cochlea, a plug-in registered with a
:class:`~spectralshell.params.registry.TimeStepping`) takes in its scene exactly the keywords of
``ss.simulate(model, ...)``, each in its table (:func:`keyword_table`): the model's parameters
and tau in [params], amplitude in [initial], the run's settings in [simulate]::

    model = "cochlea"
    [params]
    kappa = 1.0
    nu = 1e-3
    alpha = 0.5
    n_spatial = 4          # the fibre: m, kappa, nu, forcing
    tau = 0.26
    [initial]
    amplitude = 1.0
    [simulate]
    t_end = 376.99         # >= 20 pi; scheme, dt, max_seconds and the resolution (the fibre:
    n_vertical = 48        # n_inner, n_outer; the cochlea: n_vertical, vertical_scale)
    [output]
    dir = "simulate-output"

:func:`simulation_scene` checks the tables, their keys, the required keywords and the model's
parameters; the stepper checks the run's settings and prices the run before any work.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._validate import (parse_int, parse_real, require_choice, require_int_in_range,
                         require_nonnegative, require_positive, require_real)
from ..errors import ParameterError
from .expression import Expression, parse_expression
from .registry import TimeStepping, get_model, make_params, models_with, param_names
from .scene import load_scene
from .stiffness import amplitude_warnings

KEYS = {"model", "params", "initial", "simulate", "output"}
PARAM_KEYS = {"kappa", "nu", "tau"}
INITIAL_KEYS = {"shape", "amplitude", "twist"}
SIMULATE_KEYS = {"t_end", "scheme", "dt", "n_radial", "tol", "l_max"}
DEFAULT_AMPLITUDE = 0.05
L_MAX = 24
_MODE = re.compile(r"^\s*(\d+)\s*:\s*([+-]?\d+)\s*(?::\s*([^,]+?))?\s*$")


@dataclass(frozen=True, kw_only=True, eq=False)
class SimulationScene:
    """A validated simulation scene (see the module docstring).

    kappa : a number (uniform) or an :class:`Expression` (non-uniform kappa(theta, phi)).
    shape, twist : {(m, k): amplitude} of the radial (X^Y) and toroidal (X^Phi) displacement,
        or an :class:`Expression` (shape only).
    """

    model: str
    kappa: float | Expression
    nu: float
    tau: float
    shape: dict[tuple[int, int], float] | Expression
    twist: dict[tuple[int, int], float]
    t_end: float
    scheme: str
    dt: float | None
    n_radial: int | None
    tol: float
    l_max: int
    l_max_given: bool
    output_dir: str
    warnings: tuple[str, ...] = field(default=())

    def params(self) -> dict[str, Any]:
        """The physical parameters as JSON values."""
        kappa = self.kappa.text if isinstance(self.kappa, Expression) else self.kappa
        return {"kappa": kappa, "nu": self.nu, "tau": self.tau}


#: The run keywords every time stepper takes (``ss.simulate(model, ...)``), -> (type, help).
RUN_KEYWORDS: dict[str, tuple[Any, str]] = {
    "tau": (float, "forcing amplitude tau: the stiffness times (1 + 2 tau sin t) (default 0)"),
    "t_end": (float, "end time"),
    "scheme": (str, "IMEX scheme (SBDF1-4, CNAB2, MCNAB2, RK111, RK222, RK443; default SBDF3)"),
    "dt": (float, "time step (default: from the fastest mode, a whole number of steps a "
                  "forcing period)"),
}

#: The sphere's keywords: those of a scene's [params], [initial] and [simulate] (module
#: docstring), and m, the degree of an initial (m, 0) shape, in place of ``shape``.
SPHERE_STEPPING = TimeStepping(
    runner="spectralshell.runner.simulate:simulate_sphere",
    keywords={"m": (int, "degree of the initial (m, 0) shape (or give shape)"),
              "shape": (str, "initial shape: modes 'm:k[:amplitude], ...' or an expression in "
                             "theta (polar), phi (azimuth)"),
              "kappa": ((float, str), "stiffness kappa (or an expression in theta, phi)"),
              "nu": (float, "viscosity nu (0: inviscid)"),
              **RUN_KEYWORDS,
              "amplitude": (float, f"amplitude of listed modes without one (default "
                                   f"{DEFAULT_AMPLITUDE})"),
              "twist": (str, "initial toroidal displacement, modes 'm:k[:amplitude], ...'"),
              "n_radial": (int, "radial nodes per side (default: chosen to reach tol)"),
              "tol": (float, "target relative spatial error (default 1e-9)"),
              "l_max": (int, f"degree cut-off of expressions (default {L_MAX})")},
    required=("kappa", "nu", "t_end"),
    initial="the membrane displaced in the given harmonic modes (or an expression), the fluid "
            "at rest", figures=("", "_shape"))


#: Default run length of the fibre's and the cochlea's steppers: 60 forcing periods.
STEPPED_T_END = 120 * math.pi
_STEPPED_RUN = {**RUN_KEYWORDS,
                "t_end": (float, "end time, >= 20 pi: ten forcing periods (default 120 pi, "
                                 "sixty)")}
_MAX_SECONDS = {"max_seconds": (float, "raise the limit on the estimated run time (default "
                                       "600 s, or $SPECTRALSHELL_MAX_SECONDS)")}

#: The fibre's keywords (:func:`spectralshell.runner.fibre_stepping.simulate_fibre`).
FIBRE_STEPPING = TimeStepping(
    runner="spectralshell.runner.fibre_stepping:simulate_fibre",
    keywords={"m": None, "kappa": None, "nu": None, "forcing": None, **_STEPPED_RUN,
              "amplitude": (float, "initial X^r (nonzero; X^theta = -X^r/m; default 1)"),
              "n_inner": (int, "radial unknowns per field inside (default 48)"),
              "n_outer": (int, "radial unknowns per field outside (default 64)"), **_MAX_SECONDS},
    required=("m", "kappa", "nu"),
    initial="X = amplitude (1, -1/m) (the inviscid mode's shape), the fluid at rest",
    figures=("",))

#: The cochlea's keywords (:func:`spectralshell.runner.cochlea_stepping.simulate_cochlea`).
COCHLEA_STEPPING = TimeStepping(
    runner="spectralshell.runner.cochlea_stepping:simulate_cochlea",
    keywords={"kappa": None, "nu": None, "alpha": None,
              "n_spatial": (int, "number M of cosine modes (required: a fixed M)"), **_STEPPED_RUN,
              "amplitude": (float, "scale of the initial state (nonzero; default 1)"),
              "n_vertical": (int, "vertical unknowns per field and mode (default 48)"),
              "vertical_scale": (float, "L of the vertical map y = L (1/xi - 1) (default 1)"),
              **_MAX_SECONDS},
    required=("kappa", "nu", "alpha", "n_spatial"),
    initial="the sum of the real parts of every oscillatory natural mode of the stepped system, "
            "fluid included, each of largest membrane amplitude 1, times amplitude",
    figures=("",))


@dataclass(frozen=True, kw_only=True, eq=False)
class SteppedScene:
    """A validated simulation scene of a model other than the sphere (module docstring): the
    keywords of ``ss.simulate(model, **keywords)``, gathered from its tables."""

    model: str
    keywords: dict[str, Any]
    output_dir: str


def keyword_table(model: str, name: str) -> str:
    """The scene table of keyword ``name`` of ``ss.simulate(model, ...)``: 'initial' (the
    initial state: shape, amplitude, twist), 'params' (tau and the model's parameters) or
    'simulate' (the run's settings)."""
    if name in INITIAL_KEYS:
        return "initial"
    return "params" if name == "tau" or name in param_names(model) else "simulate"


def sphere_scene(keywords: Mapping[str, Any]) -> dict[str, Any]:
    """The scene of ``ss.simulate("sphere", **keywords)`` (keywords of :data:`SPHERE_STEPPING`;
    exactly one of m and shape)."""
    values = dict(keywords)
    m, shape = values.pop("m", None), values.pop("shape", None)
    if (m is None) == (shape is None):
        raise ParameterError("give exactly one of m= (degree of the initial (m, 0) shape) and "
                             "shape= (modes 'm:k[:amplitude], ...' or an expression in theta, "
                             "phi)")
    if m is not None:
        shape = f"{require_int_in_range('initial degree m', m, 2, 200)}:0"
    tables: dict[str, dict[str, Any]] = {"params": {}, "initial": {"shape": shape},
                                         "simulate": {}}
    for name, value in values.items():
        tables[keyword_table("sphere", name)][name] = value
    return {"model": "sphere", **tables}


def parse_modes(name: str, spec: Any, amplitude: float) -> dict[tuple[int, int], float]:
    """{(m, k): amplitude} from "m:k[:a], ..." or a list of [m, k] / [m, k, a]."""
    items = []
    if isinstance(spec, str):
        for part in spec.split(","):
            match = _MODE.match(part)
            if not match:
                raise ParameterError(f"{name} = {spec!r} is invalid: must be modes 'm:k[:amplitude]' "
                                     "separated by commas, e.g. '2:0' or '2:0, 3:1:0.02'")
            m, k, a = match.groups()
            items.append((parse_int(f"{name} degree m", m), parse_int(f"{name} order k", k),
                          amplitude if a is None else parse_real(f"{name} amplitude", a)))
    elif isinstance(spec, (list, tuple)):
        for entry in spec:
            if not isinstance(entry, (list, tuple)) or len(entry) not in (2, 3):
                raise ParameterError(f"{name} = {spec!r} is invalid: each mode must be [m, k] or "
                                     "[m, k, amplitude]")
            items.append((entry[0], entry[1], entry[2] if len(entry) == 3 else amplitude))
    else:
        raise ParameterError(f"{name} = {spec!r} is invalid: must be a mode list or an expression")
    out: dict[tuple[int, int], float] = {}
    for m, k, a in items:
        m = require_int_in_range(f"{name} degree m", m, 2, 200)
        k = int(require_int_in_range(f"{name} order k", k, -m, m))
        out[(m, k)] = out.get((m, k), 0.0) + require_real(f"{name} amplitude", a)
    return out


def _is_mode_list(spec: Any) -> bool:
    return not isinstance(spec, str) or all(_MODE.match(p) for p in spec.split(","))


def _table(data: Mapping, key: str, allowed: set) -> dict:
    table = data.get(key, {})
    if not isinstance(table, Mapping):
        raise ParameterError(f"{key} = {table!r} is invalid: must be a table")
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise ParameterError(f"{key}.{unknown[0]} is unknown: expected "
                             f"{', '.join(sorted(allowed)) or 'no keys'}")
    return dict(table)


def _output_dir(data: Mapping) -> str:
    out_dir = _table(data, "output", {"dir"}).get("dir", "simulate-output")
    if not isinstance(out_dir, str):
        raise ParameterError(f"output.dir = {out_dir!r} is invalid: must be a string")
    return out_dir


def simulation_scene(scene: str | Path | Mapping) -> SimulationScene | SteppedScene:
    """Validate a simulation scene; nothing is computed. ``model`` (default 'sphere') is a
    model that can be time-stepped; the sphere's scene is a :class:`SimulationScene`, every
    other model's a :class:`SteppedScene` (module docstring).

    Raises
    ------
    ParameterError : unknown keys, missing or out-of-range values.
    """
    data = load_scene(scene)
    unknown = sorted(set(data) - KEYS)
    if unknown:
        raise ParameterError(f"scene key {unknown[0]!r} is unknown: expected {', '.join(sorted(KEYS))}")
    model = require_choice("model", data.get("model", "sphere"), models_with("time_stepping"))
    if model != "sphere":
        return _stepped_scene(model, data)
    params = _table(data, "params", PARAM_KEYS)
    initial = _table(data, "initial", INITIAL_KEYS)
    sim = _table(data, "simulate", SIMULATE_KEYS)
    out_dir = _output_dir(data)
    for key in ("kappa", "nu"):
        if key not in params:
            raise ParameterError(f"params.{key} is missing: the sphere needs kappa and nu")
    kappa_spec = params["kappa"]
    kappa: float | Expression
    try:
        kappa = require_positive("kappa", kappa_spec)
    except ParameterError:
        if not isinstance(kappa_spec, str):
            raise
        kappa = parse_expression("kappa", kappa_spec, positive=True)
    nu = require_nonnegative("nu", params["nu"])
    tau = require_real("tau", params.get("tau", 0.0))
    warnings = amplitude_warnings(tau)
    amplitude = require_real("initial.amplitude", initial.get("amplitude", DEFAULT_AMPLITUDE))
    if "shape" not in initial:
        raise ParameterError("initial.shape is missing: give modes, e.g. '2:0', or an expression "
                             "in theta, phi")
    spec = initial["shape"]
    shape = (parse_modes("initial.shape", spec, amplitude) if _is_mode_list(spec)
             else parse_expression("initial.shape", spec))
    twist = parse_modes("initial.twist", initial["twist"], amplitude) if "twist" in initial else {}
    if "t_end" not in sim:
        raise ParameterError("simulate.t_end is missing: the end time of the run")
    t_end = require_positive("simulate.t_end", sim["t_end"])
    scheme = sim.get("scheme", "SBDF3")
    if not isinstance(scheme, str):
        raise ParameterError(f"simulate.scheme = {scheme!r} is invalid: must be a scheme name")
    scheme = scheme.upper()   # checked against the scheme registry by the solver
    dt = None if sim.get("dt") is None else require_positive("simulate.dt", sim["dt"])
    n_radial = (None if sim.get("n_radial") is None
                else require_int_in_range("simulate.n_radial", sim["n_radial"], 14, 2000))
    tol = require_positive("simulate.tol", sim.get("tol", 1e-9))
    l_max = require_int_in_range("simulate.l_max", sim.get("l_max", L_MAX), 2, 200)
    return SimulationScene(model=model, kappa=kappa, nu=nu, tau=tau, shape=shape, twist=twist,
                           t_end=t_end, scheme=scheme, dt=dt, n_radial=n_radial, tol=tol,
                           l_max=l_max, l_max_given="l_max" in sim, output_dir=out_dir,
                           warnings=tuple(warnings))


def _stepped_scene(model: str, data: Mapping) -> SteppedScene:
    """The :class:`SteppedScene` of ``model``: each table's keys among the keywords of
    ``ss.simulate(model, ...)`` that belong in it, the required ones given, the model's
    parameters valid."""
    stepping = get_model(model).time_stepping
    assert stepping is not None   # models_with("time_stepping") chose the model
    allowed: dict[str, set[str]] = {"params": set(), "initial": set(), "simulate": set()}
    for name in stepping.keywords:
        allowed[keyword_table(model, name)].add(name)
    keywords: dict[str, Any] = {}
    for table, names in allowed.items():
        keywords.update(_table(data, table, names))
    missing = [k for k in stepping.required if k not in keywords]
    if missing:
        needs = ", ".join(f"{keyword_table(model, k)}.{k}" for k in stepping.required)
        raise ParameterError(f"{keyword_table(model, missing[0])}.{missing[0]} is missing: a "
                             f"{model} simulation needs {needs}")
    make_params(model, {k: v for k, v in keywords.items() if k in param_names(model)})
    return SteppedScene(model=model, keywords=keywords, output_dir=_output_dir(data))
