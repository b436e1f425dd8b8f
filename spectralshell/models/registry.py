"""Model name -> Hill-system builder (physics only)."""

from __future__ import annotations

from ..errors import ParameterError
from ..params.cochlea import CochleaParams
from ..params.fibre import FibreParams
from ..params.mathieu import MathieuParams
from ..params.sphere import SphereParams
from . import cochlea, fibre, mathieu, sphere, sphere_modes
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
    if isinstance(params, CochleaParams):
        if params.n_spatial is None and params.spatial_mode is None:
            raise ParameterError("n_spatial = None is invalid here: this computation needs a fixed "
                                 "number of cosine modes (only floquet converges in n_spatial)")
        return cochlea.hill_system(kappa=params.kappa, nu=params.nu, alpha=params.alpha,
                                   n_spatial=params.n_spatial, spatial_mode=params.spatial_mode)
    raise TypeError(f"no Hill system for parameters of type {type(params).__name__}")


def modal_system(params) -> ModalSystem:
    """The natural-mode dispersion relation of a validated parameter object."""
    if isinstance(params, SphereParams):
        return sphere_modes.modal_system(m=params.m, kappa=params.kappa, nu=params.nu,
                                         component=params.component)
    if isinstance(params, FibreParams):
        return fibre.modal_system(m=params.m, kappa=params.kappa, nu=params.nu)
    raise TypeError(f"no natural-mode relation for parameters of type {type(params).__name__}")
