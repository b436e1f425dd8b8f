"""Stage 2, physics: per-Fourier-index blocks of each model, independent of any truncation.

Each model module registers itself as a plug-in (:mod:`spectralshell.params.registry`); importing
this package registers the built-in models. A model of one's own is added the same way:
build a :class:`Model` and :func:`register` it (README, "Adding a model").
"""

from ..params.registry import Model, PhysicalInput, models, register, unregister
from . import mathieu, sphere, fibre, cochlea, cylinder  # noqa: F401, I001  (registers the built-in models, in this order)
from .base import HillSystem, ModalSystem, ModeFamily, ResponseModel

__all__ = ["Model", "PhysicalInput", "register", "unregister", "models", "HillSystem",
           "ModalSystem", "ModeFamily", "ResponseModel"]
