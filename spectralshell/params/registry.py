"""Model names and their parameter classes: the one place a model name is resolved."""

from __future__ import annotations

import dataclasses
from typing import Any

from .._validate import require_choice
from ..errors import ParameterError
from .cochlea import CochleaParams
from .fibre import FibreParams
from .mathieu import MathieuParams
from .sphere import SphereParams

PARAMS = {"mathieu": MathieuParams, "sphere": SphereParams, "fibre": FibreParams,
          "cochlea": CochleaParams}


def check_model(model: str) -> str:
    """Return ``model`` if it is a known model name."""
    return require_choice("model", model, tuple(PARAMS))


def param_names(model: str) -> tuple[str, ...]:
    """Names of the parameters of ``model``."""
    return tuple(f.name for f in dataclasses.fields(PARAMS[check_model(model)]))


def int_bounds(model: str, name: str) -> tuple[int, int | None]:
    """(lowest, highest or None) of the integer parameter ``name`` of ``model`` (the field's
    metadata 'range'; (0, None) where it has none), for checking a range before making it."""
    fields = dataclasses.fields(PARAMS[check_model(model)])
    field = next((f for f in fields if f.name == name), None)
    return field.metadata.get("range", (0, None)) if field is not None else (0, None)


def make_params(model: str, values: dict[str, Any]):
    """Validated parameter object of ``model`` from a name -> value mapping.

    Raises
    ------
    ParameterError : unknown model, unknown or missing parameter, or a value out of range.
    """
    cls = PARAMS[check_model(model)]
    names = param_names(model)
    unknown = sorted(set(values) - set(names))
    if unknown:
        raise ParameterError(f"{unknown[0]} is not a parameter of model {model!r}: "
                             f"expected {', '.join(names)}")
    required = [f.name for f in dataclasses.fields(cls)
                if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    missing = [n for n in required if n not in values]
    if missing:
        raise ParameterError(f"{missing[0]} is missing: model {model!r} needs {', '.join(required)}")
    return cls(**values)
