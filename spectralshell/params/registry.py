"""The model registry: each model registers itself here with its parameters and capabilities.

A model is a plug-in. Its module (the four built-in ones live in :mod:`spectralshell.models`;
a user's can live anywhere) builds one :class:`Model` and passes it to :func:`register`:

* ``name`` and a one-line ``summary``;
* ``params``: a frozen dataclass of its dimensionless parameters whose fields carry metadata
  ``help`` (meaning), ``units`` and, for integers, ``range`` = (lowest, highest or None); its
  ``__post_init__`` validates (raising :class:`~spectralshell.errors.ParameterError`);
* ``hill_system``: parameters -> :class:`spectralshell.models.base.HillSystem` (the physics of
  (2.6): D(s) and G), the one capability every model has: it gives Floquet boundaries
  (``floquet``, ``tongues``, ``stability`` for models with an integer parameter ``m``,
  ``tau_map``, sweeps) and, where D(s) is a matrix polynomial, Floquet ``exponents``;
* optional capabilities (None: the model does not offer it) -- see the attributes of
  :class:`Model`.

Everything that dispatches on a model (the API, the CLI, the sweep runner) asks this registry
what the model can do; no model name appears in a branch outside ``models/`` and ``params/``.
This module holds callables but imports no later stage: a model's capabilities are opaque here.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from .._validate import require_choice
from ..errors import ParameterError, SpectralShellError


@dataclass(frozen=True, kw_only=True)
class PhysicalInput:
    """cgs quantities a model accepts in place of its dimensionless parameters.

    Attributes
    ----------
    units : quantity name -> its cgs unit (e.g. {'omega': 'rad/s', 'rho': 'g/cm^3'}); these
        become the CLI's flags, with their units in the help.
    convert : values (dimensionless parameters and/or cgs quantities) -> (dimensionless
        parameters, the cgs quantities used or None when none was given).
    note : how missing quantities are filled (e.g. 'Table 5.1 defaults, omega required').
    """

    units: Mapping[str, str]
    convert: Callable[[dict[str, Any]], tuple[dict[str, Any], dict[str, float] | None]]
    note: str = ""


@dataclass(frozen=True, kw_only=True)
class TimeStepping:
    """How ``simulate`` time-steps a model: ``ss.simulate(model, **keywords)``.

    Attributes
    ----------
    runner : 'module:function' of the stepper, imported on first use (a stepper discretises
        and solves, stages later than the model's registration, which may not import them);
        function(*, progress, **keywords) -> a result with the time series and the fitted
        growth rate.
    keywords : keyword -> (type, help) of every keyword the stepper takes, in the order the
        CLI lists them; None in place of (type, help): the model's parameter of that name (its
        type and help from the parameter metadata). A type (float, str) is a number or else a
        text (an expression).
    required : the keywords without a default.
    initial : the initial state the run starts from (one line, for help and documentation).
    figures : the files ``simulate --png FILE`` writes, as suffixes of FILE's stem ('' is FILE
        itself; the sphere adds '_shape'); empty: the result has no figure and --png is refused.
    """

    runner: str
    keywords: Mapping[str, tuple[Any, str] | None]
    required: tuple[str, ...] = ()
    initial: str = ""
    figures: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        module, _, function = self.runner.partition(":")
        if not (module and function.isidentifier()):
            raise ParameterError(f"runner = {self.runner!r} is invalid: must be "
                                 "'module:function'")
        missing = [k for k in self.required if k not in self.keywords]
        if missing:
            raise ParameterError(f"required keyword {missing[0]!r} is invalid: not among the "
                                 f"keywords {', '.join(self.keywords)}")
        if not (isinstance(self.figures, tuple) and all(isinstance(f, str) for f in self.figures)
                and (not self.figures or self.figures[0] == "")):
            raise ParameterError(f"figures = {self.figures!r} is invalid: must be a tuple of "
                                 "file-name suffixes starting with '' (the --png file itself), "
                                 "or ()")


@dataclass(frozen=True, kw_only=True)
class Model:
    """A model plug-in: its parameters, its physics and what it can compute.

    Attributes
    ----------
    name : the name users type ('mathieu', 'sphere', ...).
    summary : one line: what the model is (thesis chapter), shown by the CLI's help.
    params : frozen dataclass of the dimensionless parameters (field metadata: 'help',
        'units', 'range').
    hill_system : params -> HillSystem (:mod:`spectralshell.models.base`).
    modal_system : params -> ModalSystem, the natural-mode dispersion relation f(x) = 0 in one
        variable (``natural_modes`` by Newton from seeds, :mod:`spectralshell.solvers.modes`).
    mode_family : params -> ModeFamily, the natural modes as a nonlinear matrix eigenproblem
        T(s; zeta) continued in the viscosity (:mod:`spectralshell.solvers.continued_modes`).
    inviscid_modes : (params, kappa) -> lambda0^2, the closed-form squared natural frequency at
        nu = 0 (kappa may be an mpmath number), with ``inviscid_method`` naming its source;
        ``natural_modes`` returns gamma = i lambda0 at nu = 0 instead of root finding.
    spatial : the model carries an integer parameter ``n_spatial`` (a number M of spatial modes
        in each Hill block) that ``floquet`` may refine until tau_min converges (None: refined;
        ``spatial_mode``: one decoupled mode).
    physical : cgs input of the Floquet computations (floquet, response), or None.
    mode_inputs : cgs input of ``natural_modes`` (rates then in s^-1): quantity -> unit, and
        ``mode_scale`` (params, physical) -> (dimensionless params, 1 / time scale in s, the
        cgs values to record).
    response : params -> ResponseModel (:mod:`spectralshell.models.base`), the pure-tone and
        parametric response envelopes along the membrane (``response``).
    time_stepping : :class:`TimeStepping`, how ``simulate`` time-steps the model (its keywords
        and stepper), or None.
    """

    name: str
    summary: str
    params: type
    hill_system: Callable[[Any], Any]
    modal_system: Callable[[Any], Any] | None = None
    mode_family: Callable[[Any], Any] | None = None
    inviscid_modes: Callable[[Any, Any], Any] | None = None
    inviscid_method: str = ""
    spatial: bool = False
    physical: PhysicalInput | None = None
    mode_inputs: Mapping[str, str] = field(default_factory=dict)
    mode_scale: Callable[[Any, dict[str, float]], tuple[Any, float, dict[str, Any]]] | None = None
    response: Callable[[Any], Any] | None = None
    time_stepping: TimeStepping | None = None

    def __post_init__(self) -> None:
        if not (isinstance(self.name, str) and self.name.isidentifier()):
            raise ParameterError(f"model name = {self.name!r} is invalid: must be an identifier")
        if not (isinstance(self.params, type) and dataclasses.is_dataclass(self.params)):
            raise ParameterError(f"params = {self.params!r} of model {self.name!r} is invalid: "
                                 "must be a dataclass")


_MODELS: dict[str, Model] = {}


def register(model: Model) -> Model:
    """Register ``model`` (replacing a model of the same name, so that re-importing a plug-in
    module is harmless) and return it."""
    if not isinstance(model, Model):
        raise ParameterError(f"model = {model!r} is invalid: must be a spectralshell Model")
    _MODELS[model.name] = model
    return model


def unregister(name: str) -> None:
    """Remove the model ``name`` from the registry (ParameterError if it is not registered)."""
    del _MODELS[check_model(name)]


def load_entry_points() -> tuple[str, ...]:
    """Import the plug-in modules installed under the entry-point group ``spectralshell.models``
    (each registers its models on import) and return the names of the models registered.

    A package offers a model to the CLI by declaring in its pyproject.toml::

        [project.entry-points."spectralshell.models"]
        twin = "mypackage.twin"
    """
    from importlib.metadata import entry_points

    for point in entry_points(group="spectralshell.models"):
        try:
            point.load()
        except Exception as exc:  # an installed plug-in is broken: say which, run nothing
            raise SpectralShellError(f"model plug-in {point.name!r} ({point.value}) failed to "
                                     f"load: {type(exc).__name__}: {exc}") from exc
    return models()


def models() -> tuple[str, ...]:
    """Names of the registered models, in registration order."""
    return tuple(_MODELS)


def get_model(name: str) -> Model:
    """The registered model ``name``.

    Raises
    ------
    ParameterError : no model of that name.
    """
    return _MODELS[check_model(name)]


def models_with(*capabilities: str) -> tuple[str, ...]:
    """Names of the models offering any of ``capabilities`` (attributes of :class:`Model` that
    are set: not None, not False, not empty), in registration order."""
    return tuple(n for n, m in _MODELS.items() if any(getattr(m, c) for c in capabilities))


def check_model(model: str) -> str:
    """Return ``model`` if it is a registered model name."""
    return require_choice("model", model, tuple(_MODELS))


def require_capability(model: str, what: str, *capabilities: str) -> Model:
    """The model ``model`` if it offers any of ``capabilities``, else ParameterError naming the
    models that do (``what``: the computation, for the message)."""
    spec = get_model(model)
    if not any(getattr(spec, c) for c in capabilities):
        able = ", ".join(repr(n) for n in models_with(*capabilities)) or "none"
        raise ParameterError(f"model = {model!r} is invalid for {what}: must be one of {able}")
    return spec


def stepping_keywords(model: str) -> dict[str, tuple[Any, str]]:
    """keyword -> (type, help) of ``simulate`` for ``model`` (:class:`TimeStepping`; a model
    parameter's from its field metadata), ParameterError if it cannot be time-stepped."""
    stepping = require_capability(model, "simulate", "time_stepping").time_stepping
    fields = {f.name: f for f in param_fields(model)}
    out = {}
    for name, entry in stepping.keywords.items():
        if entry is None:
            f = fields[name]
            entry = (f.type if isinstance(f.type, type) else str(f.type).split(" |")[0],
                     param_help(f))
        out[name] = entry
    return out


def param_fields(model: str) -> tuple[dataclasses.Field, ...]:
    """The dataclass fields of the parameters of ``model`` (name, type, default, metadata)."""
    return dataclasses.fields(get_model(model).params)


def param_help(f: dataclasses.Field) -> str:
    """A parameter's meaning (metadata 'help') with its units (metadata 'units': '[units]',
    '[dimensionless]' for '1') unless the meaning already states them."""
    meaning = f.metadata.get("help", f.name)
    units = f.metadata.get("units")
    if units and "dimensionless" not in meaning and units not in meaning:
        meaning += " [dimensionless]" if units == "1" else f" [{units}]"
    return meaning


def parameters_doc() -> str:
    """The registered models' parameters as text: per model its summary, then each parameter
    with its meaning, units and default ('required' where it has none), from the field
    metadata (appended to the API's docstrings, so that ``help(ss.floquet)`` lists them)."""
    lines = ["Model parameters (``**params``), per model:"]
    for name, spec in _MODELS.items():
        lines.append(f"    {name}: {spec.summary}")
        for f in dataclasses.fields(spec.params):
            given = "required" if f.default is dataclasses.MISSING else f"default {f.default!r}"
            lines.append(f"        {f.name} : {param_help(f)}; {given}")
    return "\n".join(lines)


def param_names(model: str) -> tuple[str, ...]:
    """Names of the parameters of ``model``."""
    return _field_names(get_model(model).params)


def int_bounds(model: str, name: str) -> tuple[int, int | None]:
    """(lowest, highest or None) of the integer parameter ``name`` of ``model`` (the field's
    metadata 'range'; (0, None) where it has none), for checking a range before making it."""
    field_ = next((f for f in param_fields(model) if f.name == name), None)
    return field_.metadata.get("range", (0, None)) if field_ is not None else (0, None)


def physical_values(model: str, values: dict[str, Any]) -> tuple[dict[str, Any], dict | None]:
    """(dimensionless parameter values, the cgs inputs used or None): the model's physical input
    converted where it has one (:class:`PhysicalInput`); otherwise ``values`` unchanged."""
    spec = get_model(model)
    if spec.physical is None:
        return dict(values), None
    return spec.physical.convert(dict(values))


@functools.cache
def _field_names(cls: type) -> tuple[str, ...]:
    """The field names of a parameter class, in order (read once per class, as
    :func:`_required_fields`)."""
    return tuple(f.name for f in dataclasses.fields(cls))


@functools.cache
def _required_fields(cls: type) -> tuple[dataclasses.Field, ...]:
    """The fields of a parameter class without a default, in order (read once per class: a
    sweep makes the parameters of every point)."""
    return tuple(f for f in dataclasses.fields(cls)
                 if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING)


def make_params(model: str, values: dict[str, Any]):
    """Validated parameter object of ``model`` from a name -> value mapping.

    Raises
    ------
    ParameterError : unknown model, unknown or missing parameter, or a value out of range.
    """
    cls = get_model(model).params
    names = _field_names(cls)
    unknown = sorted(set(values).difference(names))
    if unknown:
        raise ParameterError(f"{unknown[0]} is not a parameter of model {model!r}: "
                             f"expected {', '.join(names)}")
    required = _required_fields(cls)
    missing = [f for f in required if f.name not in values]
    if missing:
        raise ParameterError(f"{missing[0].name} is missing: model {model!r} has no default for "
                             f"it ({param_help(missing[0])}); it needs "
                             f"{', '.join(f.name for f in required)}")
    return cls(**values)


def model_of(params) -> Model:
    """The registered model whose parameter class ``params`` is an instance of."""
    for spec in _MODELS.values():
        if type(params) is spec.params:
            return spec
    raise TypeError(f"no registered model has parameters of type {type(params).__name__}")
