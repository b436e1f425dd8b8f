"""Parameters -> physics of their registered model (:mod:`spectralshell.params.registry`)."""

from __future__ import annotations

from ..params.registry import model_of
from .base import HillSystem, ModalSystem


def hill_system(params) -> HillSystem:
    """The Hill-system physics of a validated parameter object."""
    return model_of(params).hill_system(params)


def modal_system(params) -> ModalSystem:
    """The natural-mode dispersion relation of a validated parameter object."""
    spec = model_of(params)
    if spec.modal_system is None:
        raise TypeError(f"model {spec.name!r} has no natural-mode dispersion relation")
    return spec.modal_system(params)
