"""Sweep scenes: a scene with a [grid] table -> a validated, hashable SweepSpec (no computing).

A sweep scene::

    model = "sphere"
    ask = ["tau_min"]
    [params]                       # fixed parameters of the model
    nu = 2.39e-4
    [grid]                         # swept parameters; the axes keep this order
    kappa = {start = 0.001, stop = 0.2, num = 200}   # linear (or spacing = "log"), or "a:b:n"
    m = [2, 3, 4, 5, 6]                              # integer parameters: a list or "lo:hi"
    kind = ["harmonic", "subharmonic"]               # default: both kinds
    [tau_min]                      # solver options of the ask (all optional)
    tol = 1e-10                    # absolute tolerance on tau_min (or n_temporal = 40)
    tau_max = 0.5                  # only marginal tau <= tau_max (0.5: the stiffness stays > 0)
    continuation = true            # start each point from its neighbour's truncation
    tol_spatial = 1e-3             # models with spatial modes (cochlea) without n_spatial only
    over_kinds = "each"            # or "minimum" (M refined per point only): see below
    [sweep]
    chunk = 256                    # points per task along the line axis (the default)

Any value list (``[0.1, 0.2, 0.4]``) works for a real parameter too. With model 'sphere' the
physical cgs quantities rho (g/cm^3), mu (g/(cm s)), radius (cm), sigma (dyn/cm) and omega
(rad/s) or bpm (beats/min) may be fixed or swept instead of kappa and nu, which then follow from
(6.4)-(6.5) (:class:`~spectralshell.params.physical.PhysicalSphere`).

With model 'cochlea' the cgs inputs rho (g/cm^3), mu (g/(cm s)), sigma (g/(cm^2 s^2), a
stiffness per unit area, = dyn/cm^3: the thesis's sigma of chapter 5), length (cm), lambda_c
(1/cm) and omega (rad/s) or frequency (Hz, omega = 2 pi f) may be fixed or swept instead of
kappa, nu and alpha (:func:`~spectralshell.params.physical.cochlea_forced`, thesis 5.2); exactly
one of omega and frequency is needed, and rho, mu, sigma, length and lambda_c left out take
their Table 5.1 values (written into the scene's fixed parameters, so they enter its hash),
unless the dimensionless parameter they set (nu, kappa, alpha) is given instead. Angular
frequencies are rad/s throughout (ERRATA); ``frequency`` in Hz is offered because audible ranges
are ranges of f in Hz -- the thesis's Fig 5.18 labels its axis "omega in [50, 20000] Hz", which
the packaged scenes spectralshell/scenes/fig-5.18-*.toml read as f in Hz (the figure's JSON
states the shift, log10(2 pi) = 0.8 decade, that the reading omega in s^-1 would give).

The sphere with a non-uniform stiffness (kappa in [params] an expression in theta, phi, e.g.
``kappa = "0.02*(1 + 0.3*cos(theta)**2)"``; :mod:`spectralshell.runner.nonuniform`) sweeps nu
and the degree truncation l_max (a list of integers, or 'lo:hi'); fixed, l_max is 'auto' (the
default: refined per point to ``tol_spatial``, default 1e-6) or an integer. Each point is the
``floquet`` of that kappa with the sweep's kinds, and the result also holds ``l_max`` (the
degree truncation of the values) and the critical mode's dominant (l, k) and its share
(``critical_l``, ``critical_k``, ``critical_share``). Its points are solved independently (no
continuation).

Models with spatial modes (the cochlea): with ``n_spatial`` fixed in [params] (or swept) every
point is solved with that M, and error_estimate is the temporal one only; without it (and
without spatial_mode) M is refined per point, M = 16, 24, 32, 48, ... <= 512, until each kind's
tau_min at M differs by at most ``tol_spatial`` from its values at the two M before (default
1e-3; see
:mod:`spectralshell.solvers.spatial_refinement`), and error_estimate includes that change. The
result then has the variables n_spatial (the M of each value) and spatial_converged (False
where M = 512 was reached first, or an empty answer of the last window of M could not be proved:
the point is kept, with its values at the last M, and flagged).
With ``over_kinds = "minimum"`` (M refined per point, both kinds) only the smallest tau_min over
the kinds is converged, as a minimum-tau map needs (thesis Fig 5.18): at each M the kind that
gave the minimum is solved first and the other only below it, up to M = 1024. The kind attaining
the minimum then has has_tau True and its tau_min; the other has has_tau False and tau_min = the
value it was resolved up to ("no tau below this"), not tau_max.

The *line axis* is the last real-valued axis of the grid (else the last axis other than kind):
points are solved along it in order, so each can start from its neighbour (continuation), and a
task (a chunk) is a run of at most ``chunk`` consecutive points of one line.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import (require_choice, require_choices, require_int_in_range, require_positive,
                         require_real)
from ..errors import ParameterError
from .grid import parse_int_range, parse_range
from .limits import SWEEP_BYTES, check_grid, check_points
from .physical import (COCHLEA_SWEEP_UNITS, PHYSICAL_UNITS, TABLE_5_1, cochlea_sweep_params,
                       sphere_forced_params)
from .registry import (check_model, get_model, int_bounds, make_params, models, param_fields,
                       param_names)
from .scene import load_scene
from .sphere import L_MAX_RANGE, is_nonuniform, nonuniform_params

ASKS = ("tau_min",)
KINDS = ("harmonic", "subharmonic")
SCENE_KEYS = ("model", "ask", "params", "grid", "tau_min", "sweep", "output")
OPTION_KEYS = ("tol", "n_temporal", "tau_max", "continuation", "tol_spatial", "over_kinds")
#: What is converged per point: every kind's tau_min ('each'), or only the smallest over the
#: kinds ('minimum': each other kind only below it, :func:`spectralshell.solvers.
#: spatial_refinement.refine_minimum`; with M refined per point and both kinds only).
OVER_KINDS = ("each", "minimum")
SWEEP_KEYS = ("chunk",)
N_TEMPORAL_MAX = 400  # = solvers.marginal.N_MAX (a later stage: not importable here)
#: Points per chunk along the line axis (lines longer than this are cut into equal pieces): the
#: unit of the store and of continuation; the runner batches consecutive chunks into tasks
#: (runner.sweep.batches). Measured in validation/bench_sweep.py with the cheapest points
#: (Mathieu, ~0.5 ms per grid point, 2-core machine): the Zarr write of a chunk (~9 ms, in the
#: main process) and the dispatch of a task (~0.5 ms on processes, ~10 ms on a Dask
#: LocalCluster); end to end (wall x workers - compute) / compute was 3.2 % with one chunk per
#: task and 1.8 % (processes) and 0.9 % (Dask) with batching; dearer models are far below.
DEFAULT_CHUNK = 256
TOL_SPATIAL = 1e-3  # = solvers.spatial_refinement.TOL_SPATIAL (a later stage: not importable here)
#: The cgs quantities the built-in models with sweep rules of their own accept in a sweep in place
#: of their dimensionless parameters (the sphere's beat rate, the cochlea's Table 5.1 defaults);
#: any other model sweeps the quantities of its physical input (:func:`physical_names`).
PHYSICAL_NAMES = {"sphere": tuple(PHYSICAL_UNITS), "cochlea": tuple(COCHLEA_SWEEP_UNITS)}
PHYSICAL = tuple(PHYSICAL_UNITS)
UNITS = {"kappa": "1", "nu": "1", "m": "1", "component": "", "kind": "", **PHYSICAL_UNITS}
MODEL_UNITS = {"cochlea": {"alpha": "1", "n_spatial": "1", "spatial_mode": "1",
                           **COCHLEA_SWEEP_UNITS}}
LONG_NAMES = {"l_max": "degree truncation l_max", "kappa": "stiffness kappa", "nu": "viscosity nu", "m": "degree m",
              "component": "component", "kind": "Floquet kind", "rho": "fluid density",
              "mu": "dynamic viscosity", "radius": "radius", "sigma": "membrane stiffness",
              "omega": "forcing angular frequency", "bpm": "beat rate",
              "frequency": "forcing frequency f", "length": "membrane length",
              "lambda_c": "stiffness decay rate", "alpha": "stiffness grading alpha",
              "n_spatial": "spatial modes M", "spatial_mode": "spatial mode"}
#: Long names of the Floquet variables of a sweep store and of a result's Dataset
#: (:meth:`spectralshell.results.base.Result.to_xarray`).
VARIABLE_LONG_NAMES = {"tau_min": "smallest marginal forcing amplitude tau <= tau_max",
                       "has_tau": "a marginal tau <= tau_max exists",
                       "error_estimate": "Floquet error estimate of tau_min",
                       "n_temporal": "final temporal truncation N",
                       "complete_to": "no real tau below this was missed (an empty point is "
                                      "proved only up to it; 0: uncertified)",
                       "n_spatial": "number of spatial modes M of the values",
                       "l_max": "degree truncation l_max of the values",
                       "critical_l": "degree l of the critical mode's largest share",
                       "critical_k": "order k of the critical mode's largest share",
                       "critical_share": "that mode's share of the critical mode's squared "
                                         "displacement norm"}
#: What a sweep of the non-uniform sphere may put in its grid (kappa, an expression, is fixed).
NONUNIFORM_GRID = ("nu", "l_max", "kind")
#: Table 5.1 defaults of a physical cochlea sweep, and the dimensionless parameter each sets.
_COCHLEA_DEFAULTS = {"rho": None, "length": None, "mu": "nu", "sigma": "kappa", "lambda_c": "alpha"}


def physical_names(model: str) -> tuple[str, ...]:
    """The cgs quantities a sweep of ``model`` may give in place of its dimensionless
    parameters: PHYSICAL_NAMES for the sphere and the cochlea, else those of the model's
    physical input (:class:`~spectralshell.params.registry.PhysicalInput`), else none."""
    if model in PHYSICAL_NAMES:
        return PHYSICAL_NAMES[model]
    physical = get_model(model).physical if model in models() else None
    return () if physical is None else tuple(physical.units)


def physical_models() -> tuple[str, ...]:
    """The registered models whose sweeps accept cgs quantities."""
    return tuple(m for m in models() if physical_names(m))


def units(model: str, name: str) -> str:
    """Units of parameter or axis ``name`` of ``model`` ('1': dimensionless)."""
    if model not in MODEL_UNITS and model not in PHYSICAL_NAMES and name in physical_names(model):
        return get_model(model).physical.units[name]
    return MODEL_UNITS.get(model, UNITS).get(name, "1")


@dataclass(frozen=True)
class Axis:
    """One swept parameter: ``name``, its ``values`` (a tuple of float, int or str), ``units``
    and ``spacing`` ('linear', 'log' or 'list', how the values were given)."""

    name: str
    values: tuple
    units: str
    spacing: str

    @property
    def is_real(self) -> bool:
        """True for a real-valued (float) axis."""
        return bool(self.values) and isinstance(self.values[0], float)


@dataclass(frozen=True)
class SolverOptions:
    """Options of the ask 'tau_min' (see :func:`spectralshell.solvers.marginal.marginal_tau`)."""

    tol: float = 1e-10
    n_temporal: int | None = None
    tau_max: float = 0.5
    continuation: bool = True
    tol_spatial: float | None = None
    over_kinds: str = "each"

    def marginal_kwargs(self) -> dict[str, Any]:
        """Keyword arguments of ``marginal_tau``: an empty answer of a viscous model is proved
        by the zero count or returned with complete_to = 0, which the sweep stores as an
        uncertified point (``certify_empty='mark'``; issue 23)."""
        return {"tol": self.tol, "n_temporal": self.n_temporal, "tau_max": self.tau_max,
                "certify_empty": "mark"}


@dataclass(frozen=True, kw_only=True)
class SweepSpec:
    """A validated sweep: model, fixed parameters, axes (grid order, 'kind' always present),
    ask, solver options, chunk length, the scene's stable hash ``digest`` (of
    :meth:`canonical`) and ``source``, the scene as given (JSON; provenance only, not hashed).
    Its derived layout (dims, shape, kinds, point and line axes, spatial) is computed once: a
    sweep reads it per point and kind."""

    model: str
    fixed: tuple[tuple[str, Any], ...]
    axes: tuple[Axis, ...]
    ask: tuple[str, ...]
    options: SolverOptions
    chunk: int
    physical: bool
    digest: str = ""
    source: str = ""

    @functools.cached_property
    def dims(self) -> tuple[str, ...]:
        """Axis names in order (the dimensions of the result)."""
        return tuple(a.name for a in self.axes)

    @functools.cached_property
    def shape(self) -> tuple[int, ...]:
        """Number of values of each axis."""
        return tuple(len(a.values) for a in self.axes)

    @property
    def size(self) -> int:
        """Number of grid points (every axis, kind included)."""
        return math.prod(self.shape)

    @functools.cached_property
    def kinds(self) -> tuple[str, ...]:
        """The Floquet kinds swept."""
        return self.axis("kind").values

    @functools.cached_property
    def point_axes(self) -> tuple[int, ...]:
        """Positions of the axes other than 'kind' (one solve of each kind per combination)."""
        return tuple(i for i, a in enumerate(self.axes) if a.name != "kind")

    @functools.cached_property
    def line_axis(self) -> int | None:
        """Position of the line (continuation) axis: the last real axis, else the last
        non-kind axis; None when only 'kind' is swept."""
        points = self.point_axes
        real = [i for i in points if self.axes[i].is_real]
        return real[-1] if real else (points[-1] if points else None)

    @functools.cached_property
    def spatial(self) -> bool:
        """The model has spatial modes (a parameter n_spatial): the result also stores
        n_spatial and spatial_converged."""
        return "n_spatial" in param_names(self.model)

    @functools.cached_property
    def refines_spatial(self) -> bool:
        """M is refined per point (a spatial model with neither n_spatial nor spatial_mode)."""
        given = set(dict(self.fixed)) | set(self.dims)
        return self.spatial and not given & {"n_spatial", "spatial_mode"}

    @functools.cached_property
    def nonuniform(self) -> bool:
        """The sphere with kappa given as an expression: the result also stores l_max and the
        critical mode's dominant (l, k)."""
        return is_nonuniform(self.model, {**dict(self.fixed), **{n: None for n in self.dims}})

    def axis(self, name: str) -> Axis:
        """The axis called ``name``."""
        return next(a for a in self.axes if a.name == name)

    def params_at(self, values: Mapping[str, Any]) -> dict[str, Any]:
        """Model parameters at a grid point (``values``: the non-kind axis values), with the
        physical quantities converted to kappa and nu (and alpha, for the cochlea)."""
        merged = {**dict(self.fixed), **values}
        if not self.physical:
            return merged
        if self.model not in PHYSICAL_NAMES:  # the model's own physical input
            return get_model(self.model).physical.convert(merged)[0]
        return cochlea_sweep_params(merged) if self.model == "cochlea" else \
            sphere_forced_params(merged)

    def canonical(self) -> dict[str, Any]:
        """JSON-able form of everything that determines the numbers (hashed into ``digest``)."""
        options = dataclasses.asdict(self.options)
        if options["tol_spatial"] is None:  # scenes without spatial modes keep their old hash
            del options["tol_spatial"]
        if options["over_kinds"] == "each":  # the default keeps the hash of older scenes
            del options["over_kinds"]
        return {"model": self.model, "ask": list(self.ask), "params": dict(self.fixed),
                "grid": [[a.name, list(a.values), a.spacing] for a in self.axes],
                "options": options, "chunk": self.chunk}


