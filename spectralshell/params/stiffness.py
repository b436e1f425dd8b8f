"""The negative-stiffness flag: K(t) = kappa (1 + 2 tau sin t) turns negative during the forcing
cycle exactly when |tau| > 1/2 (either sign of tau: tau -> -tau is the time shift t -> t + pi).
Such values are computed but flagged (physically meaningless, numerically fine)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

#: The largest |tau| at which the stiffness stays >= 0 throughout the cycle.
TAU_POSITIVE_STIFFNESS = 0.5
_NEGATIVE = "the stiffness kappa (1 + 2 tau sin t) becomes negative during the cycle"


def amplitude_warnings(tau: float) -> list[str]:
    """The flag of a given forcing amplitude ``tau`` (exponents, stability, simulate)."""
    if abs(tau) <= TAU_POSITIVE_STIFFNESS:
        return []
    return [f"|tau| = {abs(tau):g} > 1/2: {_NEGATIVE}"]


def threshold_warnings(tau_min: Mapping[str, Sequence[float | None]]) -> list[str]:
    """The flag of each kind whose instability threshold ``tau_min`` (per point of a result; None
    where a point has none) exceeds 1/2 somewhere. Marginal tau above a tau_min <= 1/2 bound the
    same unstable region further up and are not flagged."""
    out = []
    for kind, values in tau_min.items():
        over = [t for t in values if t is not None and t > TAU_POSITIVE_STIFFNESS]
        if not over:
            continue
        where = (f" = {over[0]:.6g}" if len(values) == 1
                 else f" (up to {max(over):.6g}) at {len(over)} of {len(values)} points")
        out.append(f"{kind} tau_min{where} > 1/2: {_NEGATIVE} before this instability sets in")
    return out
