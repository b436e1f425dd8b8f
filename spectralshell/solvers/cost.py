"""Cost of a marginal-tau solve predicted from its parameters, before it starts.

Truncations. :func:`~spectralshell.solvers.marginal.marginal_tau` starts at
N0 = ceil(n_resonant) + 8 and raises N by half (N + max(6, N // 2)) until tau_min converges. Once
N passes the highest natural frequency of the truncation's modes (``HillSystem.n_highest``, in
units of the forcing frequency; n_resonant where the model does not say) every mode's
resonances lie inside the truncation, so N is priced up to n_highest + 8 (at most N_MAX), and at
least the two truncations every solve makes. A fixed ``n_temporal`` N is priced as the two
truncations it solves (N and the smaller one of its error estimate).

Spatial modes. With ``n_spatial`` M given, M and M // 2 are solved; refined automatically, the least
any refinement does is the first window (SPATIAL_START, 3/2 SPATIAL_START, 2 SPATIAL_START), and the
most is every M of its ladder up to SPATIAL_LIMIT (:mod:`spectralshell.solvers.spatial_refinement`).

Price. A truncation of order n = (N + 1) b (b: the block size) is priced as a dense
eigenproblem, :data:`DENSE_SECONDS` n^3. Measured on the cochlea of Table 5.1 at omega = 10
rad/s (M = 16, one BLAS thread, a shared 2-core VM): order 1024 took 1.9 s (harmonic, real)
and 3.2 s (subharmonic, complex), order 1520 8.0 s (subharmonic): 1.8e-9 to 3.0e-9 s n^3.
The Arnoldi path of large truncations (``method = "auto"``) is often faster (5-10x at b = 128
with a finite tau_max) but gives up, at the dense cost and more, where many eigenvalues lie
below the wanted tau (the same M = 16 run), so the dense price is what a solve may cost, not a
lower bound.

Certificate. An empty answer (no tau <= tau_max) of a viscous model (D(s) not a matrix
polynomial) is proved by the argument principle's zero count at both truncations of the final
pair (issue 23; ``marginal_tau(..., certify_empty=...)``, what ``floquet``, ``response`` and the
sweeps ask); for M x M blocks one node of it is (N + 1) LAPACK LUs of order M. Each kind is
priced as if it might be empty: :data:`COUNT_NODES` nodes at :data:`COUNT_SECONDS` (N + 1) M^3
each, per truncation of the pair. Measured (validation/bench_certify_cochlea.py; gerbil cochlea
of Fig 5.18 at 5 kHz, sigma = 1.5e8, harmonic, N = 15, one BLAS thread, 2 cores under a load of
6-7, CPU time): a count that proves the strip empty far below the spectrum walks 17 nodes
(M = 128: 1.7 s; M = 256: 10.1 s, against 3.8 s and 26 s for the dense eig of W of the same
truncation), one that meets an eigenvalue near the strip 93-95 (M = 128: 9.6 s), and 92-106 on
the cell of Fig 5.18 that climbs to N = 141 (solvers/marginal.py notes); per node 3.0e-9 (M =
128) and 2.2e-9 (M = 256) s per (N + 1) M^3, more at small M (6e-9 at M = 32: overheads). The
price therefore adds at most ~2.5x the dense price of the final truncation at N = 15, and a few
per cent at N >~ 100.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from ..models.base import HillSystem
from .marginal import FIRST_MARGIN, N_MAX, TruncationSchedule, coarser, finer
from .spatial_refinement import SPATIAL_LIMIT, SPATIAL_START, spatial_ladder

#: Seconds per n^3 of a dense truncation of order n (module notes).
DENSE_SECONDS = 2.5e-9
#: Seconds per node of the zero count per (N + 1) M^3, and the nodes priced per count (module
#: notes, "Certificate").
COUNT_SECONDS = 3.0e-9
COUNT_NODES = 100


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


def certify_seconds(system: HillSystem, pair: tuple[int, int]) -> float:
    """Price of proving one kind empty at the truncation ``pair`` (module notes,
    "Certificate"): COUNT_NODES nodes of COUNT_SECONDS (N + 1) b^3 at each N; 0 for a model
    whose D(s) is a matrix polynomial (its spectra certify an empty answer) and for 2 x 2
    blocks (the compiled count, O(N) per node)."""
    if system.polynomial is not None or system.block_size <= 2:
        return 0.0
    return COUNT_NODES * COUNT_SECONDS * system.block_size ** 3 * sum(n + 1 for n in pair)


def solve_seconds(system: HillSystem, kinds: int, n_temporal: int | None = None) -> float:
    """Price of marginal_tau of ``kinds`` kinds on ``system``: the truncations of its schedule,
    and the certificate of an empty answer at the last two (:func:`certify_seconds`)."""
    schedule = temporal_schedule(system, n_temporal)
    return kinds * (sum(truncation_seconds(system.block_size, n) for n in schedule)
                    + certify_seconds(system, schedule[-2:]))


def spatial_cost(factory: Callable[[int], HillSystem], kinds: Iterable[str], *,
                 n_spatial: int | None = None, n_temporal: int | None = None,
                 upper: bool = True) -> CostEstimate:
    """Predicted cost of the marginal tau of ``kinds`` of a model with spatial modes
    (``factory``: M -> its HillSystem), at a fixed ``n_spatial`` (M and M // 2) or refined in M
    (least: the first window; most: every M of the ladder up to SPATIAL_LIMIT; ``upper``
    False: the least only, without building the larger M, as a sweep prices its points)."""
    count = len(tuple(kinds))
    if n_spatial is not None:
        least = most = tuple(m for m in (n_spatial // 2, n_spatial) if m >= 1)
    else:
        least = spatial_ladder(SPATIAL_START, 2 * SPATIAL_START)
        most = spatial_ladder(SPATIAL_START, SPATIAL_LIMIT) if upper else least
    systems = {m: factory(m) for m in most}
    price = {m: solve_seconds(s, count, n_temporal) for m, s in systems.items()}
    return CostEstimate(seconds=sum(price[m] for m in least), seconds_max=sum(price.values()),
                        n_temporal=temporal_schedule(systems[least[-1]], n_temporal)[-1],
                        n_spatial=least[-1], levels=len(most))
