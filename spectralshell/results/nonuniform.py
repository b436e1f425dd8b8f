"""Floquet result of the sphere with non-uniform stiffness: degrees coupled, refined in l_max."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .floquet import FloquetResult
from .records import MarginalTau
from .spatial import truncation_reason


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class NonUniformFloquetResult(FloquetResult):
    """Marginal amplitudes of the sphere with kappa(theta, phi), the minimum over its decoupled
    sectors, at a truncation in degree l_max, with the change from l_max - 2 in the error.

    The attributes of :class:`FloquetResult` (each kind's ``tau`` lists the marginal tau of the
    critical sector, the one attaining tau_min; its ``complete_to`` is what all the sectors
    prove together, :func:`spectralshell.runner.nonuniform.sector_minimum`: tau_max for a
    proved empty kind, at least tau_min for a tau_min no sector undercuts, 0 where the zero
    count could not prove a sector empty at a fixed n_temporal), and these:

    Attributes
    ----------
    l_max : the degree truncation of the reported values.
    l_max_previous : the truncation l_max - 2 they were compared with.
    l_change : per kind, |tau_min(l_max) - tau_min(l_max_previous)| (None when only one of
        the two has a tau_min); each kind's ``error_estimate`` is the larger of this and the
        temporal estimate.
    content : per kind, the modes of the critical mode with their share of its squared
        displacement norm (|X^Y|^2 + l(l+1) (|X^Psi|^2 + |X^Phi|^2), summed over the Fourier
        coefficients), largest first: dicts {"l", "k", "component", "share"} (shares >= 1e-4).
    multiplicity : per kind, how many equivalent critical modes there are (sectors equal up to
        a rotation or reflection: cos and sin of an order; the 2l + 1 orders of a uniform
        kappa); ``content`` is that of one of them.
    sectors : the number of decoupled sectors solved (equal copies counted once).
    """

    l_max: int
    l_max_previous: int
    l_change: dict[str, float | None]
    content: dict[str, list[dict[str, Any]]]
    multiplicity: dict[str, int]
    sectors: int

    def to_dict(self) -> dict[str, Any]:
        out = super().to_dict()
        out.update(l_max=self.l_max, l_max_previous=self.l_max_previous,
                   l_change=dict(self.l_change), content={k: list(v) for k, v in
                                                          self.content.items()},
                   multiplicity=dict(self.multiplicity), sectors=self.sectors)
        return out

    def summary(self) -> str:
        """The FloquetResult text, then the truncation in l and the dominant modes per kind."""
        lines = [super().summary(),
                 f"  degrees 2..{self.l_max} ({self.sectors} sectors; compared with "
                 f"l_max = {self.l_max_previous})"]
        for kind, modes in self.content.items():
            top = ", ".join(f"(l, k) = ({c['l']}, {c['k']}) {c['component']} {c['share']:.3f}"
                            for c in modes[:3])
            copies = self.multiplicity.get(kind, 1)
            also = f"  (one of {copies} equivalent)" if copies > 1 else ""
            lines.append(f"  {kind:<12} critical mode: {top}{also}")
        return "\n".join(lines)

    def error_reason(self, kind: str, m: MarginalTau) -> str:
        """The truncation in degree where its change is the larger part of the estimate."""
        reason = truncation_reason(
            m, self.l_change.get(kind), self.provenance,
            pair=f"l_max = {self.l_max_previous} and {self.l_max}",
            what="the truncation in degree", size="l_max", fixed="l_max is fixed")
        return super().error_reason(kind, m) if reason is None else reason
