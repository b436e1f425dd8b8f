"""Scenes (TOML: model, parameters, what is asked) and the planner that decides what to compute.

A scene file::

    model = "mathieu"
    ask = ["floquet", "tongues", "exponents"]     # any subset
    [params]                                      # the model's parameters
    kappa = 0.25
    nu = 0.1
    [floquet]                                     # options of each asked task (all optional)
    kind = "both"                                 # 'both', 'harmonic' or 'subharmonic'
    tol = 1e-10                                   # or n_temporal = 30
    [tongues]
    kappa = "0:3:301"                             # or {start = 0, stop = 3, num = 301}
    kind = "both"
    [exponents]
    tau = 0.3
    [output]                                      # files written by `spectralshell run`
    dir = "scene-output"

Planning validates everything before anything is computed and keeps only what is asked: a task
not in ``ask`` is not run, and each task computes only the Floquet kinds its ``kind`` names.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from .._validate import (require_choice, require_choices, require_int_in_range, require_positive,
                         require_real)
from ..errors import ParameterError
from .grid import parse_range
from .registry import make_params
from .sphere import is_nonuniform, nonuniform_params

TASKS = ("floquet", "tongues", "exponents")
_OPTIONS = {
    "floquet": {"kind", "tol", "n_temporal"},
    "tongues": {"kappa", "kind", "tol", "n_temporal", "tips"},
    "exponents": {"tau", "tol", "n_temporal"},
}


@dataclass(frozen=True, kw_only=True, eq=False)
class Task:
    """One validated computation of a plan: ``name`` with its keyword options."""

    name: str
    kinds: tuple[str, ...] = ()
    options: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True, kw_only=True, eq=False)
class Plan:
    """What a scene will compute: model, validated parameters, tasks and output directory."""

    model: str
    params: dict
    tasks: tuple[Task, ...]
    output_dir: str


def load_scene(scene: str | Path | Mapping) -> dict:
    """A scene as a dict, from a mapping, a TOML file path or a TOML string."""
    if isinstance(scene, Mapping):
        return dict(scene)
    text = str(scene)
    try:
        if "\n" not in text and (text.endswith(".toml") or Path(text).is_file()):
            path = Path(text)
            if not path.is_file():
                raise ParameterError(f"scene = {text!r} is invalid: no such file")
            text = _read_text(path)
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"scene is invalid TOML: {exc}") from None


def _read_text(path: Path) -> str:
    """The UTF-8 text of scene file ``path`` (TOML is UTF-8), or a ParameterError naming the
    file and, for bytes that are not UTF-8, the offset of the first one."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ParameterError(f"scene = {str(path)!r} cannot be read: {exc.strerror}") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ParameterError(f"scene = {str(path)!r} is invalid: not UTF-8 text (byte "
                             f"0x{data[exc.start]:02x} at offset {exc.start})") from None


def default_scene() -> dict:
    """The embedded demo scene (``spectralshell/params/scenes/demo.toml``)."""
    return tomllib.loads(resources.files(__package__).joinpath("scenes/demo.toml").read_text())


def _kind(task: str, value: Any) -> tuple[str, ...]:
    kind = require_choice(f"{task}.kind", value, ("both", "harmonic", "subharmonic"))
    return ("harmonic", "subharmonic") if kind == "both" else (kind,)


def _solver_options(task: str, opts: Mapping) -> dict:
    out = {}
    if "tol" in opts:
        out["tol"] = require_positive(f"{task}.tol", opts["tol"])
    if "n_temporal" in opts:
        out["n_temporal"] = require_int_in_range(f"{task}.n_temporal", opts["n_temporal"], 1, 400)
    return out


def is_simulation_scene(scene: Mapping[str, Any]) -> bool:
    """True for a scene with an [initial] or [simulate] table: a time-stepping run
    (:func:`spectralshell.params.simulation.simulation_scene`), not a planner scene."""
    return "initial" in scene or "simulate" in scene


def plan(scene: str | Path | Mapping) -> Plan:
    """Validate a scene and decide what to compute (nothing is computed here).

    Raises
    ------
    ParameterError : unknown keys, wrong types or values out of range anywhere in the scene.
    """
    data = load_scene(scene)
    if is_simulation_scene(data):
        raise ParameterError("scene is a simulation scene (it has [initial] or [simulate]): "
                             "ss.simulate(scene) runs it, as do spectralshell run and simulate")
    allowed = {"model", "ask", "params", "output", *TASKS}
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise ParameterError(f"scene key {unknown[0]!r} is unknown: expected {', '.join(sorted(allowed))}")
    if "model" not in data:
        raise ParameterError("scene is invalid: it has no 'model'")
    model = data["model"]
    params_table = data.get("params", {})
    if not isinstance(params_table, Mapping):
        raise ParameterError(f"params = {params_table!r} is invalid: must be a table")
    tasks = []
    for name in require_choices("ask", data.get("ask", ["floquet"]), TASKS):
        opts = data.get(name, {})
        if not isinstance(opts, Mapping):
            raise ParameterError(f"{name} = {opts!r} is invalid: must be a table")
        extra = sorted(set(opts) - _OPTIONS[name])
        if extra:
            raise ParameterError(f"{name}.{extra[0]} is unknown: expected {', '.join(sorted(_OPTIONS[name]))}")
        options = _solver_options(name, opts)
        kinds: tuple[str, ...] = ()
        if name in ("floquet", "tongues"):
            kinds = _kind(name, opts.get("kind", "both"))
        if name == "tongues":
            options["kappa"] = parse_range("tongues.kappa", opts.get("kappa", "0:3:301"))
            tips = opts.get("tips", True)
            if not isinstance(tips, bool):
                raise ParameterError(f"tongues.tips = {tips!r} is invalid: must be true or false")
            options["tips"] = tips
        if name == "exponents":
            if "tau" not in opts:
                raise ParameterError("exponents.tau is missing: the exponents need a forcing amplitude")
            options["tau"] = require_real("exponents.tau", opts["tau"])
        tasks.append(Task(name=name, kinds=kinds, options=options))
    params = dict(params_table)
    for task in tasks:  # validate the parameters each task will use (tongues sweep kappa)
        if is_nonuniform(model, params):
            if task.name != "floquet":
                raise ParameterError(f"ask = {task.name!r} is invalid with a non-uniform kappa: "
                                     "only 'floquet' is computed for it")
            nonuniform_params(params)
            continue
        values = {**params, "kappa": task.options["kappa"][0]} if task.name == "tongues" else params
        make_params(model, values)
    output = data.get("output", {})
    if not isinstance(output, Mapping) or not isinstance(output.get("dir", "scene-output"), str):
        raise ParameterError(f"output = {output!r} is invalid: must be a table with a string 'dir'")
    return Plan(model=model, params=params, tasks=tuple(tasks),
                output_dir=output.get("dir", "scene-output"))