def scene_digest(canonical: Mapping[str, Any]) -> str:
    """Stable hash (sha256, 16 hex digits) of a canonical scene: the same numbers, the same hash,
    in every process and Python version (no dict order or hash seed enters)."""
    text = json.dumps(canonical, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _field_types(model: str) -> dict[str, str]:
    """'int', 'str' or 'float' for each parameter of ``model`` (from the dataclass annotations)."""
    out = {}
    for f in param_fields(model):
        t = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", "float")
        t = t.removesuffix(" | None")  # optional parameters (the cochlea's n_spatial)
        out[f.name] = t if t in ("int", "str") else "float"
    return out


def _value_type(model: str, name: str) -> str:
    if name == "kind":
        return "str"
    if (model, name) == ("sphere", "l_max"):  # the non-uniform sphere's degree truncation
        return "int"
    return _field_types(model).get(name, "float")


def allowed_grid_names(model: str) -> tuple[str, ...]:
    """Parameters a sweep of ``model`` may put in its grid (the sphere: also l_max, the
    degree truncation of a non-uniform kappa)."""
    extra = ("l_max",) if model == "sphere" else ()
    return param_names(model) + extra + physical_names(model) + ("kind",)


def _distinct(name: str, values: list) -> None:
    if len(set(values)) != len(values):
        dup = next(v for v in values if values.count(v) > 1)
        raise ParameterError(f"grid {name} = {values!r} is invalid: value {dup!r} appears twice "
                             "(each grid value must be distinct)")


def _real_axis(name: str, spec: object, max_points: int | None) -> tuple[tuple[float, ...], str]:
    if isinstance(spec, Mapping):
        keys = set(spec)
        if not {"start", "stop", "num"} <= keys or keys - {"start", "stop", "num", "spacing"}:
            raise ParameterError(f"grid {name} = {dict(spec)!r} is invalid: must be a table with "
                                 "keys start, stop, num (and optionally spacing)")
        spacing = require_choice(f"grid {name}.spacing", spec.get("spacing", "linear"),
                                 ("linear", "log"))
        values = parse_range(f"grid {name}", {k: spec[k] for k in ("start", "stop", "num")},
                             max_points)
        if spacing == "log":
            if values[0] <= 0:
                raise ParameterError(f"grid {name}.start = {spec['start']!r} is invalid: must be "
                                     "> 0 with spacing = 'log'")
            values = np.geomspace(values[0], values[-1], values.size)
        return tuple(float(v) for v in values), spacing
    if isinstance(spec, str):
        return tuple(float(v) for v in parse_range(f"grid {name}", spec, max_points)), "linear"
    if isinstance(spec, (list, tuple)):
        if not spec:
            raise ParameterError(f"grid {name} = [] is invalid: must be a non-empty list of "
                                 "numbers")
        check_points(f"grid {name} (a list)", len(spec), max_points)
        values = [require_real(f"grid {name}", v) for v in spec]
        _distinct(name, values)
        return tuple(values), "list"
    raise ParameterError(f"grid {name} = {spec!r} is invalid: must be a list of values, a table "
                         "{start, stop, num[, spacing]} or 'start:stop:num'")


def _int_axis(name: str, spec: object, bounds: tuple, max_points: int | None
              ) -> tuple[tuple[int, ...], str]:
    if not isinstance(spec, (list, tuple, str)) or isinstance(spec, str) and ":" not in spec:
        raise ParameterError(f"grid {name} = {spec!r} is invalid: must be a list of integers or "
                             "'lo:hi'")
    values = parse_int_range(f"grid {name}", spec, bounds, max_points)
    _distinct(name, values)
    return tuple(values), "list"


def _str_axis(name: str, spec: object) -> tuple[tuple[str, ...], str]:
    if name == "kind" and spec == "both":
        spec = list(KINDS)
    if not isinstance(spec, (list, tuple)) or not spec or not all(isinstance(v, str) for v in spec):
        raise ParameterError(f"grid {name} = {spec!r} is invalid: must be a non-empty list of "
                             "names")
    if name == "kind":
        for v in spec:
            require_choice("grid kind", v, KINDS)
    _distinct(name, list(spec))
    return tuple(spec), "list"


def parse_axis(model: str, name: str, spec: object, max_points: int | None = None) -> Axis:
    """One [grid] entry -> an Axis, typed by the model's parameter (int, str or float).

    Raises
    ------
    ParameterError : malformed, empty, reversed or duplicated values; integers outside the
        model's range; more values than the points limit (``max_points``).
    """
    kind = _value_type(model, name)
    if kind == "int":
        bounds = L_MAX_RANGE if (model, name) == ("sphere", "l_max") else int_bounds(model, name)
        values, spacing = _int_axis(name, spec, bounds, max_points)
    else:
        values, spacing = _real_axis(name, spec, max_points) if kind == "float" else \
            _str_axis(name, spec)
    return Axis(name=name, values=values, units=units(model, name), spacing=spacing)


def _check_physical(model: str, names: set[str]) -> bool:
    """Whether the sweep uses physical quantities; refuses an incomplete or mixed set."""
    used = names & set(physical_names(model) or PHYSICAL)
    if not used:
        return False
    if not physical_names(model):
        name = sorted(used)[0]
        raise ParameterError(f"{name} is not a parameter of model {model!r}: physical quantities "
                             f"need model {' or '.join(repr(m) for m in physical_models())}")
    if model == "cochlea":
        return _check_cochlea_physical(names, used)
    if model not in PHYSICAL_NAMES:  # its physical input checks each point (_validate_points)
        return True
    for derived in ("kappa", "nu"):
        if derived in names:
            raise ParameterError(f"{derived} is given together with physical quantities "
                                 f"({', '.join(sorted(used))}): it follows from them by "
                                 "(6.4)-(6.5); remove one of the two")
    for name in ("rho", "mu", "radius", "sigma"):
        if name not in names:
            raise ParameterError(f"{name} is missing: physical sweeps need rho, mu, radius, sigma "
                                 "and omega or bpm")
    if len(names & {"omega", "bpm"}) != 1:
        raise ParameterError("omega/bpm is invalid: give exactly one of omega (rad/s) or bpm "
                             "(beats/min)")
    return True


def _check_cochlea_physical(names: set[str], used: set[str]) -> bool:
    """The cochlea's cgs inputs: exactly one of omega and frequency, and no dimensionless
    parameter together with the quantity it follows from."""
    if len(names & {"omega", "frequency"}) != 1:
        both = names >= {"omega", "frequency"}
        raise ParameterError(f"{'omega/frequency' if both else 'omega'} is invalid: give exactly "
                             "one of omega (rad/s) or frequency (Hz, omega = 2 pi f) with the "
                             f"cochlea's physical quantities ({', '.join(sorted(used))})")
    for source, derived in _COCHLEA_DEFAULTS.items():
        if derived and derived in names and source in names:
            raise ParameterError(f"{derived} is given together with {source}: it follows from "
                                 f"{source} (thesis 5.2); remove one of the two")
    return True


def _with_cochlea_defaults(fixed: Mapping[str, Any], grid: Mapping[str, Any]) -> dict[str, Any]:
    """``fixed`` plus the Table 5.1 value of every cgs input of a physical cochlea sweep that is
    neither given nor replaced by its dimensionless parameter."""
    given = set(fixed) | set(grid)
    extra = {name: TABLE_5_1[name] for name, derived in _COCHLEA_DEFAULTS.items()
             if name not in given and derived not in given}
    return {**fixed, **extra}


def _spatial_options(model: str, options: SolverOptions, fixed: Mapping,
                     grid: Mapping) -> SolverOptions:
    """``options`` with tol_spatial resolved: TOL_SPATIAL by default when M is refined per
    point; refused (ParameterError) when M is fixed or the model has no spatial modes."""
    given = options.tol_spatial is not None
    fixed_m = sorted((set(fixed) | set(grid)) & {"n_spatial", "spatial_mode"})
    if options.over_kinds == "minimum" and ("n_spatial" not in param_names(model) or fixed_m):
        raise ParameterError("tau_min.over_kinds = 'minimum' is invalid here: it needs a model "
                             "with spatial modes whose M is refined per point (no n_spatial or "
                             "spatial_mode given); use 'each'")
    if "n_spatial" not in param_names(model):
        if given:
            raise ParameterError(f"tau_min.tol_spatial = {options.tol_spatial!r} is invalid for "
                                 f"model {model!r}: it has no spatial modes")
        return options
    if fixed_m:
        if given:
            raise ParameterError(f"tau_min.tol_spatial = {options.tol_spatial!r} is invalid with "
                                 f"{fixed_m[0]} given: it sets when the refinement in n_spatial "
                                 "stops, and there is none")
        return options
    return options if given else dataclasses.replace(options, tol_spatial=TOL_SPATIAL)


def _checked_table(name: str, table: object, keys: tuple[str, ...]) -> Mapping:
    """``table`` if it is a TOML table holding only ``keys``."""
    if not isinstance(table, Mapping):
        raise ParameterError(f"{name} = {table!r} is invalid: must be a table")
    extra = sorted(set(table) - set(keys))
    if extra:
        raise ParameterError(f"{name}.{extra[0]} is unknown: expected {', '.join(keys)}")
    return table


def _options(table: object) -> SolverOptions:
    table = _checked_table("tau_min", table, OPTION_KEYS)
    out: dict[str, Any] = {}
    if "tol" in table:
        out["tol"] = require_positive("tau_min.tol", table["tol"])
    if "n_temporal" in table:
        out["n_temporal"] = require_int_in_range("tau_min.n_temporal", table["n_temporal"], 1,
                                                 N_TEMPORAL_MAX)
    if "tau_max" in table:
        out["tau_max"] = require_positive("tau_min.tau_max", table["tau_max"])
    if "continuation" in table:
        if not isinstance(table["continuation"], bool):
            raise ParameterError(f"tau_min.continuation = {table['continuation']!r} is invalid: "
                                 "must be true or false")
        out["continuation"] = table["continuation"]
    if "tol_spatial" in table:
        out["tol_spatial"] = require_positive("tau_min.tol_spatial", table["tol_spatial"])
    if "over_kinds" in table:
        out["over_kinds"] = require_choice("tau_min.over_kinds", table["over_kinds"], OVER_KINDS)
    return SolverOptions(**out)


def _chunk(table: object) -> int:
    table = _checked_table("sweep", table, SWEEP_KEYS)
    return require_int_in_range("sweep.chunk", table.get("chunk", DEFAULT_CHUNK), 1)


def _normalised(model: str, name: str, value: Any) -> Any:
    """Fixed values as the hash sees them: reals as float, so 1 and 1.0 hash alike."""
    if _value_type(model, name) == "float" and not isinstance(value, (bool, str)):
        try:
            return require_real(name, value)
        except ParameterError:
            return value  # make_params reports it
    return value


def _validate_points(spec: SweepSpec) -> None:
    """Every value of every axis, with the other axes at their first value, gives valid
    parameters (each parameter is range-checked on its own, so this covers the grid)."""
    first = {spec.axes[i].name: spec.axes[i].values[0] for i in spec.point_axes}
    check = nonuniform_params if spec.nonuniform else (
        lambda values: make_params(spec.model, values))
    for i in spec.point_axes:
        axis = spec.axes[i]
        for v in axis.values:
            check(spec.params_at({**first, axis.name: v}))


def _check_nonuniform(fixed: Mapping[str, Any], grid: Mapping[str, Any],
                      options: SolverOptions) -> None:
    """A sweep of the non-uniform sphere: kappa (an expression) fixed, only NONUNIFORM_GRID
    swept, tol_spatial only with l_max refined ('auto').

    Raises
    ------
    ParameterError : kappa swept or not an expression, another grid name, tol_spatial with a
        fixed l_max.
    """
    if "kappa" in grid or not isinstance(fixed.get("kappa"), str):
        raise ParameterError(f"kappa = {grid.get('kappa', fixed.get('kappa'))!r} is invalid "
                             "with l_max: a non-uniform sweep needs kappa fixed in [params] as "
                             "an expression in theta, phi (e.g. '0.02*(1 + 0.3*cos(theta)**2)')")
    for name in grid:
        if name not in NONUNIFORM_GRID:
            raise ParameterError(f"grid parameter {name!r} is invalid with a non-uniform kappa: "
                                 f"expected one of {', '.join(NONUNIFORM_GRID)}")
    fixed_l = "l_max" in grid or fixed.get("l_max", "auto") != "auto"
    if options.tol_spatial is not None and fixed_l:
        raise ParameterError(f"tau_min.tol_spatial = {options.tol_spatial!r} is invalid with a "
                             "fixed l_max: it sets when the refinement in l_max stops")


def is_sweep_scene(scene: Mapping[str, Any]) -> bool:
    """True for a scene with a [grid] table (a sweep), False for a planner scene."""
    return "grid" in scene


def _axes(model: str, grid: Mapping[str, Any], max_points: int | None) -> tuple[Axis, ...]:
    """The [grid] axes (and 'kind', both kinds, unless swept), refused as soon as their points
    exceed the points limit or their results the memory limit
    (:func:`spectralshell.params.limits.check_grid`)."""
    axes: list[Axis] = []
    for name, spec in grid.items():
        axes.append(parse_axis(model, name, spec, max_points))
        _check_axes(axes, max_points)
    if "kind" not in grid:
        axes.append(Axis(name="kind", values=KINDS, units="", spacing="list"))
        _check_axes(axes, max_points)
    return tuple(axes)


def _check_axes(axes: list[Axis], max_points: int | None) -> None:
    names = " x ".join(a.name for a in axes)
    check_grid(f"grid {names}", tuple(len(a.values) for a in axes), SWEEP_BYTES, max_points)


def sweep_spec(scene: str | Path | Mapping, *, max_points: int | None = None) -> SweepSpec:
    """Validate a sweep scene (path, TOML string or dict) and return its SweepSpec.

    ``max_points`` raises the limit on the grid's points (kind included) for this sweep
    (default: :data:`spectralshell.params.limits.POINTS`); the SweepSpec can be passed to
    :func:`spectralshell.sweep` in place of the scene.

    Raises
    ------
    ParameterError : unknown scene key, model, ask or grid parameter; empty, reversed or
        duplicated grid values; a parameter both fixed in [params] and swept in [grid]; a value
        out of range; bad solver options; a grid above the points or memory limit (checked
        axis by axis, before the next axis is made). Each with a one-line message.
    """
    data = load_scene(scene)
    unknown = sorted(set(data) - set(SCENE_KEYS))
    if unknown:
        raise ParameterError(f"scene key {unknown[0]!r} is unknown in a sweep: expected "
                             f"{', '.join(SCENE_KEYS)}")
    if "model" not in data:
        raise ParameterError("scene is invalid: it has no 'model'")
    model = check_model(data["model"])
    ask = require_choices("ask", data.get("ask", ["tau_min"]), ASKS)
    fixed = data.get("params", {})
    grid = data.get("grid")
    for name, table in (("params", fixed), ("grid", grid)):
        if not isinstance(table, Mapping):
            raise ParameterError(f"{name} = {table!r} is invalid: must be a table")
    if not grid:
        raise ParameterError("grid = {} is invalid: a sweep needs at least one swept parameter")
    allowed = allowed_grid_names(model)
    for name in grid:
        if name not in allowed:
            raise ParameterError(f"grid parameter {name!r} is unknown for model {model!r}: "
                                 f"expected one of {', '.join(allowed)}")
        if name in fixed:
            raise ParameterError(f"{name} is both fixed in [params] ({fixed[name]!r}) and swept "
                                 "in [grid]: remove one of the two")
    if "kind" in fixed:
        raise ParameterError("kind is invalid in [params]: sweep kinds in [grid], e.g. "
                             "kind = ['harmonic']")
    # a kappa in [grid] is a grid (its 'start:stop:num' text is no expression); l_max anywhere
    if is_nonuniform(model, {**fixed, **{name: None for name in grid if name != "kappa"}}):
        options = _options(data.get("tau_min", {}))
        _check_nonuniform(fixed, grid, options)
        physical = False
    else:
        physical = _check_physical(model, set(fixed) | set(grid))
        options = _spatial_options(model, _options(data.get("tau_min", {})), fixed, grid)
    if physical and model == "cochlea":
        fixed = _with_cochlea_defaults(fixed, grid)
    axes = _axes(model, grid, max_points)
    spec = SweepSpec(model=model,
                     fixed=tuple((k, _normalised(model, k, v)) for k, v in fixed.items()),
                     axes=axes, ask=ask, options=options,
                     chunk=_chunk(data.get("sweep", {})), physical=physical)
    _validate_points(spec)
    return dataclasses.replace(spec, digest=scene_digest(spec.canonical()),
                               source=json.dumps(data, default=str))
