"""Exploration (issue 25; not part of ``make bench``): the cochlea's Hill blocks projected onto
their lowest inviscid natural modes, against the cosine-mode blocks the package solves. (What
it found is now the package's natural basis of minimum-tau maps,
spectralshell/discretise/natural_modes.py: m = M / 4 natural modes of M cosine modes, refined in
M by the window rule, planned per point; this script keeps measuring m at a fixed M.)

The package discretises the membrane in M cosine modes: D(s) = diag(Z_k(s)) + kappa C, forcing
G = kappa C (models/cochlea.py). Here D(s) and G are projected (Galerkin) onto the m lowest
natural modes of the same M modes: K v = w^2 Mass v with K = kappa C, Mass = diag(2/k) (the
inviscid added mass, models.cochlea.natural_frequencies), V mass-orthonormal, so that
V^T G V = diag(w^2) and V^T D(s) V = diag(w^2) + V^T diag(Z_k(s)) V: blocks of size m instead
of M. For each point of the seeded Fig 5.18 sample of validation/bench_sweep.py (its point
solved first as the sweep solves it: M refined, both kinds), the kind of the smaller tau_min is
solved again at the point's final (M, N) -- by the package (``marginal_tau`` with
``n_temporal = N``, CPU time) and in the reduced basis for m = 8, 12, 16, 24, ... <= M -- and
the smallest m whose tau_min agrees with the package's to TOL is printed with w_m / the kind's
resonance (1/2 subharmonic, 1 harmonic) and the package's time; and where a rule that needs no
reference would stop: the first window of three m of the ladder (m / 2 <= m' < m) agreeing to
TOL_WINDOW whose coarsest m reaches REACH times the resonance, with its error and the reduced
solves' time up to it.

What this does not do: prove anything about the reduced truncations (no counts, no proof of the
other kind's empty answer), refine M or N in the reduced basis, or project efficiently; it
measures how small the blocks could be. Run: python validation/explore_modal_reduction.py
[--every K] (every K-th point of the sample).

Measured on all 100 points (2026-12-07, 2 processes): the smallest m of the ladder agreeing to 1e-6
is 8 (the first tried) on 51 points, 12-32 on 12, 48-128 on 27, 192-384 on 10 (the high-frequency
points, M = 192..512, whose subharmonic resonance at 1/2 lies inside their natural frequencies
0.01-4: m ~ M / 2); w_m / resonance 1.1-60 (median 2.3). On the crowded low-frequency points, whose
cosine-mode solves cost the most, m = 8 agrees to 2e-9..4e-8 at 15-20x less CPU for the same (M, N)
(human 63.6 Hz, sigma = 1.85e9, harmonic, M = 48, N = 51: 0.20 s against 3.23 s; gerbil 192.7 Hz;
human 54.7 Hz), 97x at human 523 Hz (M = 128, m = 8); at M = 192..256 and m = 96..128 this script's
projection (an einsum per s, O(M m^2)) makes the reduced solve no faster (0.5-1.2x). Summed over
the points' final truncations: 24.6 s reduced against 47.8 s. The window rule in m: without the
reach condition it stopped at m = 16 on the high-frequency points with no tau at m = 8, 12, 16 (off
by 0.47: bases too small to carry the resonant modes agree on nothing, as truncations in M do
without their reach test); with it (REACH = 2, TOL_WINDOW = 1e-4) it stops on 65 of the 100 points
(at m = 16 on 45, 24-64 on 13, 96-192 on 7), each within 8.8e-8 of the package's tau_min, and on
none of the 35 others (M >= 96, mostly 192-384: keep the cosine basis there); the crowded points'
ladders (m = 8, 12, 16) took 0.15-1.41 s against 1.3-2.9 s for one cosine solve of the same (M, N).
Across M, the reduced tau_min of the crowded harmonic point (m = 8, N = 51, tol 1e-4) moves as the
cosine solves do: 0.4943543 at M = 48, 0.4943463 at 96, 0.4943456 at 192, each in 0.1 s.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time

import numpy as np
import scipy.linalg as sla

from bench_sweep import sample_points
from spectralshell.models.cochlea import transfer
from spectralshell.params.registry import make_params
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.runner import run_sweep
from spectralshell.runner.layout import chunk_points, chunks
from spectralshell.runner.solve import spatial_system
from spectralshell.runner.executors import open_pool
from spectralshell.runner.engine import run_tasks
from spectralshell.solvers.marginal import marginal_tau
from spectralshell.solvers.spatial_refinement import RESONANCE

TOL = 1e-6            # agreement of the reduced tau_min with the package's
#: A rule that needs no reference: stop at the first window (m / 2 <= m' < m'' = m) of the ladder
#: whose tau_min at m is within TOL_WINDOW of those at the two before (as the refinement in M).
TOL_WINDOW = 1e-4
#: ... counting only windows whose coarsest m keeps a natural frequency of at least REACH times
#: the kind's resonance (as the refinement in M's reach test: without it, bases too small to
#: carry the resonant modes all find no tau and agree).
REACH = 2.0
LADDER = (8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512)


def natural_basis(full) -> tuple[np.ndarray, np.ndarray]:
    """(w^2 ascending, V mass-orthonormal) of ``full`` (the cochlea in M cosine modes):
    K v = w^2 Mass v, K = kappa C (the forcing), Mass = diag(2/k)."""
    k = np.arange(1, full.block_size + 1, dtype=float)
    return sla.eigh(full.forcing, np.diag(2.0 / k))


def reduced_system(full, nu: float, m: int, basis: tuple[np.ndarray, np.ndarray] | None = None):
    """The HillSystem of ``full`` (the cochlea in M cosine modes, viscosity ``nu``) projected
    onto its m lowest natural modes (``basis``: :func:`natural_basis` of ``full``, computed
    when not given), and w_m (the highest kept natural frequency, forcing units). With m = M
    the projection is a congruence: the same marginal tau."""
    M = full.block_size
    k = np.arange(1, M + 1, dtype=float)
    w2, V = natural_basis(full) if basis is None else basis
    Vm = np.ascontiguousarray(V[:, :m])
    idx = np.arange(m)

    def unforced(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=complex).ravel()
        Z = transfer(s[:, None], k[None, :], nu)                    # (len(s), M)
        out = np.einsum("ki,nk,kj->nij", Vm, Z, Vm, optimize=True)
        out[:, idx, idx] += w2[:m]
        return out

    system = dataclasses.replace(full, block_size=m, forcing=np.diag(w2[:m]),
                                 unforced=unforced, polynomial=None, n_highest=None)
    return system, math.sqrt(w2[m - 1])


def cell(label: str, scene: dict) -> tuple[str, str]:
    ds = run_sweep(scene, executor="serial", max_seconds=1e8).dataset
    spec = sweep_spec(scene)
    params = spec.params_at(next(iter(chunk_points(spec, chunks(spec)[0])))[1])
    tau = ds["tau_min"].values.ravel()
    if np.all(np.isnan(tau)):
        return label, "no tau <= 1/2: nothing to compare"
    q = int(np.nanargmin(tau))
    kind = str(ds["kind"].values[q])
    M, N = int(ds["n_spatial"].values.ravel()[q]), int(ds["n_temporal"].values.ravel()[q])
    options = {"n_temporal": N, "tau_max": 0.5}
    full = spatial_system(spec.model, params, M)
    nu = make_params(spec.model, {**params, "n_spatial": M}).nu
    t0 = time.process_time()
    reference = marginal_tau(full, kind, **options).tau_min
    t_full = time.process_time() - t0
    found, spent, matched, window, reach = {}, 0.0, None, None, {}
    basis = natural_basis(full)
    for m in (m for m in LADDER if m <= M):
        system, w_m = reduced_system(full, nu, m, basis)
        reach[m] = w_m >= REACH * RESONANCE[kind]
        t0 = time.process_time()
        tau = marginal_tau(system, kind, **options).tau_min
        spent += time.process_time() - t0
        found[m] = 0.5 if tau is None else tau  # capped at tau_max, as the refinement in M
        if matched is None and tau is not None and reference is not None \
                and abs(tau - reference) <= TOL:
            matched = (m, w_m, abs(tau - reference))
        ladder = list(found)
        if window is None and len(ladder) >= 3 and ladder[-3] * 2 >= m and reach[ladder[-3]] \
                and max(abs(found[m] - found[j]) for j in ladder[-3:-1]) <= TOL_WINDOW:
            window = (m, abs(found[m] - (0.5 if reference is None else reference)), spent)
        if matched is not None and window is not None:
            break
    if matched is None:
        return label, f"{kind} M = {M} N = {N}: no m <= M agrees to {TOL:g}"
    m, w_m, diff = matched
    rule = ("no window of three m passed" if window is None else
            f"window rule in m stops at m = {window[0]} (off by {window[1]:.1e}; the ladder to "
            f"it {window[2]:.2f} s)")
    return label, (f"{kind:11s} M = {M:3d} N = {N:2d} tau_min {reference:.6f}: m = {m:3d} "
                   f"(w_m / resonance {w_m / RESONANCE[kind]:7.2f}) |diff| {diff:.1e}; full "
                   f"solve {t_full:6.2f} s; {rule}")


def main() -> None:
    every = int(sys.argv[sys.argv.index("--every") + 1]) if "--every" in sys.argv else 1
    tasks = sample_points()[::every]
    print(f"modal reduction on {len(tasks)} points of the seeded Fig 5.18 sample: the smallest m "
          f"reproducing the package's tau_min to {TOL:g} at its (M, N), CPU s (one BLAS thread)")
    with open_pool("processes") as pool:
        run_tasks(pool.executor, cell, tasks, in_flight=pool.slots,
                  on_result=lambda task, result: print(f"  {result[0]:<46} {result[1]}",
                                                       flush=True))


if __name__ == "__main__":
    main()
