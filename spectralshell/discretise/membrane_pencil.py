"""Accessors of the operators of a membrane in fluid: s M v = (L_fluid + K L_stiffness) v.

An operators dataclass holds the real matrices ``M``, ``L_fluid`` and ``L_stiffness`` (the
membrane term at unit stiffness) and ``blocks``, a mapping name -> slice of the state v with a
``membrane`` entry; :class:`MembranePencil` adds the size of v, the natural-mode pencil at a
constant stiffness and the membrane part of a state. Used by
:mod:`spectralshell.discretise.cochlea_vertical`.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .._validate import require_positive


class MembranePencil:
    """Mixin of the operators s M v = (L_fluid + K L_stiffness) v (module docstring)."""

    M: np.ndarray
    L_fluid: np.ndarray
    L_stiffness: np.ndarray
    blocks: Mapping[str, slice]

    @property
    def size(self) -> int:
        """Length of the state vector v."""
        return self.M.shape[0]

    def pencil(self, kappa: float) -> tuple[np.ndarray, np.ndarray]:
        """(L, M) of the natural-mode problem s M v = L v at the stiffness K = kappa (times the
        model's fixed profile, if any)."""
        kappa = require_positive("kappa", kappa)
        return self.L_fluid + kappa * self.L_stiffness, self.M

    def displacement(self, v: np.ndarray) -> np.ndarray:
        """The membrane unknowns (``blocks['membrane']``) of a state vector (or of its columns)."""
        return np.asarray(v)[self.blocks["membrane"]]
