"""Model name -> Hill-system builder (physics only)."""

from __future__ import annotations

from ..params.fibre import FibreParams
from ..params.mathieu import MathieuParams
from ..params.sphere import SphereParams
from . import fibre, mathieu, sphere, sphere_modes
from .base import HillSystem, ModalSystem


def hill_system(params) -> HillSystem:
    """The Hill-system physics of a validated parameter object."""
    if isinstance(params, MathieuParams):
        return mathieu.hill_system(kappa=params.kappa, nu=params.nu)
    if isinstance(params, SphereParams):
        return sphere.hill_system(m=params.m, kappa=params.kappa, nu=params.nu,
                                  component=params.component)
    if isinstance(params, FibreParams):
        return fibre.hill_system(m=params.m, kappa=params.kappa, nu=params.nu,
                                 forcing=params.forcing)
    raise TypeError(f"no Hill system for parameters of type {type(params).__name__}")


def modal_system(params) -> ModalSystem:
    """The natural-mode dispersion relation of a validated parameter object."""
    if isinstance(params, SphereParams):
        return sphere_modes.modal_system(m=params.m, kappa=params.kappa, nu=params.nu,
                                         component=params.component)
    raise TypeError(f"no natural-mode relation for parameters of type {type(params).__name__}")
