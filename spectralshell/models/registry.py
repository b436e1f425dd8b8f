"""Model name -> Hill-system builder (physics only)."""

from __future__ import annotations

from ..params.mathieu import MathieuParams
from . import mathieu
from .base import HillSystem


def hill_system(params) -> HillSystem:
    """The Hill-system physics of a validated parameter object."""
    if isinstance(params, MathieuParams):
        return mathieu.hill_system(kappa=params.kappa, nu=params.nu)
    raise TypeError(f"no Hill system for parameters of type {type(params).__name__}")
