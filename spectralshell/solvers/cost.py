"""Cost of a marginal-tau solve predicted from its parameters, before it starts.

Truncations. :func:`~spectralshell.solvers.marginal.marginal_tau` starts at
N0 = ceil(n_resonant) + 8 and raises N by half (N + max(6, N // 2)) until tau_min converges. Once
N passes the highest natural frequency of the truncation's modes (``HillSystem.n_highest``, in
units of the forcing frequency; n_resonant where the model does not say) every mode's
resonances lie inside the truncation, so N is priced up to n_highest + 8 (at most N_MAX), and at
least the two truncations every solve makes. A fixed ``n_temporal`` N is priced as the two
truncations it solves (N and the smaller one of its error estimate).

Spatial modes. With ``n_spatial`` M given, M and M // 2 are solved; refined automatically, the
least any refinement does is the first pair (SPATIAL_START, 2 SPATIAL_START), and the most is
every M up to SPATIAL_LIMIT (:mod:`spectralshell.solvers.spatial_refinement`).

Price. A truncation of order n = (N + 1) b (b: the block size) is priced as a dense
eigenproblem, :data:`DENSE_SECONDS` n^3. Measured on the cochlea of Table 5.1 at omega = 10
rad/s (M = 16, one BLAS thread, a shared 2-core VM): order 1024 took 1.9 s (harmonic, real)
and 3.2 s (subharmonic, complex), order 1520 8.0 s (subharmonic): 1.8e-9 to 3.0e-9 s n^3.
The Arnoldi path of large truncations (``method = "auto"``) is often faster (5-10x at b = 128
with a finite tau_max) but gives up, at the dense cost and more, where many eigenvalues lie
below the wanted tau (the same M = 16 run), so the dense price is what a solve may cost, not a
lower bound.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from ..models.base import HillSystem
from .marginal import FIRST_MARGIN, N_MAX, TruncationSchedule, coarser, finer
from .spatial_refinement import SPATIAL_LIMIT, SPATIAL_START

#: Seconds per n^3 of a dense truncation of order n (module notes).
DENSE_SECONDS = 2.5e-9


@dataclass(frozen=True)
class CostEstimate:
    """Predicted cost of a solve: ``seconds`` of the least work it must do, with the largest
    truncation ``n_temporal`` at the spatial modes ``n_spatial`` it needs for that, and
    ``seconds_max`` if the refinement in M goes to its limit (= ``seconds`` when M is fixed);
    ``levels``: the number of M it may solve at (a progress bar's length)."""

    seconds: float
    seconds_max: float
    n_temporal: int
    n_spatial: int
    levels: int

    def describe(self) -> str:
        """'N = 316, M = 32: about 1.7 h (up to 9.2 h)', the needs and the estimate in words."""
        upper = f" (up to {duration(self.seconds_max)})" if self.seconds_max > self.seconds else ""
        return (f"N = {self.n_temporal}, M = {self.n_spatial}: about "
                f"{duration(self.seconds)}{upper}")


def duration(seconds: float) -> str:
    """``seconds`` in the largest fitting unit, to 2 digits: '0.4 s', '12 min', '1.7 h'."""
    for unit, size in (("h", 3600.0), ("min", 60.0)):
        if seconds >= size:
            return f"{seconds / size:.2g} {unit}"
    return f"{seconds:.2g} s"


def temporal_schedule(system: HillSystem, n_temporal: int | None = None) -> tuple[int, ...]:
    """The truncations N that :func:`marginal_tau` is expected to solve (module notes)."""
    if n_temporal is not None:
        return (coarser(n_temporal), n_temporal)
    top = system.n_highest if system.n_highest is not None else system.n_resonant
    target = min(N_MAX, math.ceil(top) + FIRST_MARGIN)
    schedule = [TruncationSchedule.of(system).first]
    while len(schedule) < 2 or schedule[-1] < target:
        schedule.append(min(finer(schedule[-1]), N_MAX))
        if schedule[-1] == N_MAX:
            break
    return tuple(schedule)


def truncation_seconds(block_size: int, n_temporal: int) -> float:
    """Price of one truncation: DENSE_SECONDS ((N + 1) b)^3."""
    return DENSE_SECONDS * float((n_temporal + 1) * block_size) ** 3


def solve_seconds(system: HillSystem, kinds: int, n_temporal: int | None = None) -> float:
    """Price of marginal_tau of ``kinds`` kinds on ``system``."""
    return kinds * sum(truncation_seconds(system.block_size, n)
                       for n in temporal_schedule(system, n_temporal))


def spatial_cost(factory: Callable[[int], HillSystem], kinds: Iterable[str], *,
                 n_spatial: int | None = None, n_temporal: int | None = None) -> CostEstimate:
    """Predicted cost of the marginal tau of ``kinds`` of a model with spatial modes
    (``factory``: M -> its HillSystem), at a fixed ``n_spatial`` (M and M // 2) or refined in M
    (least: the first pair; most: every M up to SPATIAL_LIMIT)."""
    count = len(tuple(kinds))
    if n_spatial is not None:
        least = most = tuple(m for m in (n_spatial // 2, n_spatial) if m >= 1)
    else:
        least = (SPATIAL_START, 2 * SPATIAL_START)
        most = tuple(m for m in (SPATIAL_START << i for i in range(32)) if m <= SPATIAL_LIMIT)
    systems = {m: factory(m) for m in most}
    price = {m: solve_seconds(s, count, n_temporal) for m, s in systems.items()}
    return CostEstimate(seconds=sum(price[m] for m in least), seconds_max=sum(price.values()),
                        n_temporal=temporal_schedule(systems[least[-1]], n_temporal)[-1],
                        n_spatial=least[-1], levels=len(most))
