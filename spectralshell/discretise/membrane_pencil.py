"""Accessors of the operators of a membrane in fluid: s M v = (L_fluid + K L_stiffness) v.

An operators dataclass holds the real matrices ``M``, ``L_fluid`` and ``L_stiffness`` (the
membrane term at unit stiffness) and ``blocks``, a mapping name -> slice of the state v with a
``membrane`` entry; :class:`MembranePencil` adds the size of v, the natural-mode pencil at a
constant stiffness and the membrane part of a state. Used by
:mod:`spectralshell.discretise.fibre_radial` and :mod:`spectralshell.discretise.cochlea_vertical`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Protocol

import numpy as np

from .._validate import require_positive


class _Operators(Protocol):
    """What the mixin reads (attributes or read-only properties of the operators class)."""

    @property
    def M(self) -> np.ndarray: ...

    @property
    def L_fluid(self) -> np.ndarray: ...

    @property
    def L_stiffness(self) -> np.ndarray: ...

    @property
    def blocks(self) -> Mapping[str, slice]: ...


class MembranePencil:
    """Mixin of the operators s M v = (L_fluid + K L_stiffness) v (module docstring)."""

    @property
    def size(self: _Operators) -> int:
        """Length of the state vector v."""
        return self.M.shape[0]

    def pencil(self: _Operators, kappa: float) -> tuple[np.ndarray, np.ndarray]:
        """(L, M) of the natural-mode problem s M v = L v at the stiffness K = kappa (times the
        model's fixed profile, if any)."""
        kappa = require_positive("kappa", kappa)
        return self.L_fluid + kappa * self.L_stiffness, self.M

    def displacement(self: _Operators, v: np.ndarray) -> np.ndarray:
        """The membrane unknowns (``blocks['membrane']``) of a state vector (or of its columns)."""
        return np.asarray(v)[self.blocks["membrane"]]
