"""Parameters of the damped Mathieu equation u'' + nu u' + kappa (1 + 2 tau sin t) u = 0 (2.9)."""

from __future__ import annotations

from dataclasses import dataclass, field

from .._validate import require_nonnegative


@dataclass(frozen=True, kw_only=True)
class MathieuParams:
    """Dimensionless parameters of the damped Mathieu equation (thesis (2.9)).

    kappa : stiffness, kappa = g / (l omega^2) for the pendulum (thesis 2.2); >= 0.
    nu : damping per unit time (time scaled by the forcing frequency); >= 0.
    """

    kappa: float = field(metadata={"help": "stiffness kappa (dimensionless, >= 0)"})
    nu: float = field(metadata={"help": "damping nu (dimensionless, >= 0; 0 = undamped)"})

    def __post_init__(self) -> None:
        object.__setattr__(self, "kappa", require_nonnegative("kappa", self.kappa))
        object.__setattr__(self, "nu", require_nonnegative("nu", self.nu))
